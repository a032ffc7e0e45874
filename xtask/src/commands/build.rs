//! `cargo xtask build`: each image built, its memory map checked, its flash and RAM printed.

use crate::image::signing::SigningKey;
use crate::image::{build_checked, Image};

/// The boards `cargo xtask build` builds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum BoardArg {
    /// QEMU mps2-an386 (Cortex-M4F): the serial and the MAVLink images.
    Qemu,
    /// STM32F405 flight controller, the serial and the MAVLink images (QEMU netduinoplus2).
    Stm32f405,
    /// BBC micro:bit (nRF51822, Cortex-M0, fixed point).
    Microbit,
    /// Raspberry Pi Pico (RP2040, Cortex-M0+, fixed point; rp2040js).
    Rp2040,
    /// `--board qemu --tables`' former spelling, kept for one release.
    #[value(hide = true)]
    QemuTables,
    /// `--board stm32f405 --tables`' former spelling, kept for one release.
    #[value(hide = true)]
    Stm32f405Tables,
    /// Every board.
    All,
}

/// `cargo xtask build`'s options.
#[derive(Debug, Clone, clap::Args)]
pub struct BuildArgs {
    /// The board.
    #[arg(long, value_enum, default_value = "all")]
    board: BoardArg,
    /// With `--board qemu`: the image with the value tables of two pairs of ratios in flash
    /// (solved first, about a minute each, then cached); with `--board stm32f405`: the one
    /// with the paper's (built and sized only).
    #[arg(long)]
    tables: bool,
    /// Build the MAVLink images with this signing key (a file of 32 bytes or 64 hexadecimal
    /// digits).
    #[arg(long)]
    signing_key: Option<std::path::PathBuf>,
}

/// `cargo xtask build [--board qemu|stm32f405|microbit|rp2040|all] [--tables]`: builds each
/// image, checks its memory map and prints its size.
pub fn command(args: &BuildArgs) -> i32 {
    let Ok(key) = SigningKey::given(args.signing_key.as_deref(), "xtask build") else {
        return 2;
    };
    let boards: Vec<Image> = match (args.board, args.tables) {
        (BoardArg::Qemu, true) => vec![Image::QemuTables],
        (BoardArg::Stm32f405, true) => vec![Image::Stm32f405Tables],
        (BoardArg::Microbit | BoardArg::Rp2040, true) => {
            eprintln!("xtask build: --tables: only the QEMU and STM32F405 images carry tables");
            return 2;
        }
        (board, _) => match board {
            BoardArg::Qemu => vec![Image::Qemu, Image::QemuMavlink],
            BoardArg::Stm32f405 => vec![Image::Stm32f405, Image::Stm32f405Mavlink],
            BoardArg::Microbit => vec![Image::Microbit],
            BoardArg::Rp2040 => vec![Image::Rp2040],
            BoardArg::QemuTables => vec![Image::QemuTables],
            BoardArg::Stm32f405Tables => vec![Image::Stm32f405Tables],
            BoardArg::All => Image::ALL.to_vec(),
        },
    };
    let mut rows = Vec::new();
    for board in boards {
        match build_checked(board, key.as_ref()) {
            Ok((elf, s)) => rows.push(format!(
                "| {} | {} | {} | {:#010x} | {} B ({} + {} + {}) | {} B ({} + {}) |",
                board.name(),
                board.target(),
                elf.file_name()
                    .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
                s.entry,
                s.flash(),
                s.text,
                s.rodata,
                s.data,
                s.ram(),
                s.data,
                s.bss
            )),
            Err(e) => {
                eprintln!("xtask build: {e}");
                return 1;
            }
        }
    }
    println!("| board | target | image | entry | flash (text + rodata + data) | static RAM (data + bss) |");
    println!("|---|---|---|---|---|---|");
    for row in rows {
        println!("{row}");
    }
    0
}
