//! `mcctl serve`, the tuning page, from the outside: an `emu:` card served by this test, `mcctl
//! serve` against it, and the page driven in Debian's headless Chromium by
//! `tests/browser/drive.mjs` (playwright-core): the live plots, a step test (the figures and the
//! plotted data against the samples the server answered and against the card), a gain the card
//! accepts and one it refuses.
//!
//! Needs `chromium` (`apt-get install -y chromium`) and `npm ci --prefix tests/browser`
//! (`.ci/run` installs both and sets `MOTIONCARD_BROWSER_TEST=required`, under which a missing
//! tool fails the test, saying what to install; without that variable the browser test says
//! what is missing and does not run, so the suite passes with the Rust toolchain alone). With
//! `TUNING_SCREENSHOT=path.png` it saves a screenshot of the page after the step test.
use card_emu::emu::server::Server;
use card_emu::{EmuOptions, Emulator, Runner};
use motioncard::tuning::{figures, Band, Response};
use serde_json::Value;
use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

const MCCTL: &str = env!("CARGO_BIN_EXE_mcctl");

/// Set by `.ci/run`: the browser test must run (a missing tool fails it).
const REQUIRED: &str = "MOTIONCARD_BROWSER_TEST";

/// The browser and the driver's packages. What is missing fails the test under `.ci/run`
/// (`MOTIONCARD_BROWSER_TEST=required`, with what to install); elsewhere (the README's test
/// command on a machine with only the Rust toolchain) the test says so on stderr and does not
/// run (`None`).
fn browser_tools() -> Option<(PathBuf, PathBuf)> {
    let chromium = std::env::var_os("CHROMIUM")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/usr/bin/chromium"));
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/browser");
    let node = Command::new("node").arg("--version").output();
    let missing = if !chromium.exists() {
        format!(
            "{} not found: the tuning page's test drives Debian's Chromium; install it with \
             `apt-get install -y chromium` (or set CHROMIUM to a Chromium binary)",
            chromium.display()
        )
    } else if !dir
        .join("node_modules/playwright-core/package.json")
        .exists()
    {
        "tests/browser/node_modules is missing: run `npm ci --prefix tests/browser` (node and \
         npm from Debian's nodejs and npm packages)"
            .to_string()
    } else if !node.as_ref().is_ok_and(|o| o.status.success()) {
        format!("node not found: install Node.js (Debian's nodejs package): {node:?}")
    } else {
        return Some((chromium, dir));
    };
    assert!(
        std::env::var(REQUIRED).as_deref() != Ok("required"),
        "{missing}"
    );
    // Straight to the process's stderr, past the test harness's capture: the user sees it.
    let _ = writeln!(
        std::io::stderr(),
        "the tuning page's browser test did not run ({REQUIRED} is not `required`): {missing}"
    );
    None
}

/// A child process killed if the test ends early.
struct Proc(Option<Child>);

impl Proc {
    fn wait_for(&mut self, limit: Duration) -> Option<ExitStatus> {
        let child = self.0.as_mut()?;
        let end = Instant::now() + limit;
        while Instant::now() < end {
            if let Ok(Some(st)) = child.try_wait() {
                return Some(st);
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        None
    }
}

impl Drop for Proc {
    fn drop(&mut self) {
        if let Some(mut c) = self.0.take() {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

/// `mcctl serve --listen 127.0.0.1:0` against `uri`: the process and the URL it printed.
fn serve(uri: &str, axis: usize) -> (Proc, String) {
    let mut child = Command::new(MCCTL)
        .args(["--card", uri, "serve", "--listen", "127.0.0.1:0"])
        .args(["--axis", &axis.to_string()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start mcctl serve");
    let out = child.stdout.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut line = String::new();
        let _ = BufReader::new(out).read_line(&mut line);
        let _ = tx.send(line);
    });
    let mut proc = Proc(Some(child));
    let line = rx.recv_timeout(Duration::from_secs(15)).unwrap_or_default();
    let url = line
        .trim()
        .strip_prefix("listening on ")
        .map(str::to_string)
        .unwrap_or_else(|| {
            let mut err = String::new();
            if let Some(mut c) = proc.0.take() {
                let _ = c.kill();
                let _ = c.stderr.take().map(|mut e| e.read_to_string(&mut err));
            }
            panic!("mcctl serve printed {line:?} instead of its address; stderr: {err}")
        });
    assert!(
        url.starts_with("http://127.0.0.1:") && url.ends_with('/'),
        "{url}"
    );
    (proc, url)
}

/// A GET over plain HTTP/1.1: the status code and the body.
fn http_get(url: &str, path: &str) -> (u16, String) {
    let addr = url
        .trim_start_matches("http://")
        .trim_end_matches('/')
        .to_string();
    let mut s = std::net::TcpStream::connect(&addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    write!(
        s,
        "GET {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut text = String::new();
    s.read_to_string(&mut text).unwrap();
    let (head, body) = text.split_once("\r\n\r\n").expect("an HTTP answer");
    let code = head
        .split_whitespace()
        .nth(1)
        .and_then(|c| c.parse().ok())
        .unwrap();
    (code, body.to_string())
}

/// Run the page's driver; its JSON report.
fn drive(dir: &Path, chromium: &Path, url: &str, opts: &Value) -> Value {
    let child = Command::new("node")
        .arg(dir.join("drive.mjs"))
        .arg(url)
        .arg(opts.to_string())
        .env("CHROMIUM", chromium)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start node");
    let mut child = child;
    // Drained as it writes: its report is larger than a pipe holds.
    let reader = |mut r: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut s = String::new();
            let _ = r.read_to_string(&mut s);
            s
        })
    };
    let out = reader(Box::new(child.stdout.take().unwrap()));
    let err = reader(Box::new(child.stderr.take().unwrap()));
    let mut p = Proc(Some(child));
    let st = p.wait_for(Duration::from_secs(60));
    drop(p); // killed if it overran
    let (out, err) = (out.join().unwrap(), err.join().unwrap());
    assert!(
        st.is_some_and(|s| s.success()),
        "the page's driver failed ({st:?}): {err}"
    );
    serde_json::from_str(out.trim()).unwrap_or_else(|e| panic!("driver output {e}: {out}"))
}

/// The same JSON, numbers compared as numbers (the page's copy went through JavaScript: 400.0
/// comes back as 400); Err: where they differ.
fn same_json(a: &Value, b: &Value, at: &str) -> Result<(), String> {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            close(x, y).then_some(()).ok_or(format!("{at}: {x} vs {y}"))
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => x
            .iter()
            .zip(y)
            .enumerate()
            .try_for_each(|(i, (x, y))| same_json(x, y, &format!("{at}[{i}]"))),
        (Value::Object(x), Value::Object(y)) if x.len() == y.len() => {
            x.iter().try_for_each(|(k, v)| {
                same_json(v, y.get(k).unwrap_or(&Value::Null), &format!("{at}.{k}"))
            })
        }
        (x, y) if x == y => Ok(()),
        _ => Err(format!("{at}: different kinds or lengths")),
    }
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("not an array: {v}"))
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * a.abs().max(b.abs()).max(1e-300)
}

/// The first number in a text ("18.50 ms" → 18.5).
fn first_number(text: &str) -> f64 {
    let start = text
        .find(|c: char| c.is_ascii_digit() || c == '-')
        .unwrap_or_else(|| panic!("no number in {text:?}"));
    let s: String = text[start..]
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.' || *c == '-')
        .collect();
    s.parse().unwrap_or_else(|e| panic!("{text:?}: {e}"))
}

/// A figure shown on the page: its exact value (`data-value`) is the server's, and its text
/// is that value rounded to `decimals` (after scaling by `scale`: s to ms).
fn check_shown(shown: &Value, id: &str, want: f64, scale: f64, decimals: i32) {
    let el = &shown[id];
    let value: f64 = el["value"].as_str().unwrap().parse().unwrap();
    assert!(close(value, want), "{id}: data-value {value} vs {want}");
    let text = el["text"].as_str().unwrap();
    let half = 0.5 * 10f64.powi(-decimals) + 1e-9;
    assert!(
        (first_number(text) - want * scale).abs() <= half,
        "{id}: {text:?} is not {} to {decimals} decimals",
        want * scale
    );
}

#[test]
fn the_tuning_page_runs_a_step_test_and_applies_gains_in_chromium() {
    let Some((chromium, dir)) = browser_tools() else {
        return;
    };
    let name = format!("test-serve-{}", std::process::id());
    let emu = Emulator::create(&name, &EmuOptions::new(2, 10_000)).unwrap();
    let _server = Server::start(&name, emu.lessor()).unwrap();
    let runner = Runner::spawn(emu, card_emu::Clock::RealTime, false).unwrap();
    let uri = format!("emu:{name}");
    let axis = 1;
    let (mut mcctl, url) = serve(&uri, axis);

    let (step, good_kp, bad_kp) = (400.0, 70.0, -5.0);
    let mut opts = serde_json::json!({ "step": step, "kp": good_kp, "bad_kp": bad_kp });
    if let Some(p) = std::env::var_os("TUNING_SCREENSHOT") {
        opts["screenshot"] = p.to_string_lossy().into();
    }
    let j = drive(&dir, &chromium, &url, &opts);

    // The page loaded everything from the server, without an error in its scripts; the only
    // console error is the refused gain's 422.
    assert_eq!(
        j["foreign_requests"],
        serde_json::json!([]),
        "{}",
        j["foreign_requests"]
    );
    assert_eq!(
        j["page_errors"],
        serde_json::json!([]),
        "{}",
        j["page_errors"]
    );
    for e in j["console_errors"].as_array().unwrap() {
        assert!(e.as_str().unwrap().contains("422"), "{e}");
    }

    // The server's answer for the step test, and the same answer asked for again.
    let api = &j["api"];
    let (code, kept) = http_get(&url, &format!("/api/tests/{}", api["id"]));
    assert_eq!(code, 200, "{kept}");
    let kept: Value = serde_json::from_str(&kept).unwrap();
    if let Err(at) = same_json(&kept, api, "") {
        panic!("GET /api/tests/ID is not the page's test: they differ at {at}");
    }
    let (code, body) = http_get(&url, "/api/tests/99");
    assert_eq!(code, 404, "{body}");
    assert_eq!(api["kind"], "step");
    assert_eq!(api["axis"], axis);
    assert_eq!(api["distance"], step);
    assert_eq!(api["in_position"], true, "{}", api["outcome"]);
    let s = &api["samples"];
    let (t, cmd, act, ferr, dac) = (
        floats(&s["t"]),
        floats(&s["cmd"]),
        floats(&s["act"]),
        floats(&s["ferr"]),
        floats(&s["dac"]),
    );
    let ticks: Vec<u64> = s["tick"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap())
        .collect();
    // One sample per servo tick, times from the command's start.
    assert!(
        ticks.windows(2).all(|w| w[1] == w[0] + 1),
        "a gap in the ticks"
    );
    let start_tick = api["start_tick"].as_u64().unwrap();
    for (tk, ti) in ticks.iter().zip(&t) {
        assert!(close(*ti, (*tk as f64 - start_tick as f64) / 10_000.0));
    }

    // The figures, computed here from the samples the server answered.
    let mine = figures(
        &Response {
            t: &t,
            cmd: &cmd,
            act: &act,
            ferr: &ferr,
        },
        Band::default(),
    )
    .unwrap();
    let f = &api["figures"];
    let num = |k: &str| f[k].as_f64().unwrap_or_else(|| panic!("{k}: {}", f[k]));
    assert!(close(mine.step, num("step")));
    assert!(close(mine.rise_time.unwrap(), num("rise_time")));
    assert!(close(mine.overshoot_pct, num("overshoot_pct")));
    assert!(close(mine.settling_time.unwrap(), num("settling_time")));
    assert!(close(
        mine.peak_following_error,
        num("peak_following_error")
    ));
    assert!(close(mine.band, num("band")));
    assert_eq!(mine.start_index as u64, f["start_index"].as_u64().unwrap());
    // ... and checked against the samples themselves: the whole step is following error on
    // the command's first tick, the peak is the largest |ferr|, the step reached its target.
    let start = mine.start_index;
    assert!(start >= 100, "pre-trigger samples: {start}");
    assert_eq!(cmd[start - 1], cmd[0]);
    assert_eq!(cmd[start], cmd[0] + step, "the command jumps in one tick");
    assert!(cmd[start..].iter().all(|&c| c == cmd[0] + step));
    let peak = ferr.iter().fold(0.0_f64, |m, e| m.max(e.abs()));
    assert_eq!(mine.peak_following_error, peak);
    assert!(peak >= 0.95 * step, "{peak}");
    assert!((act[act.len() - 1] - (cmd[0] + step)).abs() <= 1.0);
    assert!(dac.iter().any(|v| v.abs() > 1.0), "the DAC drove the step");
    let (rise, settle) = (mine.rise_time.unwrap(), mine.settling_time.unwrap());
    assert!(rise > 1e-3 && rise < settle && settle < 0.2, "{mine:?}");

    // What the page shows: the same figures, to its display rounding.
    let shown = &j["displayed"];
    check_shown(shown, "fig-step", mine.step, 1.0, 0);
    check_shown(shown, "fig-rise", rise, 1e3, 2);
    check_shown(shown, "fig-overshoot", mine.overshoot_pct, 1.0, 2);
    check_shown(shown, "fig-settling", settle, 1e3, 2);
    check_shown(shown, "fig-peak-ferr", peak, 1.0, 2);
    check_shown(shown, "fig-band", mine.band, 1.0, 2);
    check_shown(shown, "fig-command", mine.command_end_time, 1e3, 2);
    assert_eq!(
        mine.command_end_time, 0.0,
        "a step reaches its target on its first tick"
    );
    assert_eq!(shown["fig-kind"]["value"], "step");
    assert_eq!(shown["fig-outcome"]["value"], "true");
    // What the page plots: exactly the samples (the charts' own arrays), and the band.
    let p = &j["plotted"];
    assert_eq!(p["id"], api["id"]);
    for (k, want) in [
        ("t", &t),
        ("cmd", &cmd),
        ("act", &act),
        ("ferr", &ferr),
        ("dac", &dac),
    ] {
        let got = floats(&p[k]);
        assert_eq!(got.len(), want.len(), "{k}");
        assert!(
            got.iter().zip(want.iter()).all(|(a, b)| close(*a, *b)),
            "the plotted {k} is not the samples"
        );
    }
    let target = cmd[0] + step;
    assert!(floats(&p["band_hi"])
        .iter()
        .all(|&v| close(v, target + mine.band)));
    assert!(floats(&p["band_lo"])
        .iter()
        .all(|&v| close(v, target - mine.band)));

    // The live plots ran before the test and run again after it, with newer samples.
    let (before, after) = (&j["live_before"], &j["live_after"]);
    assert_eq!(before["state"], "live");
    assert_eq!(after["state"], "live");
    assert!(before["points"].as_u64().unwrap() >= 20, "{before}");
    assert!(
        after["last_tick"].as_u64().unwrap() > *ticks.last().unwrap(),
        "{after}"
    );
    // The live stream, a capture of its own, shows the axis where the step put it.
    assert_eq!(after["cmd_last"].as_f64(), Some(target), "{after}");
    assert!(
        (after["act_last"].as_f64().unwrap() - target).abs() <= 1.0,
        "{after}"
    );

    // Gains: the accepted one is held; the refused one shows the card's refusal and changes
    // nothing.
    let g0 = &j["gains_before"];
    assert_eq!(g0["axis"], axis);
    assert_eq!(g0["law"], "ffpiv");
    assert_eq!(g0["source"], "read back from the card");
    let good = &j["good"];
    assert_eq!(good["status"], "ok", "{}", good["message"]);
    assert_eq!(good["held_kp"], "70");
    assert_eq!(good["server"]["ffpiv"]["kp"].as_f64(), Some(good_kp));
    // The other gains stay as they were.
    for k in ["ki", "kv", "kvff", "kaff", "vel_filter_hz"] {
        assert_eq!(good["server"]["ffpiv"][k], g0["ffpiv"][k], "{k}");
    }
    let bad = &j["bad"];
    assert_eq!(bad["status"], "error");
    let msg = bad["message"].as_str().unwrap();
    assert!(
        msg.contains("The card refused") && msg.contains("BadConfig"),
        "{msg}"
    );
    assert_eq!(bad["typed_kp"], "-5", "the form keeps what was typed");
    assert_eq!(bad["held_kp"], "70", "{msg}");
    if let Err(at) = same_json(&bad["server"], &good["server"], "") {
        panic!("the refused gain changed what the server holds: {at}");
    }

    // A step beyond the following-error limit (MIN_FERROR, 1000 counts): the page shows the
    // card's trip; its reset takes the axis out of ErrorStop (to Disabled: the trip removed
    // the drive's power), and the next step test powers it on and runs.
    let trip = j["trip_message"].as_str().unwrap();
    assert!(
        trip.contains("did not finish") && trip.contains("ErrorStop (FollowingError)"),
        "{trip}"
    );
    let (reset, again) = (&j["reset"], &j["again"]);
    assert_eq!(reset["status"], "ok", "{reset}");
    assert!(
        reset["message"].as_str().unwrap().ends_with("Disabled"),
        "{reset}"
    );
    assert_eq!(again["status"], "ok", "{again}");
    assert!(
        again["message"].as_str().unwrap().ends_with("in position"),
        "{again}"
    );

    // Stop the server as a person would (SIGTERM): a clean exit.
    let pid = mcctl.0.as_ref().unwrap().id().to_string();
    let killed = Command::new("kill").args(["-TERM", &pid]).status().unwrap();
    assert!(killed.success());
    let st = mcctl.wait_for(Duration::from_secs(10));
    assert!(st.is_some_and(|s| s.success()), "mcctl serve: {st:?}");

    // The card itself: the axis at rest after the last step, running the gain the page
    // applied (and nothing of the refused one).
    let emu = runner.stop().expect("the emulator back");
    let a = emu.firmware().axis(axis).unwrap();
    assert_eq!(a.state, motioncard::AxisState::Standstill);
    assert_eq!(a.config.ffpiv.kp, good_kp);
    assert_eq!(a.config.ffpiv.ki, g0["ffpiv"]["ki"].as_f64().unwrap());
}

/// Bad arguments are exit status 2; an axis the card has not, or a port in use, exit 1 with
/// the reason.
#[test]
fn serve_refuses_bad_arguments_axes_and_busy_ports() {
    let run = |args: &[&str]| {
        let out = Command::new(MCCTL).args(args).output().unwrap();
        (
            out.status.code().unwrap_or(-1),
            String::from_utf8_lossy(&out.stderr).to_string(),
        )
    };
    let (code, err) = run(&["serve", "--listen", "localhost-ish"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--listen"), "{err}");
    let (code, err) = run(&["serve", "--axis", "-1"]);
    assert_eq!(code, 2, "{err}");
    let (code, err) = run(&["serve", "--axis", "99", "--listen", "127.0.0.1:0"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("axis 99"), "{err}");
    let busy = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = busy.local_addr().unwrap().to_string();
    let (code, err) = run(&["serve", "--listen", &addr]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains(&format!("listen on {addr}")), "{err}");
}
