//! Links defmt's script into the firmware binaries (only they link defmt); `-Tlink.x` comes from
//! `.cargo/config.toml` for every thumb target.
fn main() {
    let target = std::env::var("TARGET").unwrap_or_default();
    if target.starts_with("thumb") && std::env::var_os("CARGO_FEATURE_DEFMT").is_some() {
        println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
    }
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");
}
