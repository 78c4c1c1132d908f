//! The C library's SONAME: `libpixgeo.so.MAJOR`, or `libpixgeo.so.0.MINOR`
//! before 1.0, since 0.x versions break compatibility at each minor release.
//! `tools/install` installs the library under that name and reads it back to
//! make its links.

use std::env;

fn main() {
    if env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("linux") {
        return;
    }
    let major = env::var("CARGO_PKG_VERSION_MAJOR").expect("CARGO_PKG_VERSION_MAJOR");
    let minor = env::var("CARGO_PKG_VERSION_MINOR").expect("CARGO_PKG_VERSION_MINOR");
    let version = if major == "0" {
        format!("0.{minor}")
    } else {
        major
    };
    println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,libpixgeo.so.{version}");
}
