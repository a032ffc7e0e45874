//! Selects the memory map of the board being built (see memory.x) and links defmt's script
//! into the firmware binaries that log with defmt; `-Tlink.x` comes from `.cargo/config.toml`.
use std::path::PathBuf;

fn main() {
    let target = std::env::var("TARGET").unwrap_or_default();
    let feature = |name: &str| std::env::var_os(format!("CARGO_FEATURE_{name}")).is_some();
    let map = if feature("BOARD_STM32F405") {
        "src/board/stm32f405.x"
    } else if feature("FIRMWARE_RP2040") {
        "src/board/rp2040.x"
    } else if feature("BOARD_MICROBIT") {
        "src/board/microbit.x"
    } else {
        "src/board/qemu_mps2.x"
    };
    if let Some(out) = std::env::var_os("OUT_DIR").map(PathBuf::from) {
        if std::fs::copy(map, out.join("board-memory.x")).is_ok() {
            println!("cargo:rustc-link-search={}", out.display());
        }
    }
    if target.starts_with("thumb") && feature("DEFMT") {
        println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
    }
    for file in [
        "memory.x",
        "build.rs",
        "src/board/qemu_mps2.x",
        "src/board/stm32f405.x",
        "src/board/microbit.x",
        "src/board/rp2040.x",
    ] {
        println!("cargo:rerun-if-changed={file}");
    }
}
