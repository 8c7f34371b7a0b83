//! Building and installing libmotioncard for C users: `lib/libmotioncard.so.VERSION` with the
//! symlinks `libmotioncard.so.MAJOR` (its SONAME, what programs load) and `libmotioncard.so`
//! (what the linker finds), `lib/libmotioncard.a`, `include/motioncard.h` and
//! `lib/pkgconfig/motioncard.pc` under a prefix. Used by
//! `cargo xtask install` and, through `#[path]`, by the C tests in `cffi/tests/c_programs.rs`,
//! so both build and install the same way. Standard library and binutils (`ld`, `objcopy`,
//! `nm`, `readelf`, `ar`) only.
//!
//! Both libraries export the C ABI and nothing else. The shared one already does: rustc links
//! a cdylib with a version script that keeps only the crate's `#[no_mangle]` functions. The
//! static library cargo builds is an archive of every object of the crate, its dependencies,
//! std and compiler-builtins, each with its global symbols (thousands): a second Rust static
//! library in the same program collides with them. [`hide_symbols`] makes it one relocatable
//! object whose only global definitions are the shared library's exports.

use std::collections::BTreeSet;
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
/// `libmotioncard.so.MAJOR`; the static library as [`hide_symbols`] makes it, exporting what
/// the shared library exports.
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
    let exports = exported_symbols(&artifacts.join("libmotioncard.so"))?;
    hide_symbols(
        &artifacts.join("libmotioncard.a"),
        &exports,
        &lib.join("libmotioncard.a"),
    )?;
    copy(header, &include.join("motioncard.h"))?;
    let pc = pkgconfig.join("motioncard.pc");
    std::fs::write(&pc, pkg_config_file(&prefix, version))
        .map_err(|e| format!("writing {}: {e}", pc.display()))
}

/// Run a tool to completion; its stdout, or an error with its stderr.
fn tool(cmd: &mut Command) -> Result<String, String> {
    let out = cmd
        .output()
        .map_err(|e| format!("running {cmd:?}: {e} (binutils is needed)"))?;
    if out.status.success() {
        Ok(String::from_utf8_lossy(&out.stdout).into_owned())
    } else {
        Err(format!(
            "{cmd:?} failed ({}): {}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

/// The symbols a shared library defines and exports (`nm -D --defined-only`). For
/// libmotioncard.so these are the `mc_` functions of the C ABI: the names rustc exports from a
/// cdylib, the crate's `#[no_mangle] extern "C"` functions, so the list comes from the code.
pub fn exported_symbols(shared: &Path) -> Result<BTreeSet<String>, String> {
    let out = tool(
        Command::new("nm")
            .args(["-D", "--defined-only", "--format=posix"])
            .arg(shared),
    )?;
    let names: BTreeSet<String> = out
        .lines()
        .filter_map(|l| l.split_whitespace().next())
        .map(String::from)
        .collect();
    if names.is_empty() {
        return Err(format!("{} exports nothing", shared.display()));
    }
    Ok(names)
}

/// The global symbols an object or archive defines (`nm -g --defined-only`).
pub fn defined_globals(file: &Path) -> Result<BTreeSet<String>, String> {
    let out = tool(
        Command::new("nm")
            .args(["-g", "--defined-only", "--format=posix"])
            .arg(file),
    )?;
    // Posix format: "NAME TYPE VALUE SIZE"; an archive adds "ARCHIVE[MEMBER]:" lines.
    Ok(out
        .lines()
        .filter(|l| !l.ends_with(':'))
        .filter_map(|l| l.split_whitespace().next())
        .map(String::from)
        .collect())
}

/// Make the static library `archive` into `out`, an archive of one relocatable object whose
/// only global definitions are `keep`:
/// 1. `ld -r -u SYMBOL… archive`: link the members `keep` needs, as a program's link would
///    pick them, into one object (their references to each other resolved inside it);
/// 2. `objcopy --keep-global-symbols`: every other global becomes local, invisible to the
///    program's link; the undefined references (libc, libgcc_s) stay as they are. Local
///    COMDAT group signatures (`DW.ref.rust_eh_personality`) get a suffix of ours, or the
///    program's link would keep another Rust library's group of that name and drop ours, whose
///    symbol it can no longer see. The embedded LLVM bitcode (`.llvmbc`, `.llvmcmd`, only for
///    Rust LTO) goes: a C link has no use for it and binutils' LLVM plugin may choke on it;
/// 3. `ar`: the archive.
///
/// Fails when the result defines other globals than `keep`.
pub fn hide_symbols(archive: &Path, keep: &BTreeSet<String>, out: &Path) -> Result<(), String> {
    let work = std::env::temp_dir().join(format!("motioncard-install-{}", std::process::id()));
    std::fs::create_dir_all(&work).map_err(|e| format!("creating {}: {e}", work.display()))?;
    let result = hide_symbols_in(archive, keep, out, &work);
    let _ = std::fs::remove_dir_all(&work);
    result
}

fn hide_symbols_in(
    archive: &Path,
    keep: &BTreeSet<String>,
    out: &Path,
    work: &Path,
) -> Result<(), String> {
    let linked = work.join("linked.o");
    let object = work.join("libmotioncard.o");
    let keep_file = work.join("keep");
    let list: String = keep.iter().map(|k| format!("{k}\n")).collect();
    std::fs::write(&keep_file, list)
        .map_err(|e| format!("writing {}: {e}", keep_file.display()))?;

    let mut ld = Command::new("ld");
    ld.arg("-r").arg("-o").arg(&linked);
    for k in keep {
        ld.arg(format!("--undefined={k}"));
    }
    tool(ld.arg(archive))?;

    let groups = tool(Command::new("readelf").args(["-g", "-W"]).arg(&linked))?;
    let mut objcopy = Command::new("objcopy");
    objcopy
        .arg(format!("--keep-global-symbols={}", keep_file.display()))
        .args(["--remove-section=.llvmbc", "--remove-section=.llvmcmd"]);
    for signature in comdat_signatures(&groups) {
        if !keep.contains(signature) {
            objcopy.arg(format!("--redefine-sym={signature}={signature}.motioncard"));
        }
    }
    tool(objcopy.arg(&linked).arg(&object))?;

    let globals = defined_globals(&object)?;
    if &globals != keep {
        let extra: Vec<_> = globals.difference(keep).collect();
        let missing: Vec<_> = keep.difference(&globals).collect();
        return Err(format!(
            "hiding the static library's symbols: extra globals {extra:?}, missing {missing:?}"
        ));
    }
    // Replace, never write through (as the other installed files).
    let _ = std::fs::remove_file(out);
    tool(Command::new("ar").arg("crsD").arg(out).arg(&object))?;
    Ok(())
}

/// The signatures of the COMDAT groups `readelf -g -W` lists:
/// ``COMDAT group section [    1] `.group' [DW.ref.rust_eh_personality] contains 2 sections:``.
fn comdat_signatures(readelf: &str) -> Vec<&str> {
    readelf
        .lines()
        .filter(|l| l.starts_with("COMDAT group section"))
        .filter_map(|l| {
            let head = &l[..l.rfind("] contains")?];
            Some(&head[head.rfind('[')? + 1..])
        })
        .collect()
}
