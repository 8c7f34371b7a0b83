//! The C programs of the workspace's `examples/c/`, built the way a C user builds them: the library is
//! installed under a temporary prefix by the install code of `cargo xtask install`, each
//! program is compiled by gcc with `-std=c11 -Wall -Wextra -Werror` (`c89.c` with
//! `-pedantic-errors` under `-std=c89` and `-std=gnu89`) and the flags pkg-config
//! reads from the installed `motioncard.pc`, and run against the emulated card, both `sim`
//! (real-time) and `stepped` (`groups`, `errors`, `safety`, `machine`, `homing`, `config`,
//! `nurbs_path`, `path`, `compare`, `probe`, `gearing`, `pvt`, `cam` and `units` choose their
//! cards; `debug` and `path_stream` run on `sim`, `debug` once under valgrind with the
//! debugging watchdog of `MOTIONCARD_SIM_WATCHDOG_MS`). A program of the tests' own compiles a
//! use of every name the header's comments cite.
//! `move` and `c89` are also linked statically, and a program of the tests' own beside a second
//! Rust static library; `errors`, `groups`, `safety`, `machine`, `homing`, `config`,
//! `nurbs_path`, `path`, `compare`, `probe`, `gearing`, `pvt`, `cam`, `scope` and `panic` also
//! run under valgrind. The installed libraries' symbols are checked with binutils' `nm`.
//!
//! Needs gcc, g++, binutils, pkg-config, valgrind (`.ci/run` installs them when missing) and
//! rustc (beside cargo). Nothing here asserts on time: the child processes only have a
//! generous limit so a hang fails instead of stalling the suite.

#[path = "../../xtask/src/install.rs"]
mod install;

use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant, SystemTime};

const CFLAGS: &[&str] = &["-std=c11", "-Wall", "-Wextra", "-Werror", "-O1", "-g"];

/// Longest a program may run before it counts as hung (valgrind included).
const HANG_LIMIT: Duration = Duration::from_secs(300);

struct Installed {
    prefix: PathBuf,
    work: PathBuf,
    /// The libraries of a workspace build in this test's profile directory
    /// (`TARGET/release/libmotioncard.{so,a}`), and when each was last written (`None`: absent),
    /// as they were before the C tests built theirs.
    workspace_libs: Vec<(PathBuf, Option<SystemTime>)>,
}

/// When `path` was last written; `None` when it does not exist.
fn modified(path: &Path) -> Option<SystemTime> {
    std::fs::metadata(path).and_then(|m| m.modified()).ok()
}

/// Install once per test run, under `target/tmp/c-abi/`.
fn installed() -> &'static Installed {
    static INSTALLED: OnceLock<Installed> = OnceLock::new();
    INSTALLED.get_or_init(|| {
        let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("c-abi");
        let _ = std::fs::remove_dir_all(&root);
        let prefix = root.join("prefix");
        let work = root.join("bin");
        std::fs::create_dir_all(&work).unwrap();
        // This test's executable is TARGET/PROFILE_DIR/deps/c_programs-HASH. `cargo test`
        // does not build the cdylib and staticlib (nothing links the library), so build them
        // with the install code of `cargo xtask install` and this test's profile, with the
        // test-panic feature (the hidden mc__test_panic_next_call for panic.c), into a target
        // directory of their own, TARGET/c-tests: in TARGET they would replace the libraries
        // of a workspace build (same file names) that `cargo xtask install` reuses.
        let exe = std::env::current_exe().unwrap();
        let profile_dir = exe.parent().and_then(Path::parent).unwrap();
        let target_dir = profile_dir.parent().unwrap().join("c-tests");
        let profile_name = profile_dir.file_name().and_then(|n| n.to_str());
        let profile = match profile_name {
            Some("debug") => "dev",
            Some(p) => p,
            None => panic!("unexpected test location {}", exe.display()),
        };
        let workspace_libs = ["libmotioncard.so", "libmotioncard.a"]
            .map(|f| profile_dir.join(f))
            .into_iter()
            .map(|p| {
                let t = modified(&p);
                (p, t)
            })
            .collect();
        let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
        let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
        install::build(
            &cargo,
            crate_dir.parent().unwrap(),
            profile,
            &target_dir,
            install::Packages::Cffi(&["test-panic"]),
        )
        .expect("build libmotioncard");
        install::install(
            &target_dir.join(profile_name.unwrap()),
            &crate_dir.join("include/motioncard.h"),
            &prefix,
            env!("CARGO_PKG_VERSION"),
        )
        .expect("install libmotioncard");
        Installed {
            prefix,
            work,
            workspace_libs,
        }
    })
}

fn examples_dir() -> PathBuf {
    // The workspace's examples/c/, next to the Rust examples of the root package.
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("cffi lives in the workspace")
        .join("examples/c")
}

/// `pkg-config ARGS motioncard` against the installed .pc file, split into words.
fn pkg_config(args: &[&str]) -> Vec<String> {
    let inst = installed();
    let out = Command::new("pkg-config")
        .args(args)
        .arg("motioncard")
        .env("PKG_CONFIG_PATH", inst.prefix.join("lib/pkgconfig"))
        .output()
        .expect("pkg-config is needed (apt-get install pkg-config)");
    assert!(
        out.status.success(),
        "pkg-config {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout)
        .unwrap()
        .split_whitespace()
        .map(String::from)
        .collect()
}

#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
enum Link {
    Shared,
    Static,
}

/// Compile `examples/c/NAME.c` with [`CFLAGS`] once per link mode; returns the executable.
fn compile(name: &str, link: Link) -> PathBuf {
    compile_with(name, link, CFLAGS)
}

/// Compile `examples/c/NAME.c` with `cflags` (the first one `-std=`) once per link mode and
/// flags; returns the executable.
fn compile_with(name: &str, link: Link, cflags: &[&str]) -> PathBuf {
    type Key = (String, Link, Vec<String>);
    static BUILT: OnceLock<Mutex<HashMap<Key, PathBuf>>> = OnceLock::new();
    let built = BUILT.get_or_init(Default::default);
    let mut built = built.lock().unwrap_or_else(|p| p.into_inner());
    let key = (
        name.to_string(),
        link,
        cflags.iter().map(|f| f.to_string()).collect(),
    );
    if let Some(p) = built.get(&key) {
        return p.clone();
    }
    let inst = installed();
    let std = cflags[0].strip_prefix("-std=").expect("-std= first");
    let exe = inst.work.join(match link {
        Link::Shared => format!("{name}-{std}"),
        Link::Static => format!("{name}-{std}-static"),
    });
    let mut cmd = Command::new("gcc");
    cmd.args(cflags)
        .arg(examples_dir().join(format!("{name}.c")))
        .arg("-o")
        .arg(&exe)
        .args(pkg_config(&["--cflags"]));
    match link {
        Link::Shared => {
            cmd.args(pkg_config(&["--libs"]));
        }
        Link::Static => {
            // The archive itself, then what it needs (Libs.private), less -lmotioncard.
            let libdir = pkg_config(&["--variable=libdir"]).join("");
            cmd.arg(Path::new(&libdir).join("libmotioncard.a")).args(
                pkg_config(&["--static", "--libs-only-l"])
                    .into_iter()
                    .filter(|l| l != "-lmotioncard"),
            );
        }
    }
    cmd.args(["-lpthread", "-lm"]);
    let out = cmd.output().expect("gcc is needed (apt-get install gcc)");
    assert!(
        out.status.success(),
        "compiling {name}.c ({link:?}) failed:\n{:?}\n{}",
        cmd,
        String::from_utf8_lossy(&out.stderr)
    );
    built.insert(key, exe.clone());
    exe
}

/// Run a command to completion (killed after [`HANG_LIMIT`]).
fn run_to_end(mut cmd: Command) -> Output {
    let mut child = cmd
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("spawning {cmd:?}: {e}"));
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > HANG_LIMIT {
            let _ = child.kill();
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// Run a compiled program with the installed library on its path; returns its stdout.
fn run(exe: &Path, args: &[&str], wrapper: &[&str]) -> String {
    run_env(exe, args, wrapper, &[])
}

/// [`run`] with these environment variables set.
fn run_env(exe: &Path, args: &[&str], wrapper: &[&str], env: &[(&str, &str)]) -> String {
    let inst = installed();
    let mut cmd = match wrapper.split_first() {
        Some((w, rest)) => {
            let mut c = Command::new(w);
            c.args(rest).arg(exe);
            c
        }
        None => Command::new(exe),
    };
    cmd.args(args)
        .env("LD_LIBRARY_PATH", inst.prefix.join("lib"))
        .envs(env.iter().copied());
    let out = run_to_end(cmd);
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "{} {args:?} exited with {:?}\nstdout:\n{stdout}\nstderr:\n{stderr}",
        exe.display(),
        out.status
    );
    stdout
}

/// Run a program on a real-time `sim` card and on a stepped one; both must pass.
fn run_both(name: &str) -> [String; 2] {
    let exe = compile(name, Link::Shared);
    ["sim", "stepped"].map(|card| {
        let out = run(&exe, &[card], &[]);
        assert!(
            out.contains(&format!("PASS {name}\n")),
            "{name} {card}:\n{out}"
        );
        out
    })
}

#[test]
fn install_lays_out_library_header_and_pkg_config() {
    let inst = installed();
    let version = env!("CARGO_PKG_VERSION");
    let real = format!("libmotioncard.so.{version}");
    for f in [
        &format!("lib/{real}"),
        "lib/libmotioncard.a",
        "include/motioncard.h",
        "lib/pkgconfig/motioncard.pc",
    ] {
        let meta = std::fs::symlink_metadata(inst.prefix.join(f)).unwrap();
        assert!(meta.is_file(), "{f} not installed as a file");
    }
    // The versioned symlinks: libmotioncard.so -> .so.0 -> .so.0.1.0.
    let so = install::soname(version);
    assert_eq!(so, "libmotioncard.so.0");
    for (link, target) in [
        (so.as_str(), real.as_str()),
        ("libmotioncard.so", so.as_str()),
    ] {
        assert_eq!(
            std::fs::read_link(inst.prefix.join("lib").join(link)).unwrap(),
            Path::new(target),
            "{link}"
        );
    }
    assert_eq!(pkg_config(&["--modversion"]), [env!("CARGO_PKG_VERSION")]);
    assert_eq!(
        pkg_config(&["--cflags"]),
        [format!("-I{}", inst.prefix.join("include").display())]
    );
    assert_eq!(
        pkg_config(&["--libs"]),
        [
            format!("-L{}", inst.prefix.join("lib").display()),
            "-lmotioncard".to_string()
        ]
    );
    // The installed header is the checked-in one.
    assert_eq!(
        std::fs::read(inst.prefix.join("include/motioncard.h")).unwrap(),
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("include/motioncard.h")).unwrap()
    );
}

/// The C tests' library (with `test-panic`) is built in a target directory of its own: the
/// libraries of a workspace build, which `cargo xtask install` reuses, are left as they were
/// (before, the tests replaced them with their own build, and the next install rebuilt them).
#[test]
fn the_c_tests_leave_the_workspace_build_alone() {
    let inst = installed();
    for (lib, before) in &inst.workspace_libs {
        assert_eq!(
            &modified(lib),
            before,
            "the C tests' build wrote {}",
            lib.display()
        );
    }
}

/// The functions the header declares (declarations start a line; comments and typedefs
/// do not).
fn header_functions() -> BTreeSet<String> {
    let h = std::fs::read_to_string(installed().prefix.join("include/motioncard.h")).unwrap();
    let fns: BTreeSet<String> = h
        .lines()
        .filter(|l| l.starts_with(|c: char| c.is_ascii_alphabetic()) && !l.starts_with("typedef"))
        .filter_map(|l| {
            // "mc_result mc_open(", "const char *mc_result_str(": the word before the '('.
            let name = l[..l.find('(')?].rsplit([' ', '*']).next()?;
            name.starts_with("mc_").then(|| name.to_string())
        })
        .collect();
    assert!(fns.len() > 60 && fns.contains("mc_open") && fns.contains("mc_result_str"));
    fns
}

/// Both installed libraries export the C ABI and nothing else: every function of the header,
/// the test build's hidden panic hook, and no other symbol (no Rust, std or
/// compiler-builtins global that could collide with another library's).
#[test]
fn both_libraries_export_the_c_abi_only() {
    let inst = installed();
    let lib = inst.prefix.join("lib");
    let shared = install::exported_symbols(&lib.join("libmotioncard.so")).unwrap();
    let archive = install::defined_globals(&lib.join("libmotioncard.a")).unwrap();
    let mut abi = header_functions();
    abi.insert("mc__test_panic_next_call".to_string());
    let not_abi: Vec<_> = archive.difference(&abi).take(20).collect();
    assert!(
        not_abi.is_empty(),
        "libmotioncard.a exports {} globals outside the C ABI, such as {not_abi:?}",
        archive.difference(&abi).count()
    );
    assert_eq!(shared, abi, "libmotioncard.so");
    assert_eq!(archive, abi, "libmotioncard.a");
}

/// A second Rust static library, with its own copy of std (built with `-C lto`, which puts std
/// and the Rust runtime symbols into one object that the program's link must take whole),
/// links into one C program with libmotioncard.a, in either order, and both work: each
/// library panics and catches its own panic (`MC_ERR_PANIC` through the test build's hook).
#[test]
fn two_rust_static_libraries_link_into_one_c_program() {
    let inst = installed();
    let dir = inst.work.join("two-rust-libs");
    std::fs::create_dir_all(&dir).unwrap();
    let other_rs = dir.join("other.rs");
    std::fs::write(
        &other_rs,
        "/// Panics on every even i < n and catches it; returns the number caught.\n\
         #[no_mangle]\n\
         pub extern \"C\" fn other_caught_panics(n: u32) -> u32 {\n\
             (0..n)\n\
                 .filter(|i| std::panic::catch_unwind(|| assert!(i % 2 == 1, \"other {i}\")).is_err())\n\
                 .count() as u32\n\
         }\n",
    )
    .unwrap();
    // rustc beside this cargo (a rustup toolchain), else the one on the PATH.
    let rustc = std::env::var_os("CARGO")
        .map(PathBuf::from)
        .map(|c| c.with_file_name("rustc"))
        .filter(|r| r.is_file())
        .unwrap_or_else(|| PathBuf::from("rustc"));
    let other = dir.join("libother.a");
    let out = Command::new(&rustc)
        .args([
            "--edition",
            "2021",
            "--crate-type",
            "staticlib",
            "--crate-name",
            "other",
        ])
        .args(["-C", "opt-level=2", "-C", "lto", "-o"])
        .arg(&other)
        .arg(&other_rs)
        .output()
        .unwrap_or_else(|e| panic!("{}: {e}", rustc.display()));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let main_c = dir.join("two.c");
    std::fs::write(
        &main_c,
        r#"#include <motioncard.h>
#include <stdio.h>

uint32_t other_caught_panics(uint32_t n);
mc_result mc__test_panic_next_call(void);

int main(void) {
    mc_card card = 0;
    uint32_t caught = other_caught_panics(4);
    mc_result r = mc_open_sim_stepped(1, 1000, &card);
    if (r != MC_OK) return 1;
    if (mc__test_panic_next_call() != MC_OK) return 1;
    r = mc_ping(card);
    printf("other caught %u panics, mc_ping after a panic: %s\n", caught, mc_result_str(r));
    if (mc_ping(card) != MC_OK || mc_close(card) != MC_OK) return 1;
    if (caught != 2 || r != MC_ERR_PANIC) return 1;
    printf("PASS two\n");
    return 0;
}
"#,
    )
    .unwrap();
    let ours = inst.prefix.join("lib/libmotioncard.a");
    for (name, first, second) in [
        ("ours-first", &ours, &other),
        ("other-first", &other, &ours),
    ] {
        let exe = dir.join(name);
        let mut cmd = Command::new("gcc");
        cmd.args(CFLAGS)
            .arg(format!("-I{}", inst.prefix.join("include").display()))
            .arg(&main_c)
            .arg(first)
            .arg(second)
            .args(install::STATIC_LIBS.split_whitespace())
            .arg("-o")
            .arg(&exe);
        let out = cmd.output().unwrap();
        assert!(
            out.status.success(),
            "linking two Rust static libraries ({name}) failed:\n{}",
            String::from_utf8_lossy(&out.stderr)
                .lines()
                .filter(|l| !l.starts_with("bfd plugin"))
                .take(12)
                .collect::<Vec<_>>()
                .join("\n")
        );
        let out = run(&exe, &[], &[]);
        assert!(out.contains("PASS two\n"), "{name}: {out}");
        assert!(
            out.contains("other caught 2 panics, mc_ping after a panic: "),
            "{name}: {out}"
        );
    }
}

/// The C programs share `examples/` with the root package's Rust examples: cargo's example
/// discovery (`examples/*.rs`, `examples/*/main.rs`) must not take `examples/c/` for one.
#[test]
fn cargo_examples_are_the_rust_files_only() {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let out = Command::new(cargo)
        .current_dir(root)
        .args([
            "metadata",
            "--no-deps",
            "--format-version",
            "1",
            "--offline",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let meta = String::from_utf8(out.stdout).unwrap();
    // Every example target's source path, from the JSON without a JSON crate.
    let examples: Vec<&str> = meta
        .split("\"kind\":[\"example\"]")
        .skip(1)
        .filter_map(|rest| rest.split("\"src_path\":\"").nth(1))
        .filter_map(|rest| rest.split('"').next())
        .collect();
    assert!(examples.len() >= 5, "{examples:?}");
    for src in &examples {
        assert!(
            src.ends_with(".rs") && !src.contains("/examples/c/"),
            "{src}"
        );
    }
    // No warning about the directory either.
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("examples/c"), "{err}");
}

/// `readelf -d FILE`: the dynamic section.
fn dynamic_section(file: &Path) -> String {
    let out = Command::new("readelf")
        .arg("-d")
        .arg(file)
        .output()
        .expect("readelf is needed (binutils)");
    assert!(out.status.success(), "readelf -d {}", file.display());
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
fn the_shared_library_has_a_soname_and_programs_need_it() {
    let inst = installed();
    let lib = dynamic_section(&inst.prefix.join("lib/libmotioncard.so"));
    assert!(
        lib.contains("(SONAME)") && lib.contains("Library soname: [libmotioncard.so.0]"),
        "{lib}"
    );
    // A program linked with -lmotioncard records the SONAME, not the development link.
    let prog = dynamic_section(&compile("move", Link::Shared));
    assert!(
        prog.contains("Shared library: [libmotioncard.so.0]"),
        "{prog}"
    );
    assert!(!prog.contains("[libmotioncard.so]"), "{prog}");
    // The static program needs no libmotioncard at all.
    let stat = dynamic_section(&compile("move", Link::Static));
    assert!(!stat.contains("libmotioncard"), "{stat}");
}

/// The installed header alone, in every language version it promises (its preamble): C89 and
/// GNU89 (no `//` comments, no `bool`, no `long long`), C99, C11, C++98 and C++11, each with
/// `-pedantic-errors -Wall -Wextra -Werror`.
#[test]
fn header_compiles_alone_as_strict_c_and_as_cxx() {
    let inst = installed();
    let src = inst.work.join("header_only.c");
    std::fs::write(
        &src,
        "#include <motioncard.h>\n\
         mc_result (*const fns[])(mc_card) = {mc_close, mc_ping};\n",
    )
    .unwrap();
    let include = format!("-I{}", inst.prefix.join("include").display());
    for (compiler, std, lang) in [
        ("gcc", "-std=c89", "c"),
        ("gcc", "-std=gnu89", "c"),
        ("gcc", "-std=c99", "c"),
        ("gcc", "-std=c11", "c"),
        ("g++", "-std=c++98", "c++"),
        ("g++", "-std=c++11", "c++"),
    ] {
        let out = Command::new(compiler)
            .args([
                std,
                "-pedantic-errors",
                "-Wall",
                "-Wextra",
                "-Werror",
                "-fsyntax-only",
            ])
            .args(["-x", lang])
            .arg(&include)
            .arg(&src)
            .output()
            .unwrap_or_else(|e| panic!("{compiler} is needed: {e}"));
        assert!(
            out.status.success(),
            "{compiler} {std}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

/// A C89 program (`examples/c/c89.c`), compiled as C89 and as GNU89 with `-pedantic-errors`,
/// links against the shared and the static library and runs.
#[test]
fn a_c89_program_builds_links_and_runs() {
    for std in ["-std=c89", "-std=gnu89"] {
        let flags = [
            std,
            "-pedantic-errors",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-O1",
        ];
        for link in [Link::Shared, Link::Static] {
            let out = run(&compile_with("c89", link, &flags), &[], &[]);
            assert!(out.contains("PASS c89\n"), "{std} {link:?}: {out}");
            assert!(out.contains("out to 10000.0, back to 6000.0"), "{out}");
        }
    }
}

#[test]
fn move_an_axis_and_wait_for_done() {
    for out in run_both("move") {
        // Done once within the program's in-position window: 2 counts, 0.001 mm.
        let at: f64 = out
            .split("moved axis 0 to ")
            .nth(1)
            .and_then(|rest| rest.split(' ').next())
            .and_then(|mm| mm.parse().ok())
            .unwrap_or(f64::NAN);
        assert!((at - 25.0).abs() <= 0.001, "done at {at} mm: {out}");
        assert!(out.contains("moved axis 0 back to 20.00"), "{out}");
        let layout = format!(
            "layout {}.{}, 8 axes",
            motioncard_sdk::proto::raw::MC_LAYOUT_MAJOR,
            motioncard_sdk::proto::raw::MC_LAYOUT_MINOR
        );
        assert!(
            out.contains("firmware 1.0.0") && out.contains(&layout),
            "{out}"
        );
    }
}

#[test]
fn read_status_in_a_loop() {
    for out in run_both("status_loop") {
        assert!(out.contains("done at 20000.0"), "{out}");
    }
}

#[test]
fn events_through_epoll_callbacks_and_waits() {
    for out in run_both("events") {
        assert!(out.contains("epoll: "), "{out}");
        assert!(out.contains("mc_wait_event: "), "{out}");
    }
}

#[test]
fn several_threads_on_one_card() {
    for out in run_both("threads") {
        assert!(out.contains("4 threads moved 20 times"), "{out}");
    }
}

#[test]
fn groups_arcs_filters_and_nurbs() {
    let out = run(&compile("groups", Link::Shared), &[], &[]);
    assert!(out.contains("PASS groups\n"), "{out}");
    assert!(out.contains("circle: "), "{out}");
    assert!(out.contains("NURBS quarter circle: "), "{out}");
}

#[test]
fn a_nurbs_path_longer_than_the_queue_and_sim_options() {
    let out = run(&compile("nurbs_path", Link::Shared), &[], &[]);
    assert!(out.contains("PASS nurbs_path\n"), "{out}");
    assert!(out.contains("NURBS path: 40 pieces to x = 80000"), "{out}");
}

#[test]
fn nurbs_path_program_is_clean_under_valgrind() {
    let out = run_under_valgrind("nurbs_path");
    assert!(out.contains("PASS nurbs_path\n"), "{out}");
}

#[test]
fn every_error_path_and_misuse() {
    let out = run(&compile("errors", Link::Shared), &[], &[]);
    assert!(out.contains("PASS errors\n"), "{out}");
}

#[test]
fn homing_from_c() {
    let out = run(&compile("homing", Link::Shared), &[], &[]);
    assert!(out.contains("PASS homing\n"), "{out}");
    assert!(out.contains("homed on the index: at 125.0"), "{out}");
}

/// Layout 1.8: the settings read back from the card, a configuration file saved, loaded on a
/// fresh card and saved again byte for byte, a bad file refused with its key and line.
#[test]
fn config_from_c() {
    let out = run(&compile("config", Link::Shared), &[], &[]);
    assert!(out.contains("PASS config\n"), "{out}");
}

/// Layout 1.9: leadscrew compensation from C: each refusal's code, the table read back, the
/// correction in the status after moves from both sides, a change refused while moving.
#[test]
fn compensation_from_c() {
    let out = run(&compile("comp", Link::Shared), &[], &[]);
    assert!(out.contains("PASS comp\n"), "{out}");
    assert!(
        out.contains("comp: at 7500 the correction is -2.000 counts"),
        "{out}"
    );
}

/// Layout 1.10: `examples/c/gantry.c`: a gantry formed, homed (squared to its offset), the
/// master moved with the slave following within a count, the slave's own move refused, and
/// the gantry dissolved.
#[test]
fn a_gantry_from_c_program() {
    let out = run(&compile("gantry", Link::Shared), &[], &[]);
    assert!(out.contains("PASS gantry\n"), "{out}");
    assert!(
        out.contains("gantry: squared, offset in force 10.0 counts"),
        "{out}"
    );
    assert!(
        out.contains("gantry: master at 20000, slave at 20010, largest skew 1 counts"),
        "{out}"
    );
}

/// Layout 1.10: the handwheel from C (x10, handed over, let go, the refusals).
#[test]
fn handwheel_from_c() {
    let out = run(&compile("handwheel", Link::Shared), &[], &[]);
    assert!(out.contains("PASS handwheel\n"), "{out}");
    assert!(
        out.contains("handwheel: 10 detents x10: 100.0 counts"),
        "{out}"
    );
}

/// Layout 1.12: cards on one sync bus from C (a synchronised start, hold, override and halt
/// on three stepped cards, a command timed to a tick, the refusals of timing).
#[test]
fn cards_on_one_sync_bus_from_c() {
    let out = run(&compile("sync", Link::Shared), &[], &[]);
    assert!(out.contains("PASS sync\n"), "{out}");
    assert!(
        out.contains("sync: 6 axes on 3 cards started on tick"),
        "{out}"
    );
}

/// Layout 1.14: a path across cards from C: a 12-axis path over two stepped cards, split
/// 6 + 6 and 8 + 4, bit-identical on every tick sampled and at its targets exactly; a halt
/// timed on both cards (after a hold and a resume); the card's refusals of staging entries
/// sent raw; a pause timed on both cards, every axis on its segment's end.
#[test]
fn a_path_across_cards_from_c() {
    let out = run(&compile("set_path", Link::Shared), &[], &[]);
    assert!(out.contains("PASS set_path"), "{out}");
    assert!(
        out.contains("at the end of segment 21 on both cards, every axis on its end"),
        "{out}"
    );
    assert!(
        out.contains("set_path: 12 axes split 6+6 and 8+4 bit-identical on"),
        "{out}"
    );
    assert!(out.contains("every axis stopped at"), "{out}");
    for l in out.lines().filter(|l| l.starts_with("set_path:")) {
        println!("{l}");
    }
}

/// Layout 1.11: analog I/O and the path-speed output from C (a threshold event, the ADC's
/// sample, a spare DAC, the PSO gated by an output, the refusals).
#[test]
fn analog_io_and_pso_from_c() {
    let out = run(&compile("analog", Link::Shared), &[], &[]);
    assert!(out.contains("PASS analog\n"), "{out}");
    assert!(
        out.contains("analog: DAC 1 set to 3.3 V puts out 3.30078125 V"),
        "{out}"
    );
}

/// Layout 1.10: `examples/c/rotary.c`: a modulo axis's period set, read back and refused
/// (zero, out of range, while moving), absolute moves the way they name, the status wrapping.
#[test]
fn rotary_axes_from_c() {
    let out = run(&compile("rotary", Link::Shared), &[], &[]);
    assert!(out.contains("PASS rotary\n"), "{out}");
    assert!(
        out.contains("rotary: shortest to 350 moved -556 counts, positive to 340 moved 9722"),
        "{out}"
    );
}

/// Layout 1.13: `examples/c/normal_arc.c`: a tilted circle of 1¼ turns with a fourth axis
/// climbing, then a helix rising along the normal, every tick on the circle within 1e-6
/// relative; the refusals (zero normal, an axis twice, the centre or the end off the plane, the
/// end off the circle, a NULL arc, a lone piece sent raw).
#[test]
fn normal_vector_arcs_in_the_move_queue_from_c() {
    let out = run(&compile("normal_arc", Link::Shared), &[], &[]);
    assert!(out.contains("PASS normal_arc (7 refusals)\n"), "{out}");
    assert!(
        out.contains("normal_arc: tilted circle, 1.25 turns"),
        "{out}"
    );
    assert!(
        out.contains("normal_arc: helix rising 800 along the normal"),
        "{out}"
    );
}

/// Layout 1.11: `examples/c/servo.c`: PID+FF switched to and back at rest, read back and
/// refused; servo filters set, read back with the card's coefficients, refused and cleared.
#[test]
fn servo_law_and_filters_from_c() {
    let out = run(&compile("servo", Link::Shared), &[], &[]);
    assert!(out.contains("PASS servo (9 refusals)\n"), "{out}");
    assert!(
        out.contains("notch at 300 Hz and low-pass at 1500 Hz; move ended at 20000"),
        "{out}"
    );
}

/// Layout 1.12: a sweep of the closed loop from C, its points read again, the resonances, and
/// the refusals (a frequency above Nyquist, a negative or NaN amplitude, a sine beyond the
/// following-error limit, an unknown mode).
#[test]
fn frequency_response_from_c() {
    let out = run(&compile("freq", Link::Shared), &[], &[]);
    assert!(out.contains("PASS freq (6 refusals)\n"), "{out}");
    assert!(out.contains("freq: closed loop"), "{out}");
}

#[test]
fn compare_and_digital_io_from_c_are_clean_under_valgrind() {
    let out = run_under_valgrind("compare");
    assert!(out.contains("PASS compare\n"), "{out}");
    assert!(
        out.contains("inputs: debounced edge 4 ticks after the pin (debounce 4)"),
        "{out}"
    );
    assert!(
        out.contains("compare: series of 1000 at 1e6 counts/s: 1000 fired, 0 missed"),
        "{out}"
    );
    assert!(
        out.contains("compare: table of 6000 streamed on low water: 6000 fired, 0 missed"),
        "{out}"
    );
}

#[test]
fn touch_probe_from_c_is_clean_under_valgrind() {
    let out = run_under_valgrind("probe");
    assert!(out.contains("PASS probe\n"), "{out}");
    assert!(out.contains("probe: 6 parts hit at 2e6 counts/s"), "{out}");
    assert!(
        out.contains("probe: index pulses in the window: 8 captured"),
        "{out}"
    );
}

#[test]
fn safety_stops_from_c() {
    let out = run(&compile("safety", Link::Shared), &[], &[]);
    assert!(out.contains("PASS safety\n"), "{out}");
    // 5 ms at 10 kHz.
    assert!(
        out.contains("watchdog: tripped 50 ticks after the heartbeat stopped"),
        "{out}"
    );
    assert!(out.contains("e-stop: category 1 stopped 4 axes"), "{out}");
    assert!(
        out.contains("soft limit: refused beyond, stopped at -10"),
        "{out}"
    );
    assert!(out.contains("following error: tripped at "), "{out}");
}

#[test]
fn a_panic_inside_the_library_becomes_mc_err_panic_in_c() {
    let out = run(&compile("panic", Link::Shared), &[], &[]);
    assert!(out.contains("PASS panic\n"), "{out}");
    // The hook is for test builds only: the public header does not declare it.
    let header = std::fs::read_to_string(installed().prefix.join("include/motioncard.h")).unwrap();
    assert!(!header.contains("test_panic"));
}

#[test]
fn panic_program_is_clean_under_valgrind() {
    let out = run_under_valgrind("panic");
    assert!(out.contains("PASS panic\n"), "{out}");
}

/// Serve an `emu:` card named `name` from this process on the real-time clock.
fn serve_emu(name: &str) -> (card_emu::emu::server::Server, card_emu::Runner) {
    serve_emu_serial(name, 0)
}

/// [`serve_emu`], the card with serial number `serial`.
fn serve_emu_serial(name: &str, serial: u64) -> (card_emu::emu::server::Server, card_emu::Runner) {
    use card_emu::{emu::server::Server, Clock, EmuOptions, Emulator, Runner};
    let opts = EmuOptions {
        serial,
        ..EmuOptions::new(2, 10_000)
    };
    let emu = Emulator::create(name, &opts).unwrap();
    let server = Server::start(name, emu.lessor()).unwrap();
    (server, Runner::spawn(emu, Clock::RealTime, false).unwrap())
}

/// Cancelling and closing from one thread end the waits of the others at once; a clean close
/// leaves the card ready for the next program (nothing latched, nothing inherited).
#[test]
fn cancel_and_close_wake_every_wait_and_a_closed_card_is_ready_for_the_next_program() {
    let name = format!("cffi-life-{}", std::process::id());
    let _card = serve_emu(&name);
    let out = run(
        &compile("lifecycle", Link::Shared),
        &[&format!("emu:{name}")],
        &[],
    );
    assert!(out.contains("PASS lifecycle\n"), "{out}");
}

const CARD_ROLE: &str = "MC_C_TESTS_CARD_ROLE";

/// The card process of the dead-card test: this test binary run again with
/// `MC_C_TESTS_CARD_ROLE=NAME` serves `emu:NAME` until it is killed.
#[test]
fn card_role() {
    let Ok(name) = std::env::var(CARD_ROLE) else {
        return;
    };
    let _card = serve_emu(&name);
    println!("\nSERVING");
    loop {
        std::thread::park();
    }
}

fn monotonic_ms() -> f64 {
    let t = nix::time::clock_gettime(nix::time::ClockId::CLOCK_MONOTONIC).unwrap();
    t.tv_sec() as f64 * 1e3 + t.tv_nsec() as f64 / 1e6
}

/// A C program waiting on a card whose process is killed, or stopped, gets the card-gone or
/// not-responding code from the wait and every later call, never stale data; a command it gave
/// up on while the card was stopped never runs (dead_card.c).
#[test]
fn a_dead_or_stopped_card_is_reported_by_every_call_from_c() {
    use nix::sys::signal::{kill, Signal};
    use nix::unistd::Pid;
    use std::io::{BufRead, BufReader};
    let exe = compile("dead_card", Link::Shared);
    for mode in ["kill", "stop"] {
        let name = format!("cffi-dead-{mode}-{}", std::process::id());
        let mut card = Command::new(std::env::current_exe().unwrap())
            .args(["--exact", "card_role", "--nocapture", "--test-threads=1"])
            .env(CARD_ROLE, &name)
            .stdout(Stdio::piped())
            .spawn()
            .unwrap();
        let serving = BufReader::new(card.stdout.take().unwrap())
            .lines()
            .map_while(Result::ok)
            .any(|l| l.contains("SERVING"));
        assert!(serving, "the card process did not start");
        let pid = Pid::from_raw(card.id() as i32);
        let mut prog = Command::new(&exe)
            .args([&format!("emu:{name}"), mode])
            .env("LD_LIBRARY_PATH", installed().prefix.join("lib"))
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut lines = BufReader::new(prog.stdout.take().unwrap()).lines();
        let mut out = String::new();
        let mut next = |out: &mut String| {
            let l = lines.next().and_then(Result::ok).unwrap_or_default();
            out.push_str(&l);
            out.push('\n');
            l
        };
        while !next(&mut out).starts_with("READY") {
            assert!(out.len() < 10_000 && !out.ends_with("\n\n"), "{out}");
        }
        std::thread::sleep(Duration::from_millis(100)); // blocked in its wait
        let t_dead = monotonic_ms();
        kill(
            pid,
            if mode == "kill" {
                Signal::SIGKILL
            } else {
                Signal::SIGSTOP
            },
        )
        .unwrap();
        let ended = next(&mut out);
        let at: f64 = ended
            .strip_prefix("WAIT-ENDED ")
            .unwrap_or_else(|| panic!("{out}"))
            .parse()
            .unwrap();
        let latency = at - t_dead;
        if mode == "kill" {
            assert!(
                latency < 100.0,
                "the wait ended {latency:.1} ms after the kill"
            );
        } else {
            // The staleness limit (100 ms here), looked at every half limit.
            assert!((50.0..400.0).contains(&latency), "{latency:.1} ms");
            while !next(&mut out).starts_with("GAVE-UP") {
                assert!(out.len() < 10_000 && !out.ends_with("\n\n"), "{out}");
            }
            kill(pid, Signal::SIGCONT).unwrap();
        }
        while lines.next().and_then(Result::ok).is_some_and(|l| {
            out.push_str(&l);
            out.push('\n');
            true
        }) {}
        let status = prog.wait().unwrap();
        let mut err = String::new();
        let _ = std::io::Read::read_to_string(&mut prog.stderr.take().unwrap(), &mut err);
        assert!(
            status.success() && out.contains("PASS dead_card\n"),
            "{mode}: {out}\n{err}"
        );
        println!("dead_card {mode}: the C program's wait failed {latency:.1} ms after it");
        let _ = card.kill();
        let _ = card.wait();
    }
}

/// A card served as `emu:NAME` by this test process (as `card-emu --name NAME` would) to the C
/// program, another process: its second open is refused while the first holds the card.
#[test]
fn a_second_open_of_an_emu_card_is_busy() {
    let name = format!("cffi-busy-{}", std::process::id());
    let _card = serve_emu(&name);
    let uri = format!("emu:{name}");
    let out = run(&compile("busy", Link::Shared), &[&uri], &[]);
    assert!(out.contains("PASS busy\n"), "{out}");
    assert!(
        out.contains(&format!("{uri}: a second open was MC_ERR_BUSY")),
        "{out}"
    );
    assert!(out.contains("(2 axes at 10000 Hz)"), "{out}");
}

/// Three `emu:` cards served by this test process, the first and the third of one serial: the
/// C program lists them (count first, then the array), opens one by name and one by serial,
/// sees the one it holds listed busy, and gets `MC_ERR_NOT_FOUND` for a name nobody has and
/// `MC_ERR_AMBIGUOUS` for the shared serial (list.c).
#[test]
fn cards_listed_and_opened_by_name_and_serial_from_c() {
    let pid = std::process::id();
    let names = ["a", "b", "c"].map(|k| format!("cffi-list-{k}-{pid}"));
    let (sa, sb) = ((u64::from(pid) << 20) | 1, (u64::from(pid) << 20) | 2);
    let _cards: Vec<_> = names
        .iter()
        .zip([sa, sb, sa])
        .map(|(n, s)| serve_emu_serial(n, s))
        .collect();
    let args = [
        &names[0],
        &names[1],
        &names[2],
        &sa.to_string(),
        &sb.to_string(),
    ];
    let args: Vec<&str> = args.iter().map(|s| s.as_str()).collect();
    let out = run(&compile("list", Link::Shared), &args, &[]);
    assert!(out.contains("PASS list\n"), "{out}");
    let a = &names[0];
    assert!(
        out.contains(&format!(
            "emu:{a}: {a}, serial {sa}, 2 axes at 10000 Hz, alone, available\n"
        )),
        "{out}"
    );
}

/// The `MC_ERR_` names the header defines.
fn header_codes() -> BTreeSet<String> {
    let h =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("include/motioncard.h"))
            .unwrap();
    let codes: BTreeSet<String> = h
        .lines()
        .filter_map(|l| l.strip_prefix("#define "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|n| n.starts_with("MC_ERR_"))
        .map(String::from)
        .collect();
    assert!(codes.len() > 50, "{codes:?}");
    codes
}

/// The codes a C source expects from its calls: the last argument of each `EXPECT(call, CODE)`
/// (each program exits when a call returns anything else, so a program that passes returned
/// every code it expects).
fn expected_codes(src: &str) -> BTreeSet<String> {
    let mut codes = BTreeSet::new();
    for (start, _) in src.match_indices("EXPECT(") {
        let body = &src[start + "EXPECT(".len()..];
        let (mut depth, mut last_comma, mut end) = (0i32, None, None);
        for (i, ch) in body.char_indices() {
            match ch {
                '(' => depth += 1,
                ')' if depth == 0 => {
                    end = Some(i);
                    break;
                }
                ')' => depth -= 1,
                ',' if depth == 0 => last_comma = Some(i),
                _ => {}
            }
        }
        if let (Some(c), Some(e)) = (last_comma, end) {
            let code = body[c + 1..e].trim();
            if code.starts_with("MC_ERR_") {
                codes.insert(code.to_string());
            }
        }
    }
    codes
}

#[test]
fn errors_c_lists_every_code_of_the_header() {
    let src = std::fs::read_to_string(examples_dir().join("errors.c")).unwrap();
    let start = src.find("ALL_CODES[] = {").expect("ALL_CODES in errors.c");
    let end = start + src[start..].find("};").unwrap();
    let listed: BTreeSet<String> = src[start..end]
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|w| w.starts_with("MC_ERR_"))
        .map(String::from)
        .collect();
    assert_eq!(listed, header_codes());
}

/// Codes no C program can provoke with an emulated card (see errors.c): the Rust tests cover
/// them on the SDK side.
const NOT_PROVOKABLE_FROM_C: &[&str] = &[
    "MC_ERR_VERSION_MISMATCH",
    "MC_ERR_PROTOCOL",
    "MC_ERR_RING_FULL",
    "MC_ERR_NURBS_SEQUENCE",
    "MC_ERR_HARD_LIMIT",
    "MC_ERR_PLAN_CHECK",
    "MC_ERR_EXPIRED",
    "MC_ERR_PERMISSION_DENIED",
    "MC_ERR_PATH_ID",
    "MC_ERR_CAM_SEQUENCE",
    "MC_ERR_COMP_SEQUENCE",
    "MC_ERR_CONFIG_KIND",
    // Layout 1.12: a lost master needs a killed card-emu process (card-emu/tests/sync_bus.rs);
    // the command of a refused timing is never waited for (the timing's refusal is the error).
    "MC_ERR_SYNC_LOST",
    "MC_ERR_TIMED_REFUSED",
    // A move refused while a sweep runs: `mc_axis_freq_response` returns once the sweep has
    // ended (tests/freq.rs provokes it from Rust).
    "MC_ERR_FREQ_BUSY",
];

#[test]
fn every_code_is_expected_by_some_c_program() {
    let mut expected = BTreeSet::new();
    for entry in std::fs::read_dir(examples_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "c") {
            expected.extend(expected_codes(&std::fs::read_to_string(&path).unwrap()));
        }
    }
    let not_provokable: BTreeSet<String> = NOT_PROVOKABLE_FROM_C
        .iter()
        .map(|s| s.to_string())
        .collect();
    let both: Vec<_> = expected.intersection(&not_provokable).collect();
    assert!(both.is_empty(), "provoked after all: {both:?}");
    let missing: Vec<_> = header_codes()
        .into_iter()
        .filter(|c| !expected.contains(c) && !not_provokable.contains(c))
        .collect();
    assert!(missing.is_empty(), "no C program expects {missing:?}");
}

/// Run a program under valgrind. Definite and indirect leaks are errors; "possibly lost" and
/// "still reachable" are not (the card table and Rust's thread-locals live until exit). No
/// suppressions are needed.
fn run_under_valgrind(name: &str) -> String {
    run(
        &compile(name, Link::Shared),
        &[],
        &[
            "valgrind",
            "--error-exitcode=1",
            "--leak-check=full",
            "--errors-for-leak-kinds=definite,indirect",
            "--show-leak-kinds=definite,indirect",
            "-q",
        ],
    )
}

#[test]
fn misuse_program_is_clean_under_valgrind() {
    let out = run_under_valgrind("errors");
    assert!(out.contains("PASS errors\n"), "{out}");
}

#[test]
fn groups_program_is_clean_under_valgrind() {
    let out = run_under_valgrind("groups");
    assert!(out.contains("PASS groups\n"), "{out}");
}

#[test]
fn machine_program_jogs_aborts_buffers_and_overrides() {
    let out = run(&compile("machine", Link::Shared), &[], &[]);
    assert!(out.contains("PASS machine"), "{out}");
    assert!(out.contains("abort: retargeted to -10000"), "{out}");
    assert!(out.contains("override 0 % held, 200 %"), "{out}");
}

/// The path from C: a blended square with outputs, a NURBS segment, the refusals.
#[test]
fn path_program_streams_a_blended_square_with_outputs_and_a_curve() {
    let out = run(&compile("path", Link::Shared), &[], &[]);
    assert!(out.contains("PASS path"), "{out}");
    assert!(
        out.contains("path: square with blends ended at (5000, 5000)"),
        "{out}"
    );
    assert!(out.contains("path: a NURBS segment and a line"), "{out}");
    assert!(
        out.contains("path: a half turn about (1, 1, 1) on its circle"),
        "{out}"
    );
}

/// As [`path_program_streams_a_blended_square_with_outputs_and_a_curve`], under valgrind.
#[test]
fn path_program_is_clean_under_valgrind() {
    let out = run_under_valgrind("path");
    assert!(out.contains("PASS path"), "{out}");
}

/// Layout 1.7 (sync): electronic gearing, exact after 10^9 master counts.
#[test]
fn gearing_from_c() {
    let out = run(&compile("gearing", Link::Shared), &[], &[]);
    assert!(out.contains("PASS gearing\n"), "{out}");
    assert!(out.contains(", error 0 counts"), "{out}");
    assert!(out.contains("in gear at 1/2: 10000.0 counts/s"), "{out}");
}

/// Layout 1.7 (sync): PT/PVT streaming through the card's buffer, refilled on low water.
#[test]
fn pvt_from_c() {
    let out = run(&compile("pvt", Link::Shared), &[], &[]);
    assert!(out.contains("PASS pvt\n"), "{out}");
    assert!(out.contains("PVT: 2000 points"), "{out}");
}

/// Layout 1.7 (sync): camming, a table switch at the end of a cycle.
#[test]
fn cam_from_c() {
    let out = run(&compile("cam", Link::Shared), &[], &[]);
    assert!(out.contains("PASS cam\n"), "{out}");
}

#[test]
fn cam_program_is_clean_under_valgrind() {
    let out = run_under_valgrind("cam");
    assert!(out.contains("PASS cam\n"), "{out}");
}

#[test]
fn pvt_program_is_clean_under_valgrind() {
    let out = run_under_valgrind("pvt");
    assert!(out.contains("PASS pvt\n"), "{out}");
}

#[test]
fn gearing_program_is_clean_under_valgrind() {
    let out = run_under_valgrind("gearing");
    assert!(out.contains("PASS gearing\n"), "{out}");
}

#[test]
fn homing_program_is_clean_under_valgrind() {
    let out = run_under_valgrind("homing");
    assert!(out.contains("PASS homing\n"), "{out}");
}

#[test]
fn config_program_is_clean_under_valgrind() {
    let out = run_under_valgrind("config");
    assert!(out.contains("PASS config\n"), "{out}");
}

#[test]
fn machine_program_is_clean_under_valgrind() {
    let out = run_under_valgrind("machine");
    assert!(out.contains("PASS machine"), "{out}");
}

#[test]
fn safety_program_is_clean_under_valgrind() {
    let out = run_under_valgrind("safety");
    assert!(out.contains("PASS safety\n"), "{out}");
}

#[test]
fn a_statically_linked_program_runs_without_the_shared_library() {
    let exe = compile("move", Link::Static);
    // No LD_LIBRARY_PATH: the program must not need libmotioncard.so.
    let out = run_to_end({
        let mut c = Command::new(&exe);
        c.arg("stepped").env_remove("LD_LIBRARY_PATH");
        c
    });
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && stdout.contains("PASS move\n"),
        "{:?}\n{stdout}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
}

/// `MOTIONCARD_TRACE` records what a C program asks of the card (no code change in the
/// program), and the trace replays on an emulated card without a difference.
#[test]
fn a_c_program_is_traced_by_the_environment_and_replays() {
    let exe = compile("move", Link::Shared);
    let trace = std::env::temp_dir().join(format!("mc-c-trace-{}", std::process::id()));
    let mut cmd = Command::new(&exe);
    cmd.arg("stepped")
        .env("LD_LIBRARY_PATH", installed().prefix.join("lib"))
        .env(motioncard_sdk::TRACE_ENV, &trace);
    let out = run_to_end(cmd);
    assert!(out.status.success(), "{out:?}");
    let r = motioncard_sdk::replay(&trace).unwrap();
    assert_eq!(r.difference, None, "{r:?}");
    assert!(r.commands >= 5 && r.events >= 5, "{r:?}");
    let _ = std::fs::remove_file(&trace);
}

/// Layout 1.8: the scope, a 16-channel capture at 20 kHz read as the card runs, every refusal.
#[test]
fn scope_from_c() {
    let out = run(&compile("scope", Link::Shared), &[], &[]);
    assert!(out.contains("PASS scope\n"), "{out}");
    assert!(
        out.contains("captured 6500 samples x 16 channels, 0 lost"),
        "{out}"
    );
    // Issue 39: a trigger 4 samples after the arm gives 4 pre-trigger samples of the 50
    // asked, and mc_scope_info.pre_captured says so.
    assert!(
        out.contains("pre-trigger: 4 samples of the 50 asked"),
        "{out}"
    );
}

#[test]
fn scope_program_is_clean_under_valgrind() {
    let out = run_under_valgrind("scope");
    assert!(out.contains("PASS scope\n"), "{out}");
}

#[test]
fn a_gcode_program_with_hooks_a_pause_a_loop_and_its_refusals() {
    let out = run(&compile("gcode", Link::Shared), &[], &[]);
    assert!(out.contains("PASS gcode ("), "{out}");
    assert!(out.contains("G-code part: paused at line 12"), "{out}");
    assert!(out.contains("G-code report: "), "{out}");
    assert!(out.contains("ended at X42 Z-3"), "{out}");
    // The spindle on a card axis: a rigid tap back at its start, the spindle forward again.
    assert!(
        out.contains("G-code spindle: a tap to Z-3 and back to Z2, the spindle at 10.0 rev/s"),
        "{out}"
    );
}

/// Issue 39: one unit rule for every event. On an axis of 1000 counts/mm, the compare, probe
/// and motion-done events report millimetres (compare within a count of 1 mm).
#[test]
fn every_event_position_is_in_user_units_from_c() {
    let out = run(&compile("units", Link::Shared), &[], &[]);
    assert!(out.contains("PASS units\n"), "{out}");
}

/// Issue 39: debugging a C program on the emulated card. With `MOTIONCARD_SIM_WATCHDOG_MS`
/// the real-time `sim` card boots with that watchdog timeout and keeps it as the least a
/// program sets, still armed (2 s: a heartbeat stopped for 2.5 s trips it); under valgrind
/// with 10 s, the first `mc_enable` works (with the default 100 ms it failed with
/// `MC_ERR_WATCHDOG_TRIPPED`, the heartbeat thread held up for seconds).
#[test]
fn the_sim_card_has_a_debugging_watchdog_timeout() {
    let exe = compile("debug", Link::Shared);
    let out = run_env(
        &exe,
        &["2000"],
        &[],
        &[("MOTIONCARD_SIM_WATCHDOG_MS", "2000")],
    );
    assert!(out.contains("PASS debug\n"), "{out}");
    assert!(
        out.contains("the watchdog tripped after 2500 ms without a heartbeat"),
        "{out}"
    );
    let out = run_env(
        &exe,
        &["10000"],
        &[
            "valgrind",
            "--error-exitcode=1",
            "--leak-check=full",
            "--errors-for-leak-kinds=definite,indirect",
            "-q",
        ],
        &[("MOTIONCARD_SIM_WATCHDOG_MS", "10000")],
    );
    assert!(out.contains("PASS debug\n"), "{out}");
    assert!(out.contains("watchdog timeout 10000 ms"), "{out}");
}

/// The C names of the header's comments: `MC_` and upper-case letters, digits, `_`, or `mc_`
/// and lower-case ones (`MC_` and a CamelCase word is PLCopen's, not C's); `(name, pattern)`,
/// a pattern being `NAME*` or a prefix ending in `_`. File names (`mc_dpram.h`) are none.
fn names_cited(comments: &str) -> BTreeSet<(String, bool)> {
    let b = comments.as_bytes();
    let id = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    let mut out = BTreeSet::new();
    let mut i = 0;
    while i < b.len() {
        if !id(b[i]) || (i > 0 && id(b[i - 1])) {
            i += 1;
            continue;
        }
        let mut j = i;
        while j < b.len() && id(b[j]) {
            j += 1;
        }
        let w = &comments[i..j];
        let upper = w.starts_with("MC_")
            && w[3..]
                .bytes()
                .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == b'_');
        let lower = w.starts_with("mc_")
            && w[3..]
                .bytes()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == b'_');
        if (upper || lower) && !comments[j..].starts_with(".h") {
            out.insert((w.to_string(), b.get(j) == Some(&b'*') || w.ends_with('_')));
        }
        i = j;
    }
    out
}

/// Issue 39: every name a comment of the header cites exists in the header. Each `MC_` or
/// `mc_` name of the comments (and every name of a pattern `MC_STATE_*` or prefix `MC_ERR_`)
/// gets a use in a C program that includes the installed header: a constant is evaluated, a
/// function-like macro called, a type's size taken, a function's address taken; gcc compiles
/// it with `-std=c11 -pedantic-errors -Werror`. A name the header does not have fails by name
/// before gcc runs. The comments name no SDK (Rust) item either: no `Card::`, no `crate::`.
#[test]
fn every_name_the_header_cites_compiles_in_c() {
    let inst = installed();
    let header = std::fs::read_to_string(inst.prefix.join("include/motioncard.h")).unwrap();
    // Comments and code apart.
    let (mut comments, mut code) = (String::new(), String::new());
    let mut rest = header.as_str();
    while let Some(s) = rest.find("/*") {
        code.push_str(&rest[..s]);
        code.push(' ');
        let e = rest[s..].find("*/").expect("a comment ends") + s + 2;
        comments.push_str(&rest[s..e]);
        comments.push('\n');
        rest = &rest[e..];
    }
    code.push_str(rest);
    assert!(
        !comments.contains("Card::") && !comments.contains("crate::"),
        "the header's comments name the Rust SDK"
    );
    // What the code declares, by kind.
    let (mut objects, mut macros) = (BTreeSet::new(), HashMap::new());
    for line in code.lines() {
        if let Some(d) = line.trim().strip_prefix("#define ") {
            let name: String = d
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if let Some(params) = d[name.len()..].strip_prefix('(') {
                let params = &params[..params.find(')').unwrap()];
                macros.insert(name, params.split(',').count());
            } else {
                objects.insert(name);
            }
        }
    }
    let words = |s: &str| -> Vec<String> {
        s.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .filter(|w| !w.is_empty())
            .map(String::from)
            .collect()
    };
    let (mut types, mut tags, mut functions) = (BTreeSet::new(), BTreeSet::new(), BTreeSet::new());
    // Statements at brace depth 0 (the code without the preprocessor lines).
    let body: String = code
        .lines()
        .filter(|l| !l.trim_start().starts_with('#') && !l.contains("extern \"C\""))
        .collect::<Vec<_>>()
        .join("\n");
    let (mut depth, mut stmt) = (0i32, String::new());
    for ch in body.chars() {
        match ch {
            '{' => depth += 1,
            '}' => depth -= 1,
            _ => {}
        }
        stmt.push(ch);
        if ch == ';' && depth == 0 {
            let s = std::mem::take(&mut stmt);
            let w = words(&s);
            for (i, t) in w.iter().enumerate() {
                if t == "struct" {
                    if let Some(tag) = w.get(i + 1) {
                        tags.insert(tag.clone());
                    }
                }
            }
            if w.first().is_some_and(|f| f == "typedef") {
                let name = match s.find("(*") {
                    Some(at) => words(&s[at..]).into_iter().next(),
                    None => w.last().cloned(),
                };
                types.extend(name);
            } else if let Some(open) = s.find('(') {
                functions.extend(words(&s[..open]).pop());
            }
        }
    }
    let use_of = |name: &str| -> Option<String> {
        if objects.contains(name) {
            Some(format!("    (void)({name});\n"))
        } else if let Some(n) = macros.get(name) {
            let args = vec!["1"; *n].join(", ");
            Some(format!("    (void)({name}({args}));\n"))
        } else if types.contains(name) {
            Some(format!("    (void)sizeof({name});\n"))
        } else if tags.contains(name) {
            Some(format!("    (void)sizeof(struct {name});\n"))
        } else if functions.contains(name) {
            Some(format!("    (void)&{name};\n"))
        } else {
            None
        }
    };
    let all: BTreeSet<&String> = objects
        .iter()
        .chain(macros.keys())
        .chain(&types)
        .chain(&tags)
        .chain(&functions)
        .collect();
    let cited = names_cited(&comments);
    assert!(cited.len() > 300, "{} names cited", cited.len());
    let (mut src, mut missing, mut uses) = (String::new(), Vec::new(), 0);
    for (name, pattern) in &cited {
        let names: Vec<&String> = if *pattern {
            all.iter()
                .copied()
                .filter(|n| n.starts_with(name.as_str()) && *n != name)
                .collect()
        } else {
            all.iter().copied().filter(|n| *n == name).collect()
        };
        if names.is_empty() {
            missing.push(format!("{name}{}", if *pattern { "*" } else { "" }));
        }
        for n in names {
            src.push_str(&use_of(n).unwrap());
            uses += 1;
        }
    }
    assert!(
        missing.is_empty(),
        "the header's comments cite names it does not have: {missing:?}"
    );
    let file = inst.work.join("cited.c");
    std::fs::write(
        &file,
        format!("#include <motioncard.h>\n\nint main(void) {{\n{src}    return 0;\n}}\n"),
    )
    .unwrap();
    let out = Command::new("gcc")
        .args([
            "-std=c11",
            "-pedantic-errors",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-fsyntax-only",
        ])
        .arg(format!("-I{}", inst.prefix.join("include").display()))
        .arg(&file)
        .output()
        .expect("gcc is needed");
    assert!(
        out.status.success(),
        "a use of a cited name does not compile:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    println!(
        "the header's comments cite {} names and patterns; {uses} uses of them compile",
        cited.len()
    );
}

/// Issue 39: a path streamed from a thread of the library, watched and joined from C: 4500
/// lines (more than the card's buffer) all accepted, the path ending on the last; a slow one
/// cancelled while it waits for room (`MC_ERR_CANCELLED`, what the card took reported); an
/// item the library refuses gives no handle.
#[test]
fn a_path_streams_in_the_background_from_c() {
    let out = run(&compile("path_stream", Link::Shared), &["sim"], &[]);
    assert!(out.contains("PASS path_stream\n"), "{out}");
    assert!(
        out.contains("4500 lines streamed from the library's thread"),
        "{out}"
    );
}
