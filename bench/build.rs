//! Picks the memory map of the machine the images run on from the target: the micro:bit's
//! (nRF51822) for the Cortex-M0, QEMU mps2-an386's otherwise. The workspace's `memory.x`
//! includes it as `board-memory.x`.
use std::path::PathBuf;

fn main() {
    capture();
    let target = std::env::var("TARGET").unwrap_or_default();
    let map = if target.starts_with("thumbv6m") {
        "../src/board/microbit.x"
    } else {
        "../src/board/qemu_mps2.x"
    };
    println!("cargo:rerun-if-changed={map}");
    println!("cargo:rerun-if-changed=build.rs");
    if !target.starts_with("thumb") {
        return;
    }
    let out = PathBuf::from(std::env::var_os("OUT_DIR").unwrap_or_default());
    if let Err(e) = std::fs::copy(map, out.join("board-memory.x")) {
        panic!("copying {map}: {e}");
    }
    println!("cargo:rustc-link-search={}", out.display());
}

/// The MAVLink capture the `replay` image carries: the file `TWOCARS_MAVLINK_CAPTURE` names,
/// or none.
fn capture() {
    println!("cargo:rerun-if-env-changed=TWOCARS_MAVLINK_CAPTURE");
    let out = PathBuf::from(std::env::var_os("OUT_DIR").unwrap_or_default()).join("capture.bin");
    let written = match std::env::var_os("TWOCARS_MAVLINK_CAPTURE") {
        Some(path) => {
            println!("cargo:rerun-if-changed={}", PathBuf::from(&path).display());
            std::fs::copy(&path, &out).map(|_| ())
        }
        None => std::fs::write(&out, []),
    };
    if let Err(e) = written {
        panic!("writing {}: {e}", out.display());
    }
}
