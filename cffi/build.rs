//! Give the shared library its SONAME, `libmotioncard.so.MAJOR`, so programs record that name
//! (not the unversioned development link) and keep working across compatible updates.
//! `cargo xtask install` lays out the matching symlinks.

fn main() {
    let major = std::env::var("CARGO_PKG_VERSION_MAJOR").expect("cargo sets the version");
    println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,libmotioncard.so.{major}");
    println!("cargo:rerun-if-changed=build.rs");
}
