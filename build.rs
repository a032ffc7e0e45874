//! Selects the memory map of the board being built (see memory.x) when a board feature is on,
//! and only then (a crate that depends on twocars brings its own), links defmt's script into
//! the firmware binaries that log with defmt (`-Tlink.x` comes from `.cargo/config.toml`), and
//! with `tables-in-flash` names the value-table sets the image includes.
use std::path::PathBuf;

/// The core's key-file reading, the one the crate and its tools use.
#[path = "src/mavlink/key_file.rs"]
#[allow(dead_code)]
mod key_file;
use key_file::parse_key;

fn main() {
    let target = std::env::var("TARGET").unwrap_or_default();
    let feature = |name: &str| std::env::var_os(format!("CARGO_FEATURE_{name}")).is_some();
    let map = if feature("BOARD_STM32F405") {
        Some("src/board/stm32f405.x")
    } else if feature("BOARD_RP2040") {
        Some("src/board/rp2040.x")
    } else if feature("BOARD_MICROBIT") {
        Some("src/board/microbit.x")
    } else if feature("BOARD_QEMU") {
        Some("src/board/qemu_mps2.x")
    } else {
        None
    };
    let out = std::env::var_os("OUT_DIR").map(PathBuf::from);
    if let (Some(map), Some(out)) = (map, out) {
        if std::fs::copy(map, out.join("board-memory.x")).is_ok() {
            println!("cargo:rustc-link-search={}", out.display());
        }
    }
    if feature("TABLES_IN_FLASH") {
        value_table_sets();
    }
    if feature("MAVLINK") {
        mavlink_key();
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

/// Writes `value_table_sets.rs` into the build directory: `SETS`, the bytes of each file that
/// `TWOCARS_VALUE_TABLES` names (separated as PATH is), included into flash by
/// `twocars::board::tables`. Fails the build, saying how to make them, where none is given.
fn value_table_sets() {
    println!("cargo:rerun-if-env-changed=TWOCARS_VALUE_TABLES");
    let paths: Vec<PathBuf> = std::env::var_os("TWOCARS_VALUE_TABLES")
        .map(|v| std::env::split_paths(&v).collect())
        .unwrap_or_default();
    let missing = paths.iter().find(|p| !p.is_file());
    if paths.is_empty() || missing.is_some() {
        panic!(
            "feature tables-in-flash: TWOCARS_VALUE_TABLES must name the value-table sets to \
             include (missing: {missing:?}); `cargo xtask hj --set FILE` writes one, and \
             `cargo xtask build --board qemu-tables` builds the image with the project's sets"
        );
    }
    let mut source = format!(
        "/// How many value-table sets the image carries.\npub const SET_COUNT: usize = {0};\n\
         /// The value-table sets in flash.\npub static SETS: [&[u8]; {0}] = [\n",
        paths.len()
    );
    for path in &paths {
        let absolute = std::fs::canonicalize(path).unwrap_or_else(|_| path.clone());
        println!("cargo:rerun-if-changed={}", absolute.display());
        source.push_str(&format!(
            "    include_bytes!({:?}),\n",
            absolute.display().to_string()
        ));
    }
    source.push_str("];\n");
    let out = PathBuf::from(std::env::var_os("OUT_DIR").unwrap_or_default());
    if let Err(e) = std::fs::write(out.join("value_table_sets.rs"), source) {
        panic!("writing value_table_sets.rs: {e}");
    }
}

/// Writes `mavlink_key.rs` into the build directory: `PROVISIONED`, the MAVLink signing key in
/// the file `TWOCARS_MAVLINK_KEY` names (32 bytes, or 64 hexadecimal digits) and the signing
/// clock's start `TWOCARS_MAVLINK_KEY_TIME` (10 us since 2015-01-01; 0 where not given), or
/// `None` without a key. Fails the build, saying why, on a key file of any other form.
fn mavlink_key() {
    println!("cargo:rerun-if-env-changed=TWOCARS_MAVLINK_KEY");
    println!("cargo:rerun-if-env-changed=TWOCARS_MAVLINK_KEY_TIME");
    let Some(out) = std::env::var_os("OUT_DIR").map(PathBuf::from) else {
        return;
    };
    let value = match std::env::var_os("TWOCARS_MAVLINK_KEY") {
        None => "None".to_string(),
        Some(path) => {
            println!("cargo:rerun-if-changed={}", PathBuf::from(&path).display());
            let bytes = std::fs::read(&path).unwrap_or_else(|e| {
                panic!(
                    "TWOCARS_MAVLINK_KEY: {}: {e}",
                    PathBuf::from(&path).display()
                )
            });
            let key = parse_key(&bytes).unwrap_or_else(|| {
                panic!(
                    "TWOCARS_MAVLINK_KEY: the key file must hold 32 bytes or 64 hexadecimal digits"
                )
            });
            let time: u64 = std::env::var("TWOCARS_MAVLINK_KEY_TIME")
                .ok()
                .and_then(|t| t.trim().parse().ok())
                .unwrap_or(0);
            format!("Some(({key:?}, {time}))")
        }
    };
    let code = format!(
        "/// The build's MAVLink signing key and clock start.\n\
         pub const PROVISIONED: Option<([u8; 32], u64)> = {value};\n"
    );
    if let Err(e) = std::fs::write(out.join("mavlink_key.rs"), code) {
        panic!("writing mavlink_key.rs: {e}");
    }
}
