//! `mcctl serve`, the tuning page, from the outside: an `emu:` card served by this test, `mcctl
//! serve` against it, and the page driven in Debian's headless Chromium by
//! `tests/browser/drive.mjs` (playwright-core): the live plots, a step test (the figures and the
//! plotted data against the samples the server answered and against the card), a gain the card
//! accepts and one it refuses, the page without its token and under a rebinding name; the
//! PID+FF form and the servo-filter list by `tests/browser/servo.mjs`, the frequency sweep and
//! its Bode plot by `tests/browser/bode.mjs`. And the
//! guard (`src/serve/guard.rs`) over plain HTTP: every route of `mcctl::serve::ROUTES`
//! sent bad Hosts, foreign Origins, missing and wrong tokens, each refused (403) with the card
//! read after (the gains, the axis's state and position as before); `--listen` beyond
//! loopback and `--token`.
//!
//! The browser test needs `chromium` (`apt-get install -y chromium`) and `npm ci --prefix tests/browser`
//! (`.ci/run` installs both and sets `MOTIONCARD_BROWSER_TEST=required`, under which a missing
//! tool fails the test, saying what to install; without that variable the browser test says
//! what is missing and does not run, so the suite passes with the Rust toolchain alone). With
//! `TUNING_SCREENSHOT=path.png` it saves a screenshot of the page after the step test, with
//! `BODE_SCREENSHOT=path.png` one of the frequency-response panel after its sweep.
use card_emu::emu::server::Server;
use card_emu::{EmuOptions, Emulator, Runner};
use mcctl::tuning::{figures, Band, Response};
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

/// A running `mcctl serve`: what it printed on stdout, and its stderr (read to the end once
/// the process is stopped: `Served::stop`).
struct Served {
    proc: Proc,
    /// The address printed, as printed: `http://ADDR/#token=TOKEN`.
    url: String,
    /// `ADDR` (`127.0.0.1:PORT`, `0.0.0.0:PORT`).
    addr: String,
    port: u16,
    token: String,
    stderr: std::thread::JoinHandle<String>,
}

/// `mcctl ARGS`, which must print `listening on http://ADDR/#token=TOKEN`.
fn serve_with(args: &[&str]) -> Served {
    let mut child = Command::new(MCCTL)
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start mcctl serve");
    let out = child.stdout.take().unwrap();
    let mut err = child.stderr.take().unwrap();
    let stderr = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = err.read_to_string(&mut s);
        s
    });
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut line = String::new();
        let _ = BufReader::new(out).read_line(&mut line);
        let _ = tx.send(line);
    });
    let mut proc = Proc(Some(child));
    let line = rx.recv_timeout(Duration::from_secs(15)).unwrap_or_default();
    let parsed = line
        .trim()
        .strip_prefix("listening on http://")
        .and_then(|rest| rest.split_once("/#token="));
    let Some((addr, token)) = parsed else {
        if let Some(mut c) = proc.0.take() {
            let _ = c.kill();
            let _ = c.wait();
        }
        panic!(
            "mcctl serve printed {line:?} instead of its address; stderr: {}",
            stderr.join().unwrap()
        )
    };
    let port = addr.rsplit_once(':').unwrap().1.parse().unwrap();
    Served {
        proc,
        url: line
            .trim()
            .strip_prefix("listening on ")
            .unwrap()
            .to_string(),
        addr: addr.to_string(),
        port,
        token: token.to_string(),
        stderr,
    }
}

/// `mcctl serve --listen 127.0.0.1:0` against `uri`.
fn serve(uri: &str, axis: usize) -> Served {
    let s = serve_with(&[
        "--card",
        uri,
        "serve",
        "--listen",
        "127.0.0.1:0",
        "--axis",
        &axis.to_string(),
    ]);
    assert!(s.addr.starts_with("127.0.0.1:"), "{}", s.url);
    assert_eq!(s.token.len(), 32, "{}", s.url);
    assert!(s.token.bytes().all(|b| b.is_ascii_hexdigit()), "{}", s.url);
    s
}

impl Served {
    /// Stop it as a person would (SIGTERM): a clean exit; its stderr.
    fn stop(mut self) -> String {
        let pid = self.proc.0.as_ref().unwrap().id().to_string();
        let killed = Command::new("kill").args(["-TERM", &pid]).status().unwrap();
        assert!(killed.success());
        let st = self.proc.wait_for(Duration::from_secs(10));
        assert!(st.is_some_and(|s| s.success()), "mcctl serve: {st:?}");
        self.stderr.join().unwrap()
    }

    /// A request as the page sends it: to `127.0.0.1:PORT`, with the token, and for a POST its
    /// own Origin and a JSON body.
    fn req(&self, method: &'static str, path: &str, body: &str) -> Req {
        let host = format!("127.0.0.1:{}", self.port);
        Req {
            method,
            path: path.to_string(),
            origin: (method != "GET").then(|| format!("http://{host}")),
            hosts: vec![host],
            auth: vec![format!("Bearer {}", self.token)],
            content_type: (method != "GET").then(|| "application/json".to_string()),
            body: body.to_string(),
        }
    }

    /// [`Served::req`], sent; the answer.
    fn call(&self, method: &'static str, path: &str, body: &str) -> Answer {
        self.req(method, path, body).send(self.port)
    }

    /// A GET as the page sends it: the status and the body.
    fn get(&self, path: &str) -> (u16, String) {
        let a = self.call("GET", path, "");
        (a.code, a.body)
    }
}

/// An HTTP/1.1 request, written out as given (no header added but Content-Length and
/// Connection).
#[derive(Debug, Clone)]
struct Req {
    method: &'static str,
    /// The request target: a path, or the absolute form `http://HOST/path`.
    path: String,
    /// Host headers (none, one, or more).
    hosts: Vec<String>,
    origin: Option<String>,
    /// Authorization headers.
    auth: Vec<String>,
    content_type: Option<String>,
    body: String,
}

/// An answer: the status, the head (lower case) and the body (empty for an event stream).
#[derive(Debug)]
struct Answer {
    code: u16,
    head: String,
    body: String,
}

impl Req {
    fn send(&self, port: u16) -> Answer {
        let mut s = std::net::TcpStream::connect(("127.0.0.1", port)).unwrap();
        s.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
        let mut text = format!("{} {} HTTP/1.1\r\n", self.method, self.path);
        for h in &self.hosts {
            text += &format!("Host: {h}\r\n");
        }
        if let Some(o) = &self.origin {
            text += &format!("Origin: {o}\r\n");
        }
        for a in &self.auth {
            text += &format!("Authorization: {a}\r\n");
        }
        if let Some(c) = &self.content_type {
            text += &format!("Content-Type: {c}\r\n");
        }
        if self.method != "GET" {
            text += &format!("Content-Length: {}\r\n", self.body.len());
        }
        text += "Connection: close\r\n\r\n";
        text += &self.body;
        s.write_all(text.as_bytes()).unwrap();
        // The head, then as much body as it announces (an event stream announces none and
        // never ends: not read).
        let mut r = BufReader::new(s);
        let mut head = String::new();
        loop {
            let mut line = String::new();
            r.read_line(&mut line).unwrap();
            if line == "\r\n" || line.is_empty() {
                break;
            }
            head += &line.to_ascii_lowercase();
        }
        let code = head
            .split_whitespace()
            .nth(1)
            .and_then(|c| c.parse().ok())
            .unwrap_or_else(|| panic!("not an HTTP answer: {head:?}"));
        let len = head
            .lines()
            .find_map(|l| l.strip_prefix("content-length:"))
            .map(|n| n.trim().parse::<usize>().unwrap());
        let mut body = vec![0; len.unwrap_or(0)];
        r.read_exact(&mut body).unwrap();
        Answer {
            code,
            head,
            body: String::from_utf8(body).unwrap(),
        }
    }
}

/// Run the page's driver; its JSON report.
fn drive(dir: &Path, chromium: &Path, url: &str, opts: &Value) -> Value {
    drive_script("drive.mjs", dir, chromium, url, opts)
}

/// Run the driver `script` of `tests/browser`; its JSON report.
fn drive_script(script: &str, dir: &Path, chromium: &Path, url: &str, opts: &Value) -> Value {
    let child = Command::new("node")
        .arg(dir.join(script))
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
    let served = serve(&uri, axis);

    let (step, good_kp, bad_kp) = (400.0, 70.0, -5.0);
    let mut opts = serde_json::json!({ "step": step, "kp": good_kp, "bad_kp": bad_kp });
    if let Some(p) = std::env::var_os("TUNING_SCREENSHOT") {
        opts["screenshot"] = p.to_string_lossy().into();
    }
    let j = drive(&dir, &chromium, &served.url, &opts);

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
    let (code, kept) = served.get(&format!("/api/tests/{}", api["id"]));
    assert_eq!(code, 200, "{kept}");
    let kept: Value = serde_json::from_str(&kept).unwrap();
    if let Err(at) = same_json(&kept, api, "") {
        panic!("GET /api/tests/ID is not the page's test: they differ at {at}");
    }
    let (code, body) = served.get("/api/tests/99");
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

    // The page took the token off the address bar; opened without it, it says what it
    // needs; under another site's name resolved to the server (DNS rebinding), the server
    // refuses it.
    let token = &served.token;
    let after = j["url_after_load"].as_str().unwrap();
    assert_eq!(after, format!("http://{}/", served.addr));
    let bare = j["without_token"].as_str().unwrap();
    assert!(
        bare.contains("could not start") && bare.contains("open the address"),
        "{bare}"
    );
    let rebound = &j["rebound"];
    assert_eq!(rebound["status"], 403, "{rebound}");
    let body = rebound["body"].as_str().unwrap();
    assert!(body.contains("does not name this server"), "{body}");
    assert!(!body.contains(token.as_str()), "{body}");

    // Stop the server as a person would (SIGTERM): a clean exit, nothing on stderr.
    let stderr = served.stop();
    assert_eq!(stderr, "");

    // The card itself: the axis at rest after the last step, running the gain the page
    // applied (and nothing of the refused one).
    let emu = runner.stop().expect("the emulator back");
    let a = emu.firmware().axis(axis).unwrap();
    assert_eq!(a.state, motioncard_sdk::AxisState::Standstill);
    assert_eq!(a.config.ffpiv.kp, good_kp);
    assert_eq!(a.config.ffpiv.ki, g0["ffpiv"]["ki"].as_f64().unwrap());
}

/// The page's PID+FF form and servo-filter list (`src/serve/web/servo.js`), driven in Chromium
/// by `tests/browser/servo.mjs`: the axis switched to PID+FF from the card's default tuning
/// (a negative derivative gain refused, the card's gains shown and kept), a notch added,
/// edited from its row, one above Nyquist refused, a low-pass added, the notch cleared; each
/// checked against the server's read-back and, at the end, against the firmware itself.
#[test]
fn the_tuning_page_sets_pidff_and_servo_filters_in_chromium() {
    let Some((chromium, dir)) = browser_tools() else {
        return;
    };
    let name = format!("test-serve-servo-{}", std::process::id());
    let emu = Emulator::create(&name, &EmuOptions::new(2, 10_000)).unwrap();
    let _server = Server::start(&name, emu.lessor()).unwrap();
    let runner = Runner::spawn(emu, card_emu::Clock::RealTime, false).unwrap();
    let axis = 1;
    let served = serve(&format!("emu:{name}"), axis);
    let kd = 4e-4;
    let opts = serde_json::json!({ "kd": kd, "bad_kd": -1.0 });
    let j = drive_script("servo.mjs", &dir, &chromium, &served.url, &opts);
    println!("{j}");
    assert_eq!(j["foreign_requests"], serde_json::json!([]));
    assert_eq!(
        j["page_errors"],
        serde_json::json!([]),
        "{}",
        j["page_errors"]
    );

    // PID+FF from the card's default tuning; the derivative gain the card accepted is held.
    let d = motioncard_sdk::PidffSettings::default();
    assert_eq!(j["law_before"], "ffpiv");
    assert_eq!(j["pidff_visible"], true);
    assert_eq!(
        j["prefilled"]["kp"]
            .as_str()
            .unwrap()
            .parse::<f64>()
            .unwrap(),
        d.kp
    );
    assert_eq!(
        j["prefilled"]["d_filter_hz"]
            .as_str()
            .unwrap()
            .parse::<f64>()
            .unwrap(),
        d.d_filter_hz
    );
    let good = &j["good_gain"];
    assert_eq!(good["status"], "ok", "{good}");
    assert!(
        good["message"].as_str().unwrap().contains("PID+FF"),
        "{good}"
    );
    assert_eq!(good["server"]["law"], "pidff");
    assert_eq!(good["server"]["pidff"]["kd"].as_f64().unwrap(), kd);
    assert_eq!(good["server"]["pidff"]["ki"].as_f64().unwrap(), d.ki);
    assert_eq!(
        good["held_kd"].as_str().unwrap().parse::<f64>().unwrap(),
        kd
    );
    assert!(
        good["held_law"].as_str().unwrap().contains("PID+FF"),
        "{good}"
    );
    let bad = &j["bad_gain"];
    assert_eq!(bad["status"], "error", "{bad}");
    let m = bad["message"].as_str().unwrap();
    assert!(
        m.contains("The card refused") && m.contains("PidffGains"),
        "{m}"
    );
    assert_eq!(
        bad["server"]["pidff"]["kd"].as_f64().unwrap(),
        kd,
        "nothing changed"
    );
    assert_eq!(bad["held_kd"].as_str().unwrap().parse::<f64>().unwrap(), kd);

    // The filter list.
    let kinds = |v: &Value| -> Vec<String> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|r| r["kind"].as_str().unwrap().to_string())
            .collect()
    };
    let server_kinds = |v: &Value| -> Vec<String> {
        v["slots"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s["filter"]["kind"].as_str().unwrap().to_string())
            .collect()
    };
    assert_eq!(kinds(&j["rows_before"]), ["none"; 4]);
    let notch = &j["notch"];
    assert_eq!(notch["status"], "ok", "{notch}");
    assert_eq!(kinds(&notch["rows"]), ["none", "notch", "none", "none"]);
    assert_eq!(
        server_kinds(&notch["server"]),
        ["none", "notch", "none", "none"]
    );
    let held = &notch["server"]["slots"][1];
    assert_eq!(held["filter"]["freq_hz"].as_f64(), Some(24.0));
    assert_eq!(held["filter"]["damping"].as_f64(), Some(0.2));
    assert_eq!(held["filter"]["depth_db"].as_f64(), Some(-20.0));
    assert_eq!(held["coeffs"].as_array().unwrap().len(), 5);
    let f = &j["edit_form"];
    assert_eq!(
        (f["slot"].as_str(), f["kind"].as_str()),
        (Some("1"), Some("notch"))
    );
    assert_eq!(f["freq_hz"].as_str().unwrap().parse::<f64>().unwrap(), 24.0);
    assert_eq!(
        f["depth_db"].as_str().unwrap().parse::<f64>().unwrap(),
        -20.0
    );
    assert_eq!(f["freq2_visible"], false, "a notch has no second frequency");
    let edited = &j["edited"];
    assert_eq!(edited["status"], "ok", "{edited}");
    assert_eq!(
        edited["server"]["slots"][1]["filter"]["freq_hz"].as_f64(),
        Some(30.0)
    );
    assert_eq!(
        edited["server"]["slots"][1]["filter"]["damping"].as_f64(),
        Some(0.2)
    );
    assert!(
        edited["rows"][1]["params"]
            .as_str()
            .unwrap()
            .contains("30 Hz"),
        "{edited}"
    );
    let refused = &j["refused"];
    assert_eq!(refused["status"], "error", "{refused}");
    let m = refused["message"].as_str().unwrap();
    assert!(
        m.contains("The card refused this filter") && m.contains("FilterFreq"),
        "{m}"
    );
    assert_eq!(refused["server"], edited["server"], "nothing changed");
    let lowpass = &j["lowpass"];
    assert_eq!(lowpass["status"], "ok", "{lowpass}");
    assert_eq!(
        server_kinds(&lowpass["server"]),
        ["none", "notch", "none", "lowpass"]
    );
    let cleared = &j["cleared"];
    assert_eq!(cleared["status"], "ok", "{cleared}");
    assert_eq!(kinds(&cleared["rows"]), ["none", "none", "none", "lowpass"]);
    assert_eq!(
        server_kinds(&cleared["server"]),
        ["none", "none", "none", "lowpass"]
    );
    // The refused requests' 422s are the console's only errors.
    let errors = j["console_errors"].as_array().unwrap();
    assert!(
        errors.iter().all(|e| e.as_str().unwrap().contains("422")),
        "{errors:?}"
    );

    assert_eq!(served.stop(), "");
    // The firmware runs PID+FF with the page's gain and holds the low-pass alone.
    let emu = runner.stop().expect("the emulator back");
    let a = emu.firmware().axis(axis).unwrap();
    assert_eq!(
        a.config.servo_law,
        motioncard_sdk::proto::raw::MC_SERVO_PIDFF
    );
    assert_eq!(a.config.pidff.map(|g| g.kd), Some(kd));
    let held = a.filters().block();
    assert_eq!(held.active, 1 << 3, "the low-pass alone");
    assert_eq!((held.slot[3].freq_hz, held.slot[3].damping), (800.0, 0.7));
}

/// The page's frequency response (`src/serve/web/bode.js`), driven in Chromium by
/// `tests/browser/bode.mjs`: a sweep from above its end refused with the card's `FreqRange`
/// (nothing plotted), then a small closed-loop sweep through the form, whose Bode charts plot
/// exactly the points `POST /api/freq` answered (`mcctl freq --json`'s object) over a log
/// frequency axis, at the frequencies the card was asked for.
#[test]
fn the_tuning_page_sweeps_the_frequency_response_and_draws_its_bode_plot_in_chromium() {
    let Some((chromium, dir)) = browser_tools() else {
        return;
    };
    let name = format!("test-serve-bode-{}", std::process::id());
    let emu = Emulator::create(&name, &EmuOptions::new(2, 10_000)).unwrap();
    let _server = Server::start(&name, emu.lessor()).unwrap();
    let runner = Runner::spawn(emu, card_emu::Clock::RealTime, false).unwrap();
    let axis = 1;
    let served = serve(&format!("emu:{name}"), axis);
    let (from, to, points) = (10.0, 60.0, 4);
    let mut opts = serde_json::json!({ "from": from, "to": to, "points": points, "amplitude": 100,
        "cycles": 2, "settle": 0.05 });
    if let Some(p) = std::env::var_os("BODE_SCREENSHOT") {
        opts["screenshot"] = p.to_string_lossy().into();
    }
    let j = drive_script("bode.mjs", &dir, &chromium, &served.url, &opts);
    println!("{j}");
    assert_eq!(j["foreign_requests"], serde_json::json!([]));
    assert_eq!(
        j["page_errors"],
        serde_json::json!([]),
        "{}",
        j["page_errors"]
    );
    // The form starts from `mcctl freq`'s defaults, on the page's axis.
    let d = &j["defaults"];
    assert_eq!(d["axis"], axis.to_string());
    assert_eq!(d["mode"], "closed_loop");
    assert_eq!(
        (d["from"].as_str(), d["to"].as_str()),
        (Some("5"), Some("1000"))
    );
    assert_eq!(
        (d["points"].as_str(), d["amplitude"].as_str()),
        (Some("40"), Some("100"))
    );

    // From above to: the card's refusal, shown; nothing plotted.
    let refused = &j["refused"];
    assert_eq!(refused["status"], "error", "{refused}");
    let m = refused["message"].as_str().unwrap();
    assert!(
        m.contains("The card refused this sweep") && m.contains("FreqRange"),
        "{m}"
    );
    assert_eq!(refused["answer"]["status"], 422, "{refused}");
    assert_eq!(refused["gain"], serde_json::json!([[], []]));
    assert_eq!(refused["phase"], serde_json::json!([[], []]));

    // The sweep: the charts plot the server's points, exactly.
    let swept = &j["swept"];
    assert_eq!(swept["status"], "ok", "{swept}");
    assert_eq!(swept["answer"]["status"], 200, "{swept}");
    let answer: Value = serde_json::from_str(swept["answer"]["body"].as_str().unwrap()).unwrap();
    assert_eq!(answer["mode"], "closed_loop");
    assert_eq!(answer["complete"], true);
    let pts = answer["points"].as_array().unwrap();
    assert_eq!(pts.len(), points);
    let col = |k: &str| -> Vec<f64> { pts.iter().map(|p| p[k].as_f64().unwrap()).collect() };
    let hz = col("hz");
    // The frequencies asked for, each as the card runs it: a whole number of cycles (at
    // least 2, and a window of MC_FREQ_WINDOW_MIN ticks) in a whole number of ticks.
    let rate = 10_000.0;
    let want: Vec<f64> = motioncard_sdk::sweep_frequencies(from, to, points)
        .into_iter()
        .map(|f| {
            let per = rate / f;
            let min = motioncard_sdk::proto::raw::MC_FREQ_WINDOW_MIN as f64;
            let c = 2f64.max((min / per).ceil());
            c * rate / (c * per).round()
        })
        .collect();
    same_json(&serde_json::json!(hz), &serde_json::json!(want), "hz").unwrap();
    let plotted_gain = &swept["gain"];
    let plotted_phase = &swept["phase"];
    same_json(&plotted_gain[0], &serde_json::json!(hz), "gain x").unwrap();
    same_json(&plotted_gain[1], &serde_json::json!(col("gain_db")), "gain").unwrap();
    same_json(&plotted_phase[0], &serde_json::json!(hz), "phase x").unwrap();
    same_json(
        &plotted_phase[1],
        &serde_json::json!(col("phase_deg")),
        "phase",
    )
    .unwrap();
    assert_eq!(swept["x_log"], 3, "a log frequency axis");
    // Well inside the loop's bandwidth the position follows the reference: near 0 dB, a
    // small lag.
    let (g0, p0) = (col("gain_db")[0], col("phase_deg")[0]);
    assert!(g0.abs() < 3.0 && p0 < 0.0 && p0 > -90.0, "{g0} dB {p0} deg");
    // Every resonance the server found is listed, by its name.
    let listed: Vec<&str> = swept["resonances"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r.as_str().unwrap())
        .collect();
    let found: Vec<&Value> = answer["resonances"]
        .as_array()
        .unwrap()
        .iter()
        .chain(answer["plant_resonances"].as_array().unwrap())
        .collect();
    if found.is_empty() {
        assert_eq!(listed, ["no resonance found (closed loop X/R)"]);
    } else {
        for r in found {
            let n = r["name"].as_str().unwrap();
            assert!(
                listed.iter().any(|l| l.ends_with(n)),
                "{n} not in {listed:?}"
            );
        }
    }
    assert!(
        swept["title"].as_str().unwrap().contains("4 points"),
        "{swept}"
    );
    // The refused sweep's 422 is the console's only error.
    let errors = j["console_errors"].as_array().unwrap();
    assert!(
        errors.len() == 1 && errors[0].as_str().unwrap().contains("422"),
        "{errors:?}"
    );
    assert_eq!(served.stop(), "");
    runner.stop().expect("the emulator back");
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
    // A token too short to be a secret, or that would not travel unescaped.
    let (code, err) = run(&["serve", "--token", "short"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--token") && err.contains("the token has 5 characters"),
        "{err}"
    );
    let (code, err) = run(&["serve", "--token", "a token with spaces in it"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("may hold only"), "{err}");
    let (code, err) = run(&["serve", "--axis", "99", "--listen", "127.0.0.1:0"]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("axis 99"), "{err}");
    let busy = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = busy.local_addr().unwrap().to_string();
    let (code, err) = run(&["serve", "--listen", &addr]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains(&format!("listen on {addr}")), "{err}");
}

// ---- The guard (src/serve/guard.rs): Host, Origin, token and content type on every route ----

/// The axis `mcctl serve` tunes in the guard's tests.
const AXIS: usize = 1;

/// A move of 2,000,000 counts at 5·10⁵ counts/s, powering the axis on: what a page that got
/// past the guard would run.
const FAR_MOVE: &str = r#"{"kind": "move", "distance": 2000000, "enable": true,
    "limits": {"vmax": 500000, "amax": 10000000, "jmax": 1000000000}}"#;

/// A step test that may not power the axis on: refused (409) naming the axis's state, so it
/// reads the state through the API without changing it.
const PROBE: &str = r#"{"kind": "step", "distance": 100, "enable": false}"#;

/// The fallback's 404 (no route), as against a route's own 404.
const NO_ROUTE: &str = "no such page or API route";

/// An `emu:` card of two axes run in real time by this test, and `mcctl serve` on its axis 1.
struct Bench {
    runner: Runner,
    _server: Server,
    served: Served,
}

fn bench(tag: &str) -> Bench {
    let name = format!("test-serve-{tag}-{}", std::process::id());
    let emu = Emulator::create(&name, &EmuOptions::new(2, 10_000)).unwrap();
    let server = Server::start(&name, emu.lessor()).unwrap();
    let runner = Runner::spawn(emu, card_emu::Clock::RealTime, false).unwrap();
    let served = serve(&format!("emu:{name}"), AXIS);
    Bench {
        runner,
        _server: server,
        served,
    }
}

impl Bench {
    /// Stop the server (a clean exit, nothing on stderr) and the card: the card's axis.
    fn finish(self) -> card_emu::firmware::axis::Axis {
        assert_eq!(self.served.stop(), "", "mcctl serve's stderr");
        let emu = self.runner.stop().expect("the emulator back");
        let axis = emu.firmware().axis(AXIS).unwrap().clone();
        // No request of these tests sets a servo filter that gets through.
        assert!(
            !axis.filters().any(),
            "a filter was set: {:?}",
            axis.filters()
        );
        axis
    }
}

/// The axis's gains as the API reads them (200).
fn gains(s: &Served) -> Value {
    let (code, body) = s.get("/api/gains");
    assert_eq!(code, 200, "{body}");
    serde_json::from_str(&body).unwrap()
}

/// The FFPIV gains `g` with K_P set to `kp`, as `POST /api/gains` takes them.
fn with_kp(g: &Value, kp: f64) -> String {
    let mut f = g["ffpiv"].clone();
    f["law"] = "ffpiv".into();
    f["kp"] = kp.into();
    f.to_string()
}

/// What the API says of the axis's state (the [`PROBE`]'s refusal).
fn axis_state(s: &Served) -> String {
    let a = s.call("POST", "/api/tests", PROBE);
    assert_eq!(a.code, 409, "{a:?}");
    a.body
}

/// A frequency sweep powering the axis on, as `POST /api/freq` takes it: a page that got past
/// the guard would have the axis shaken and left enabled.
const SWEEP: &str = r#"{"mode": "closed_loop", "from_hz": 5, "to_hz": 50, "points": 3,
    "amplitude": 1000, "settle_s": 0.05, "enable": true}"#;

/// A notch on the servo output, as `POST /api/filters` takes it.
const NOTCH: &str =
    r#"{"slot": 0, "filter": {"kind": "notch", "freq_hz": 24, "damping": 0.2, "depth_db": -20}}"#;

/// Every request the server could be asked: each route of `mcctl::serve::ROUTES` with
/// each method it answers, a method it does not (PUT, DELETE: refused by the guard before
/// axum's 405), and paths that are no route (the fallback). Each with the body that would do
/// harm if it got through: K_P = 9000, the [`FAR_MOVE`], a reset. `files`: with the GETs of
/// the page's files (which need no token).
fn every_request(g: &Value, files: bool) -> Vec<(&'static str, String, String)> {
    let mut all = Vec::new();
    for r in mcctl::serve::ROUTES {
        let path = r.path.replace("{which}", "last");
        for &m in r.methods.iter().chain(&["PUT", "DELETE"]) {
            if r.file && m == "GET" && !files {
                continue;
            }
            let body = match (m, r.path) {
                ("GET", _) => String::new(),
                ("POST", "/api/gains") => with_kp(g, 9000.0),
                ("POST", "/api/tests") => FAR_MOVE.to_string(),
                ("POST", "/api/filters") => NOTCH.to_string(),
                ("POST", "/api/freq") => SWEEP.to_string(),
                ("POST", "/api/reset") | ("PUT" | "DELETE", _) => "{}".to_string(),
                other => panic!("{other:?}: a route this test does not know; give it a body here"),
            };
            all.push((m, path.clone(), body));
        }
    }
    all.push(("GET", "/api/nope".into(), String::new()));
    all.push(("POST", "/nope".into(), "{}".into()));
    all
}

/// A 403 from the guard for `why` (a word of its message), with no CORS header and nothing
/// of the card in it.
fn refused(a: &Answer, what: &str, why: &str) {
    assert_eq!(a.code, 403, "{what}: {a:?}");
    let body: Value =
        serde_json::from_str(&a.body).unwrap_or_else(|e| panic!("{what}: {e}: {}", a.body));
    let msg = body["error"].as_str().unwrap();
    assert!(
        msg.starts_with("refused: ") && msg.to_lowercase().contains(why),
        "{what}: {msg}"
    );
    assert!(!a.head.contains("access-control-"), "{what}: {}", a.head);
    assert!(!a.body.contains("kp"), "{what}: {}", a.body);
}

/// DNS rebinding: a page of another site whose name resolves to 127.0.0.1 sends its own
/// name as the Host (and as its Origin), as does anything that names the server without its
/// port. Every route, with the right token and JSON, is refused, and the card is as before:
/// the same gains, no test run, the axis still disabled at position 0.
#[test]
fn dns_rebinding_hosts_are_refused_on_every_route_and_change_nothing() {
    let b = bench("host");
    let s = &b.served;
    let p = s.port;
    let g0 = gains(s);
    let kp0 = g0["ffpiv"]["kp"].as_f64().unwrap();
    let other_port = if p == u16::MAX { p - 1 } else { p + 1 };
    let bad_hosts: Vec<Vec<String>> = vec![
        vec![format!("evil.example:{p}")],
        vec!["evil.example".into()],
        vec![format!("localhost.evil.example:{p}")],
        vec![format!("127.0.0.1.evil.example:{p}")],
        vec![format!("127.0.0.1:{other_port}")],
        vec![format!("localhost:{other_port}")],
        vec!["127.0.0.1".into()],
        vec!["localhost".into()],
        vec![format!("[::1]:{p}")], // loopback, but not the address listened on
        vec![],                     // no Host
        vec![String::new()],
        vec![format!("127.0.0.1:{p}"), format!("evil.example:{p}")],
    ];
    let requests = every_request(&g0, true);
    for hosts in &bad_hosts {
        for (m, path, body) in &requests {
            let mut r = s.req(m, path, body);
            r.hosts = hosts.clone();
            if r.origin.is_some() {
                r.origin = hosts.first().map(|h| format!("http://{h}"));
            }
            refused(&r.send(p), &format!("{m} {path} Host {hosts:?}"), "host");
        }
    }
    // The request line in absolute form, naming another host than the Host header.
    for (m, body) in [("GET", String::new()), ("POST", with_kp(&g0, 9000.0))] {
        let r = s.req(m, &format!("http://evil.example:{p}/api/gains"), &body);
        refused(&r.send(p), &format!("{m} absolute form"), "host");
    }

    // Nothing changed: the gains, no test kept, the axis still disabled.
    assert_eq!(gains(s)["ffpiv"]["kp"].as_f64(), Some(kp0));
    let (code, body) = s.get("/api/tests/last");
    assert_eq!(code, 404, "{body}");
    let state = axis_state(s);
    assert!(state.contains("axis 1 is disabled"), "{state}");
    // Its own names work: 127.0.0.1:PORT (above) and localhost:PORT, with their origins.
    let mut r = s.req("GET", "/api/gains", "");
    r.hosts = vec![format!("localhost:{p}")];
    let a = r.send(p);
    assert_eq!(a.code, 200, "{a:?}");
    let mut r = s.req("POST", "/api/tests", PROBE);
    r.hosts = vec![format!("LocalHost:{p}")];
    r.origin = Some(format!("http://localhost:{p}"));
    let a = r.send(p);
    assert_eq!(a.code, 409, "{a:?}");
    assert!(a.body.contains("is disabled"), "{a:?}");

    // The card: K_P as it was, the axis unpowered and never moved.
    let a = b.finish();
    // (the API's copy went through the card's read-back: the same to 1e-12)
    assert!(close(a.config.ffpiv.kp, kp0), "{}", a.config.ffpiv.kp);
    assert_eq!(a.state, motioncard_sdk::AxisState::Disabled);
    assert_eq!(a.reference().pos, 0.0);
    assert_eq!(a.last_target(), 0.0);
}

/// A page of another site cannot use the server even with the token: the issue's simple
/// cross-site request (`POST /api/reset`, `text/plain`, a foreign Origin) leaves an axis in
/// ErrorStop in ErrorStop; every route refuses every Origin but the page's own; a POST
/// without an Origin is refused; the page's own Origin with a body that is not JSON is 415.
#[test]
fn a_foreign_origin_cannot_reset_an_axis_in_error_stop_nor_use_any_route() {
    let b = bench("origin");
    let s = &b.served;
    let p = s.port;
    let g0 = gains(s);
    let kp0 = g0["ffpiv"]["kp"].as_f64().unwrap();
    // A step beyond the following-error limit (1000 counts at rest) trips the axis.
    let trip = s.call(
        "POST",
        "/api/tests",
        r#"{"kind": "step", "distance": 2000, "enable": true}"#,
    );
    assert!(trip.body.contains("ErrorStop (FollowingError)"), "{trip:?}");
    let state = axis_state(s);
    assert!(state.contains("axis 1 is in ErrorStop"), "{state}");

    // The issue's request, then with the forms' content types, and with the token too.
    for ct in [
        "text/plain",
        "application/x-www-form-urlencoded",
        "multipart/form-data; boundary=x",
        "application/json",
    ] {
        for auth in [vec![], vec![format!("Bearer {}", s.token)]] {
            let mut r = s.req("POST", "/api/reset", "{}");
            r.origin = Some("http://evil.example".into());
            r.content_type = Some(ct.into());
            r.auth = auth;
            let what = format!("reset, {ct}, {} token", r.auth.len());
            refused(&r.send(p), &what, "origin");
        }
    }
    // Every route, each Origin but the page's own (and none, for what is not a GET), with the
    // token and JSON.
    let origins = [
        Some("http://evil.example".to_string()),
        Some(format!("http://evil.example:{p}")),
        Some("null".into()),
        Some(format!("https://127.0.0.1:{p}")),
        Some(format!(
            "http://127.0.0.1:{}",
            if p == u16::MAX { p - 1 } else { p + 1 }
        )),
        Some(format!("http://localhost:{p}")), // this server, but another origin than its Host
        Some(format!("http://127.0.0.1:{p}/")),
        Some(format!("http://127.0.0.1:{p}.evil.example")),
        None,
    ];
    for (m, path, body) in every_request(&g0, true) {
        for o in &origins {
            if o.is_none() && m == "GET" {
                continue; // a page's own GETs carry no Origin
            }
            let mut r = s.req(m, &path, &body);
            r.origin = o.clone();
            refused(&r.send(p), &format!("{m} {path} Origin {o:?}"), "origin");
        }
    }
    // The page's own Origin and the token, but not JSON: 415.
    for ct in [Some("text/plain"), Some("application/jsonx"), None] {
        let mut r = s.req("POST", "/api/reset", "{}");
        r.content_type = ct.map(str::to_string);
        let a = r.send(p);
        assert_eq!(a.code, 415, "{ct:?}: {a:?}");
        assert!(a.body.contains("application/json"), "{a:?}");
    }

    // Nothing changed: still in ErrorStop, the same gains.
    let state = axis_state(s);
    assert!(state.contains("axis 1 is in ErrorStop"), "{state}");
    assert_eq!(gains(s)["ffpiv"]["kp"].as_f64(), Some(kp0));
    let a = b.finish();
    assert_eq!(a.state, motioncard_sdk::AxisState::ErrorStop);
    // (the API's copy went through the card's read-back: the same to 1e-12)
    assert!(close(a.config.ffpiv.kp, kp0), "{}", a.config.ffpiv.kp);
}

/// The token: every API route (and every path that is no route) refuses a request without
/// it, with a wrong one, or with it where it does not go, and changes nothing; the page's
/// files need none and hold none; with it, every route answers (a method a route does not
/// list is axum's 405), and the page's requests work: a gain, a test, the stream, a trip and
/// its reset.
#[test]
fn requests_without_the_token_are_refused_and_with_it_every_route_answers() {
    let b = bench("token");
    let s = &b.served;
    let p = s.port;
    let t = s.token.clone();
    let g0 = gains(s);
    let kp0 = g0["ffpiv"]["kp"].as_f64().unwrap();
    let last = t.chars().last().unwrap();
    let wrong = format!(
        "{}{}",
        &t[..t.len() - 1],
        if last == '0' { '1' } else { '0' }
    );
    let bad_auth: Vec<Vec<String>> = vec![
        vec![],
        vec![format!("Bearer {wrong}")],
        vec![format!("Bearer {}", &t[..t.len() - 1])],
        vec![format!("Bearer {t}0")],
        vec![format!("Bearer {}", t.to_uppercase())],
        vec![format!("Basic {t}")],
        vec![t.clone()],
        vec!["Bearer".into()],
        vec![format!("Bearer {t}"), format!("Bearer {wrong}")],
    ];
    let live = mcctl::serve::LIVE;
    for (m, path, body) in every_request(&g0, false) {
        for auth in &bad_auth {
            let mut r = s.req(m, &path, &body);
            r.auth = auth.clone();
            refused(&r.send(p), &format!("{m} {path} {auth:?}"), "token");
        }
        // In the query, only the event stream takes it.
        if !(m == "GET" && path == live) {
            let mut r = s.req(m, &format!("{path}?token={t}"), &body);
            r.auth = vec![];
            refused(&r.send(p), &format!("{m} {path}?token="), "token");
        }
    }
    for q in [
        format!("?token={wrong}"),
        format!("?token={t}&token={t}"),
        "?token=".into(),
        format!("?tok={t}"),
    ] {
        let mut r = s.req("GET", &format!("{live}{q}"), "");
        r.auth = vec![];
        refused(&r.send(p), &format!("{live}{q}"), "token");
    }
    // Nothing changed.
    assert_eq!(gains(s)["ffpiv"]["kp"].as_f64(), Some(kp0));
    assert_eq!(s.get("/api/tests/last").0, 404);
    let state = axis_state(s);
    assert!(state.contains("axis 1 is disabled"), "{state}");

    // The page's files: no token needed, none in them.
    for r in mcctl::serve::ROUTES.iter().filter(|r| r.file) {
        let mut q = s.req("GET", r.path, "");
        q.auth = vec![];
        let a = q.send(p);
        assert_eq!(a.code, 200, "{}: {a:?}", r.path);
        assert!(!a.body.contains(&t), "{} holds the token", r.path);
        assert!(!a.head.contains("access-control-"), "{}", a.head);
        assert!(a.head.contains("x-frame-options: deny"), "{}", a.head);
    }
    // With the token every route answers each method it lists (a 403 would be the guard, a
    // 404 saying NO_ROUTE or a 405 the router), and only those: the rest are 405.
    for r in mcctl::serve::ROUTES {
        let path = r.path.replace("{which}", "last");
        for m in ["GET", "POST", "PUT", "DELETE", "PATCH"] {
            let body = match (m, r.path) {
                ("POST", "/api/tests") => PROBE, // 409: the axis is disabled
                ("POST", "/api/gains") => r#"{"law": "ffpiv"}"#, // 400: no gains in it
                (_, "/api/reset") => "{}",       // 422: the card resets no disabled axis
                _ => "{}",
            };
            let a = s.call(m, &path, if m == "GET" { "" } else { body });
            if r.methods.contains(&m) {
                assert!(
                    ![403, 405].contains(&a.code) && !a.body.contains(NO_ROUTE),
                    "{m} {path}: {a:?}"
                );
            } else {
                assert_eq!(a.code, 405, "{m} {path}: {a:?}");
            }
            assert!(!a.head.contains("access-control-"), "{}", a.head);
        }
    }
    let a = s.call("GET", "/api/nope", "");
    assert_eq!(a.code, 404, "{a:?}");
    assert!(a.body.contains(NO_ROUTE), "{a:?}");

    // What the page does, with the token.
    let a = s.call("POST", "/api/gains", &with_kp(&g0, 70.0));
    assert_eq!(a.code, 200, "{a:?}");
    assert_eq!(gains(s)["ffpiv"]["kp"].as_f64(), Some(70.0));
    let a = s.call(
        "POST",
        "/api/tests",
        r#"{"kind": "step", "distance": 400, "enable": true}"#,
    );
    assert_eq!(a.code, 200, "{a:?}");
    let run: Value = serde_json::from_str(&a.body).unwrap();
    assert_eq!(run["in_position"], true, "{}", run["outcome"]);
    for (path, auth) in [
        (format!("{live}?token={t}"), vec![]),
        (live.to_string(), vec![format!("Bearer {t}")]),
    ] {
        let mut r = s.req("GET", &path, "");
        r.auth = auth;
        let a = r.send(p);
        assert_eq!(a.code, 200, "{path}: {a:?}");
        assert!(a.head.contains("content-type: text/event-stream"), "{a:?}");
    }
    let trip = s.call(
        "POST",
        "/api/tests",
        r#"{"kind": "step", "distance": 2000, "enable": true}"#,
    );
    assert!(trip.body.contains("ErrorStop (FollowingError)"), "{trip:?}");
    let a = s.call("POST", "/api/reset", "{}");
    assert_eq!(a.code, 200, "{a:?}");
    assert_eq!(a.body, r#"{"state":"Disabled"}"#);

    let a = b.finish();
    assert_eq!(a.state, motioncard_sdk::AxisState::Disabled);
    assert_eq!(a.config.ffpiv.kp, 70.0);
}

/// `--listen 0.0.0.0:0`: the page is reachable from the network. Without `--token` mcctl
/// generates one (printed in the address) and warns on stderr, without TLS; with `--token`
/// it takes that one and no other. On loopback nothing is warned of.
#[test]
fn listening_beyond_loopback_warns_and_generates_a_token_or_takes_the_given_one() {
    let check = |s: &Served, token: &str| {
        assert_eq!(s.token, token);
        let p = s.port;
        // Over loopback, by its address, by the address listened on, and by localhost.
        for host in [
            format!("127.0.0.1:{p}"),
            format!("0.0.0.0:{p}"),
            format!("localhost:{p}"),
        ] {
            let mut r = s.req("GET", "/api/info", "");
            r.hosts = vec![host.clone()];
            assert_eq!(r.send(p).code, 200, "{host}");
        }
        let mut r = s.req("GET", "/api/info", "");
        r.hosts = vec![format!("evil.example:{p}")];
        refused(&r.send(p), "evil.example", "host");
        for auth in [
            vec![],
            vec!["Bearer 0123456789abcdef0123456789abcdef".into()],
        ] {
            let mut r = s.req("GET", "/api/info", "");
            r.auth = auth;
            refused(&r.send(p), "another token", "token");
        }
    };
    let warned = |err: &str| {
        err.starts_with("mcctl serve: warning: 0.0.0.0:")
            && err.contains("is not a loopback address")
            && err.contains("reachable from the network, without TLS")
    };

    let s = serve_with(&["serve", "--listen", "0.0.0.0:0"]);
    assert!(s.addr.starts_with("0.0.0.0:"), "{}", s.url);
    let token = s.token.clone();
    assert!(
        token.len() == 32 && token.bytes().all(|b| b.is_ascii_hexdigit()),
        "{}",
        s.url
    );
    check(&s, &token);
    let err = s.stop();
    assert!(warned(&err), "{err}");
    assert!(err.contains("The token was generated"), "{err}");
    assert!(
        !err.contains(&token),
        "the token goes to stdout only: {err}"
    );

    let mine = "a-token-of-my-own_0123456789";
    let s = serve_with(&["serve", "--listen", "0.0.0.0:0", "--token", mine]);
    check(&s, mine);
    let err = s.stop();
    assert!(warned(&err), "{err}");
    assert!(!err.contains("generated"), "{err}");

    let s = serve_with(&["serve", "--listen", "127.0.0.1:0", "--token", mine]);
    assert_eq!(s.token, mine);
    assert_eq!(s.get("/api/info").0, 200);
    assert_eq!(s.stop(), "", "loopback: no warning");
}
