//! Building and installing libmotioncard for C users: `lib/libmotioncard.so.VERSION` with the
//! symlinks `libmotioncard.so.MAJOR` (its SONAME, what programs load) and `libmotioncard.so`
//! (what the linker finds), `lib/libmotioncard.a`, `include/motioncard.h` and
//! `lib/pkgconfig/motioncard.pc` under a prefix. Used by
//! `cargo xtask install` and, through `#[path]`, by the C tests in `cffi/tests/c_programs.rs`,
//! so both build and install the same way. Standard library only.

use std::ffi::OsStr;
use std::path::Path;
use std::process::Command;

/// What [`build`] asks cargo for.
///
/// Cargo gives a dependency the union of the features the selected packages ask of it, so
/// `--package motioncard-cffi` and `--workspace` compile the dependencies (nix, nalgebra, the
/// SDK…) in different feature sets, each a build of its own; and the two builds of the
/// library share one file name (`libmotioncard.so` carries no hash), so each replaces the
/// other's.
#[allow(dead_code)] // each user of this file takes one: xtask `Workspace`, the C tests `Cffi`
pub enum Packages<'a> {
    /// The libraries of every workspace member (`--workspace --lib`): the dependencies get the
    /// features of `cargo build --workspace`, so after `cargo build --workspace --release` there
    /// is nothing left to build. `cargo xtask install`.
    Workspace,
    /// motioncard-cffi alone with these of its features (`--package motioncard-cffi --lib
    /// --features …`): the least to build. The C tests (`test-panic`), in a target directory of
    /// their own so their library never replaces the one a workspace build made.
    Cffi(&'a [&'a str]),
}

/// Build the library with `cargo`, in the workspace at `workspace`, with cargo profile
/// `profile` ("release", "dev"…), into `target_dir`. The libraries are then in
/// `target_dir/<profile directory>` (`release`, `debug`…).
pub fn build(
    cargo: &OsStr,
    workspace: &Path,
    profile: &str,
    target_dir: &Path,
    packages: Packages,
) -> Result<(), String> {
    let mut cmd = Command::new(cargo);
    cmd.current_dir(workspace)
        .args(["build", "--lib", "--profile", profile])
        .arg("--target-dir")
        .arg(target_dir);
    match packages {
        Packages::Workspace => {
            cmd.arg("--workspace");
        }
        Packages::Cffi(features) => {
            cmd.args(["--package", "motioncard-cffi"]);
            if !features.is_empty() {
                cmd.args(["--features", &features.join(",")]);
            }
        }
    }
    let status = cmd.status().map_err(|e| format!("running cargo: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("building libmotioncard failed ({status})"))
    }
}

/// The native libraries a program linked against `libmotioncard.a` needs as well
/// (`rustc --print native-static-libs`, less those the C compiler links by default).
pub const STATIC_LIBS: &str = "-lpthread -ldl -lm -lrt -lutil";

/// The pkg-config file for a library installed under `prefix`.
pub fn pkg_config_file(prefix: &Path, version: &str) -> String {
    format!(
        "prefix={}\n\
         exec_prefix=${{prefix}}\n\
         libdir=${{exec_prefix}}/lib\n\
         includedir=${{prefix}}/include\n\
         \n\
         Name: motioncard\n\
         Description: C ABI of the motion-card SDK: open a card, move axes, read status, wait for events\n\
         Version: {version}\n\
         Libs: -L${{libdir}} -lmotioncard\n\
         Libs.private: {STATIC_LIBS}\n\
         Cflags: -I${{includedir}}\n",
        prefix.display()
    )
}

/// The SONAME of the shared library of `version` ("0.1.0" → "libmotioncard.so.0"), which
/// `cffi/build.rs` gives it.
pub fn soname(version: &str) -> String {
    let major = version.split('.').next().unwrap_or(version);
    format!("libmotioncard.so.{major}")
}

/// Copy the built libraries from `artifacts` (the cargo profile directory, e.g.
/// `target/release`) and the header from `header`, and write the pkg-config file, under
/// `prefix` (made absolute). The shared library is installed as `libmotioncard.so.VERSION`
/// with the symlinks `libmotioncard.so.MAJOR` → it and `libmotioncard.so` →
/// `libmotioncard.so.MAJOR`.
pub fn install(
    artifacts: &Path,
    header: &Path,
    prefix: &Path,
    version: &str,
) -> Result<(), String> {
    let prefix =
        std::path::absolute(prefix).map_err(|e| format!("prefix {}: {e}", prefix.display()))?;
    let lib = prefix.join("lib");
    let include = prefix.join("include");
    let pkgconfig = lib.join("pkgconfig");
    for d in [&lib, &include, &pkgconfig] {
        std::fs::create_dir_all(d).map_err(|e| format!("creating {}: {e}", d.display()))?;
    }
    let copy = |from: &Path, to: &Path| {
        // Replace, never write through: a running program may have the old library mapped.
        let _ = std::fs::remove_file(to);
        std::fs::copy(from, to)
            .map(|_| ())
            .map_err(|e| format!("copying {} to {}: {e}", from.display(), to.display()))
    };
    let real = format!("libmotioncard.so.{version}");
    let so = soname(version);
    copy(&artifacts.join("libmotioncard.so"), &lib.join(&real))?;
    for (link, target) in [
        (so.as_str(), real.as_str()),
        ("libmotioncard.so", so.as_str()),
    ] {
        let link = lib.join(link);
        let _ = std::fs::remove_file(&link);
        std::os::unix::fs::symlink(target, &link)
            .map_err(|e| format!("linking {} to {target}: {e}", link.display()))?;
    }
    copy(
        &artifacts.join("libmotioncard.a"),
        &lib.join("libmotioncard.a"),
    )?;
    copy(header, &include.join("motioncard.h"))?;
    let pc = pkgconfig.join("motioncard.pc");
    std::fs::write(&pc, pkg_config_file(&prefix, version))
        .map_err(|e| format!("writing {}: {e}", pc.display()))
}
