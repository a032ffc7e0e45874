//! `cargo xtask build`: each image built, its memory map checked, its flash and RAM printed.

use crate::image::signing::SigningKey;
use crate::image::{build_checked, Image};

/// The boards `cargo xtask build` builds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum BoardArg {
    /// QEMU mps2-an386 (Cortex-M4F): the COBS and the MAVLink images.
    Qemu,
    /// STM32F405 flight controller, both images (QEMU netduinoplus2).
    Stm32f405,
    /// BBC micro:bit (nRF51822, Cortex-M0, fixed point).
    Microbit,
    /// Raspberry Pi Pico (RP2040, Cortex-M0+, fixed point; rp2040js).
    Rp2040,
    /// QEMU mps2-an386 with the value tables of two pairs of ratios in flash (solved first,
    /// about a minute each, then cached).
    QemuTables,
    /// STM32F405 with the value tables of the paper's ratios in flash (built and sized only).
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
    /// Build the MAVLink images with this signing key (a file of 32 bytes or 64 hexadecimal
    /// digits).
    #[arg(long)]
    signing_key: Option<std::path::PathBuf>,
}

/// `cargo xtask build [--board qemu|stm32f405|microbit|rp2040|qemu-tables|stm32f405-tables|all]`: builds each image, checks its memory map
/// and prints its size.
pub fn command(args: &BuildArgs) -> i32 {
    let Ok(key) = SigningKey::given(args.signing_key.as_deref(), "xtask build") else {
        return 2;
    };
    let boards: Vec<Image> = match args.board {
        BoardArg::Qemu => vec![Image::Qemu, Image::QemuMavlink],
        BoardArg::Stm32f405 => vec![Image::Stm32f405, Image::Stm32f405Mavlink],
        BoardArg::Microbit => vec![Image::Microbit],
        BoardArg::Rp2040 => vec![Image::Rp2040],
        BoardArg::QemuTables => vec![Image::QemuTables],
        BoardArg::Stm32f405Tables => vec![Image::Stm32f405Tables],
        BoardArg::All => Image::ALL.to_vec(),
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
