//! Selects the memory map of the board being built (see memory.x) and links defmt's script
//! into the firmware binaries that log with defmt; `-Tlink.x` comes from `.cargo/config.toml`.
use std::path::PathBuf;

fn main() {
    let target = std::env::var("TARGET").unwrap_or_default();
    let stm32 = std::env::var_os("CARGO_FEATURE_BOARD_STM32F405").is_some();
    let map = if stm32 {
        "src/board/stm32f405.x"
    } else {
        "src/board/qemu_mps2.x"
    };
    if let Some(out) = std::env::var_os("OUT_DIR").map(PathBuf::from) {
        if std::fs::copy(map, out.join("board-memory.x")).is_ok() {
            println!("cargo:rustc-link-search={}", out.display());
        }
    }
    if target.starts_with("thumb") && std::env::var_os("CARGO_FEATURE_DEFMT").is_some() {
        println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
    }
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=src/board/qemu_mps2.x");
    println!("cargo:rerun-if-changed=src/board/stm32f405.x");
    println!("cargo:rerun-if-changed=build.rs");
}
