//! Firmware builds: the boards, their images built with the core's own features, the value
//! tables an image carries ([`tables`]), the link-time panic check and the memory map's check.

pub mod signing;
pub mod size;
pub mod tables;

use std::path::PathBuf;
use std::process::{Command, Stdio};

use crate::image::signing::SigningKey;
use crate::util::workspace::root;

/// The firmware images xtask builds: one binary each, for one board (a chip and its
/// peripherals), one link (our serial protocol or MAVLink) and, for two, the value tables.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Image {
    /// QEMU mps2-an386 (Cortex-M4F).
    Qemu,
    /// QEMU mps2-an386 speaking MAVLink 2 (the guidance endpoint, docs/mavlink.md).
    QemuMavlink,
    /// STM32F405 flight controller (Cortex-M4F), in QEMU's netduinoplus2.
    Stm32f405,
    /// STM32F405 speaking MAVLink 2, in QEMU's netduinoplus2.
    Stm32f405Mavlink,
    /// BBC micro:bit (nRF51822, Cortex-M0, the fixed-point law), in QEMU's `microbit` machine.
    Microbit,
    /// Raspberry Pi Pico (RP2040, Cortex-M0+, the fixed-point law), in rp2040js.
    Rp2040,
    /// QEMU mps2-an386 carrying the value tables of two pairs of ratios.
    QemuTables,
    /// STM32F405 carrying the value tables of the paper's ratios: build and size only.
    Stm32f405Tables,
}

/// The emulator an image runs in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Machine {
    /// `qemu-system-arm` with these machine options.
    Qemu(&'static [&'static str]),
    /// rp2040js under Node.js (xtask/rp2040js_harness.mjs).
    Rp2040js,
}

impl Image {
    /// Every board.
    pub const ALL: [Image; 8] = [
        Image::Qemu,
        Image::QemuMavlink,
        Image::Stm32f405,
        Image::Stm32f405Mavlink,
        Image::Microbit,
        Image::Rp2040,
        Image::QemuTables,
        Image::Stm32f405Tables,
    ];

    /// The Rust target of the board's core.
    pub fn target(self) -> &'static str {
        match self {
            Image::Qemu
            | Image::QemuMavlink
            | Image::Stm32f405
            | Image::Stm32f405Mavlink
            | Image::QemuTables
            | Image::Stm32f405Tables => "thumbv7em-none-eabihf",
            Image::Microbit | Image::Rp2040 => "thumbv6m-none-eabi",
        }
    }
    pub(crate) fn bin(self) -> &'static str {
        match self {
            Image::Qemu | Image::QemuTables => "twocars-qemu",
            Image::QemuMavlink => "twocars-qemu-mavlink",
            Image::Stm32f405 | Image::Stm32f405Tables => "twocars-stm32f405",
            Image::Stm32f405Mavlink => "twocars-stm32f405-mavlink",
            Image::Microbit => "twocars-microbit",
            Image::Rp2040 => "twocars-rp2040",
        }
    }
    /// Features of the image `cargo xtask build` and `run` use.
    pub fn feature(self) -> &'static str {
        match self {
            // The QEMU image logs with defmt over semihosting.
            Image::Qemu => "qemu-log",
            Image::QemuMavlink => "board-qemu,mavlink",
            Image::Stm32f405 => "board-stm32f405",
            Image::Stm32f405Mavlink => "board-stm32f405,mavlink",
            Image::Microbit => "board-microbit",
            Image::Rp2040 => "board-rp2040",
            Image::QemuTables => "qemu-log,tables-in-flash",
            Image::Stm32f405Tables => "board-stm32f405,tables-in-flash",
        }
    }
    /// The value-table sets the image carries, one per pair of ratios (`crate::image::tables::solve::flash_sets`):
    /// both of [`crate::image::tables::sets::FLASH_SETS`] on QEMU's 4 MiB, the paper's on the STM32F405's 1 MiB.
    pub fn table_sets(self) -> &'static [crate::image::tables::sets::FlashSet] {
        match self {
            Image::QemuTables => &crate::image::tables::sets::FLASH_SETS,
            Image::Stm32f405Tables => &crate::image::tables::sets::FLASH_SETS[..1],
            _ => &[],
        }
    }
    /// The emulator that runs the board's images.
    pub(crate) fn machine(self) -> Option<Machine> {
        match self {
            Image::Qemu | Image::QemuMavlink | Image::QemuTables => {
                Some(Machine::Qemu(&["-M", "mps2-an386", "-cpu", "cortex-m4"]))
            }
            Image::Microbit => Some(Machine::Qemu(&["-M", "microbit"])),
            // An STM32F405 SoC: its USART1 is the first serial port.
            Image::Stm32f405 | Image::Stm32f405Mavlink | Image::Stm32f405Tables => {
                Some(Machine::Qemu(&["-M", "netduinoplus2"]))
            }
            Image::Rp2040 => Some(Machine::Rp2040js),
        }
    }
    /// Whether the image's UART drops what arrives during its start-up (the STM32's USART
    /// before it is enabled), so that a client waits until it answers.
    pub(crate) fn drops_bytes_at_start(self) -> bool {
        matches!(
            self,
            Image::Stm32f405 | Image::Stm32f405Mavlink | Image::Stm32f405Tables
        )
    }
    /// The board status flags (Counters' last field) its image reports in its emulator: QEMU
    /// models no crystal for the STM32F405, which then runs on its fallback clock.
    pub(crate) fn status_in_emulator(self) -> u32 {
        match self {
            Image::Stm32f405 | Image::Stm32f405Mavlink | Image::Stm32f405Tables => {
                twocars::protocol::message::BOARD_FALLBACK_CLOCK
            }
            _ => 0,
        }
    }
    /// Whether the image logs with defmt over semihosting (`qemu-log`), which xtask decodes.
    pub(crate) fn logs_with_defmt(self) -> bool {
        matches!(self, Image::Qemu | Image::QemuTables)
    }
    /// Whether the image exits (over semihosting) once it has acknowledged a Shutdown; a
    /// flight image keeps serving instead.
    pub(crate) fn exits_on_shutdown(self) -> bool {
        matches!(self, Image::Qemu | Image::QemuTables | Image::Microbit)
    }
    /// Features of the flight image: no logger, so panic freedom can be proven at link time.
    pub fn flight_features(self) -> &'static str {
        match self {
            Image::Qemu => "board-qemu,panic-never",
            Image::QemuMavlink => "board-qemu,mavlink,panic-never",
            Image::Stm32f405 => "board-stm32f405,panic-never",
            Image::Stm32f405Mavlink => "board-stm32f405,mavlink,panic-never",
            Image::Microbit => "board-microbit,panic-never",
            Image::Rp2040 => "board-rp2040,panic-never",
            Image::QemuTables => "board-qemu,tables-in-flash,panic-never",
            Image::Stm32f405Tables => "board-stm32f405,tables-in-flash,panic-never",
        }
    }
    /// Flash of the board's memory map (its `src/board/*.x`), bytes.
    pub fn flash_bytes(self) -> u64 {
        match self {
            Image::Qemu | Image::QemuMavlink | Image::QemuTables => 4 << 20,
            Image::Stm32f405 | Image::Stm32f405Mavlink | Image::Stm32f405Tables => 1 << 20,
            Image::Microbit => 256 << 10,
            // Less the 256-byte second-stage bootloader.
            Image::Rp2040 => (2 << 20) - 0x100,
        }
    }
    /// Flash origin of the board's memory map: where the vector table must be.
    pub fn flash_origin(self) -> u64 {
        match self {
            Image::Qemu | Image::QemuMavlink | Image::Microbit | Image::QemuTables => 0x0000_0000,
            Image::Stm32f405 | Image::Stm32f405Mavlink | Image::Stm32f405Tables => 0x0800_0000,
            // After the 256-byte second-stage bootloader at the start of flash.
            Image::Rp2040 => 0x1000_0100,
        }
    }
    pub(crate) fn name(self) -> &'static str {
        match self {
            Image::Qemu => "qemu (mps2-an386)",
            Image::QemuMavlink => "qemu (mps2-an386), MAVLink",
            Image::Stm32f405 => "stm32f405",
            Image::Stm32f405Mavlink => "stm32f405, MAVLink",
            Image::Microbit => "microbit (nRF51822)",
            Image::Rp2040 => "rp2040 (Raspberry Pi Pico)",
            Image::QemuTables => "qemu (mps2-an386), value tables",
            Image::Stm32f405Tables => "stm32f405, value tables",
        }
    }
}

/// Builds the release firmware for `board`, a MAVLink image signing with `key` where given;
/// returns the ELF's path.
pub fn build(board: Image, key: Option<&SigningKey>) -> Result<PathBuf, String> {
    build_with(board, board.feature(), key)
}

/// Builds the flight image of `board` with the link-time panic check: it links only if no
/// panic path survives optimisation.
pub fn prove_panic_free(board: Image) -> Result<PathBuf, String> {
    build_with(board, board.flight_features(), None)
        .map_err(|e| format!("{e}: a panic path is reachable (see the undefined symbol above)"))
}

fn build_with(board: Image, features: &str, key: Option<&SigningKey>) -> Result<PathBuf, String> {
    let key_env = key.map(SigningKey::build_env);
    let key_env: Vec<(&str, &std::ffi::OsStr)> = key_env
        .iter()
        .flatten()
        .map(|(name, value)| (*name, value.as_os_str()))
        .collect();
    let sets = board.table_sets();
    if sets.is_empty() {
        return build_image(
            CORE,
            board.target(),
            features,
            board.bin(),
            Stdio::inherit(),
            &key_env,
        )
        .map_err(|e| format!("firmware build for {board:?} failed ({e})"));
    }
    // The same binary with its sets in flash, kept beside the one without as `<bin>-tables`.
    let files = crate::image::tables::solve::flash_sets(sets)?;
    let paths = std::env::join_paths(&files).map_err(|e| e.to_string())?;
    let elf = build_image(
        CORE,
        board.target(),
        features,
        board.bin(),
        Stdio::inherit(),
        &[("TWOCARS_VALUE_TABLES", paths.as_os_str())],
    )
    .map_err(|e| format!("firmware build for {board:?} failed ({e})"))?;
    let kept = elf.with_file_name(format!("{}-tables", board.bin()));
    std::fs::copy(&elf, &kept).map_err(|e| format!("{}: {e}", kept.display()))?;
    Ok(kept)
}

/// The package of the flight images.
const CORE: &str = "twocars";

/// Builds `package`'s binary `bin` for `target` with `features` (release), cargo's own output
/// to `stdout`; returns the ELF's path. Only that package's features: a workspace build would
/// unify in those the host crates enable (`value-tables`), and their code with them
/// (docs/optimisation.md).
pub fn build_image(
    package: &str,
    target: &str,
    features: &str,
    bin: &str,
    stdout: Stdio,
    env: &[(&str, &std::ffi::OsStr)],
) -> Result<PathBuf, String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let status = Command::new(cargo)
        .current_dir(root())
        .args(["build", "--package", package, "--release"])
        .args(["--target", target, "--features", features, "--bin", bin])
        .env("DEFMT_LOG", "info")
        // The image's key is what `env` says, not what the shell has.
        .env_remove("TWOCARS_MAVLINK_KEY")
        .env_remove("TWOCARS_MAVLINK_KEY_TIME")
        .envs(env.iter().copied())
        .stdout(stdout)
        .status()
        .map_err(|e| format!("cargo build: {e}"))?;
    if !status.success() {
        return Err(status.to_string());
    }
    Ok(crate::util::workspace::target_dir()
        .join(target)
        .join("release")
        .join(bin))
}

/// Builds `board`'s image and checks its vector table sits at the board's flash origin (a
/// wrong memory map links silently otherwise).
pub fn build_checked(
    board: Image,
    key: Option<&SigningKey>,
) -> Result<(PathBuf, crate::image::size::ImageSize), String> {
    let elf = build(board, key)?;
    let size = crate::image::size::of(&elf)?;
    // The RP2040's boot ROM runs the 256 bytes at the start of flash: boot2 must be there.
    if board == Image::Rp2040 && size.boot2 != Some(0x1000_0000) {
        return Err(format!(
            "{}: no second-stage bootloader at 0x10000000 ({:?})",
            board.name(),
            size.boot2
        ));
    }
    if size.vector_table != board.flash_origin() {
        return Err(format!(
            "{}: vector table at {:#010x}, expected the board's flash origin {:#010x}",
            board.name(),
            size.vector_table,
            board.flash_origin()
        ));
    }
    Ok((elf, size))
}
