//! Build script: generates the C header with cbindgen and sets the shared library's SONAME.
//!
//! The header is written to `$OUT_DIR/dcol.h`; `tests/header.rs` checks that it equals the
//! checked-in `include/dcol.h` (regenerate with `DCOL_BLESS=1 cargo test --test header`).

use std::env;
use std::path::PathBuf;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=cbindgen.toml");
    println!("cargo:rerun-if-changed=Cargo.toml");
    println!("cargo:rerun-if-changed=src/ffi");

    let crate_dir = PathBuf::from(env::var("CARGO_MANIFEST_DIR").expect("CARGO_MANIFEST_DIR"));
    let out_dir = PathBuf::from(env::var("OUT_DIR").expect("OUT_DIR"));
    let header = out_dir.join("dcol.h");

    let mut config = cbindgen::Config::from_file(crate_dir.join("cbindgen.toml"))
        .expect("cbindgen.toml is valid");
    let version = |k: &str| env::var(k).expect("cargo sets the version variables");
    config.after_includes = Some(format!(
        "\n#define DCOL_VERSION_MAJOR {}\n#define DCOL_VERSION_MINOR {}\n#define DCOL_VERSION_PATCH {}\n#define DCOL_VERSION_STRING \"{}\"\n\n/** A cold dcol_cache (all zeros). */\n#define DCOL_CACHE_INIT {{ {{ 0 }}, {{ 0 }} }}",
        version("CARGO_PKG_VERSION_MAJOR"),
        version("CARGO_PKG_VERSION_MINOR"),
        version("CARGO_PKG_VERSION_PATCH"),
        version("CARGO_PKG_VERSION"),
    ));
    cbindgen::Builder::new()
        .with_config(config)
        .with_src(crate_dir.join("src/ffi/mod.rs"))
        .generate()
        .expect("cbindgen could not generate the header from src/ffi")
        .write_to_file(&header);
    println!("cargo:rustc-env=DCOL_GENERATED_HEADER={}", header.display());

    // The shared library's SONAME: the ABI major version (0 until 1.0).
    if env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("linux") {
        println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,libdcol.so.0");
    }
}
