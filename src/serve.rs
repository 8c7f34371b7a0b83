//! `mcctl serve`: the tuning page. A local web server (axum on tokio) for one axis of an
//! open card: live plots of the scope stream, the step and move tests with their figures
//! ([`crate::tuning`]), and the servo gains, read and applied.
//!
//! Every request passes one middleware first ([`guard`], layered over the whole router, its
//! fallback included): a `Host` naming this server (no DNS rebinding), an `Origin` of its own
//! page for anything but GET and HEAD (and never another one), the server's token ([`Token`],
//! printed in the address at start) for everything but the page's files, and `Content-Type:
//! application/json` for anything but GET and HEAD. The routes are [`ROUTES`]:
//!
//! | route | what |
//! |---|---|
//! | `GET /` and its files | the page (`serve/web/`, compiled into the binary: nothing is fetched at run time); no token |
//! | `GET /api/info` | the card, the axis, the figure definitions' constants and the defaults |
//! | `GET /api/live` | the live stream, server-sent events: `samples` ([`live::Batch`]), `paused`, `resumed`, `failure`; the token also as `?token=` (an `EventSource` sets no header) |
//! | `POST /api/tests` | `{"kind": "step"\|"move", "distance": counts, "limits"?: {vmax, amax, jmax}, "enable"?: bool}`: run a test, answer its [`TestRun`] with an `id` |
//! | `GET /api/tests/{id}`, `GET /api/tests/last` | a test's answer again (the last 8 are kept) |
//! | `POST /api/reset` | MC_Reset of the axis (after a trip); answers `{"state"}` |
//! | `GET /api/gains` | the gains the axis runs with ([`Gains`]) |
//! | `POST /api/gains` | `{"law": "ffpiv", kp, ki, kv, kvff, kaff, vel_filter_hz}`, `{"law": "pdplus", kp, kd, kv, ka, kc, tau, ke, umax}` or `{"law": "pidff", kp, ki, kd, kvff, kaff, friction, friction_deadband, d_filter_hz}`: apply, answer the gains then held |
//! | `GET /api/filters` | the servo output's filter slots ([`servo_filters::Filters`]) |
//! | `POST /api/filters` | `{"slot": k, "filter": {"kind": "notch", freq_hz, damping, depth_db}}` (or `lowpass`, `lead_lag`, `raw`; `none` clears): set, answer the slots then held |
//! | `POST /api/freq` | `{"mode": "closed_loop"\|"plant", from_hz, to_hz, points, amplitude, "cycles"?, "settle_s"?, "enable"?: bool, "axis"?}` ([`sweep::SweepRequest`]): run a frequency sweep, answer `mcctl freq --json`'s object (`points`, `resonances`, `plant`, `open_loop`, ...) |
//!
//! Errors are `{"error": message, "kind": the SDK's error kind (if any)}` with 400 (a bad
//! request, or an axis not the page's), 403 (refused by the guard: Host, Origin or token), 404 (no such route, or a test
//! no longer kept), 409 (the axis not at rest, the scope or the test slot busy), 415 (not a
//! GET or HEAD, and not `Content-Type: application/json`), 422 (the card refused, or ended a
//! test's motion or a sweep), 500 (a capture that cannot be measured) or 503 (the card failed).
//!
//! The card's SDK blocks; the handlers run its calls with `spawn_blocking`. The only lock guard
//! held across an `.await` is the one-test guard, which is only ever try-locked (a second test
//! gets 409, never waits) and which nothing else takes. The live stream is its own thread
//! ([`live`]); a test pauses it for the capture and the stream resumes when the test ends,
//! whatever the outcome.

pub mod guard;
pub mod live;

use crate::tuning::gains::{self, Apply, Gains};
use crate::tuning::run::{run_test, Limits, TestError, TestKind, TestRun, TestSpec};
use crate::tuning::servo_filters::{self, FilterError, Filters};
use crate::tuning::sweep;
use crate::{Card, Error, Result, Scope};
use axum::extract::rejection::JsonRejection;
use axum::extract::State;
use axum::http::{header, StatusCode};
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post, MethodRouter};
use axum::{Json, Router};
pub use guard::Token;
use live::{Live, LiveMsg};
use serde::Deserialize;
use serde_json::json;
use std::io::Write as _;
use std::net::SocketAddr;
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// What `mcctl serve` serves.
#[derive(Debug, Clone)]
pub struct Options {
    /// Where to listen (port 0: any free port; the address is printed). Beyond loopback the
    /// page is reachable from the network: [`serve`] warns so on stderr.
    pub listen: SocketAddr,
    /// The token every API request must carry; None: one generated from the OS's random
    /// source. Printed either way, in the address.
    pub token: Option<Token>,
    /// The axis the page tunes.
    pub axis: usize,
    /// The card's URI, shown on the page.
    pub uri: String,
}

/// The step the page proposes, counts: below the default following-error limit at rest
/// (MIN_FERROR, 1000 counts), which a step larger than it trips on its first tick.
pub const DEFAULT_STEP: f64 = 500.0;
/// The move the page proposes, counts (two revolutions of the default motor).
pub const DEFAULT_DISTANCE: f64 = 20_000.0;

/// Test answers kept for `GET /api/tests/{id}`.
pub const KEPT_TESTS: usize = 8;

/// The server's state, shared by the handlers.
struct App {
    card: Card,
    scope: Arc<Scope>,
    axis: usize,
    uri: String,
    live: Live,
    /// Held while a test runs (try-locked: a second test is refused, never queued).
    test: tokio::sync::Mutex<()>,
    /// The last tests' answers, as sent, oldest first (at most [`KEPT_TESTS`]).
    kept: Mutex<std::collections::VecDeque<(u64, Arc<str>)>>,
    next_id: std::sync::atomic::AtomicU64,
}

/// An error answer: a status and `{"error", "kind"}`.
struct ApiError(StatusCode, String, Option<String>);

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        (self.0, Json(json!({ "error": self.1, "kind": self.2 }))).into_response()
    }
}

impl From<Error> for ApiError {
    fn from(e: Error) -> Self {
        let status = match e {
            Error::Nack { .. }
            | Error::Refused { .. }
            | Error::NotFinite { .. }
            | Error::NonPositive { .. }
            | Error::BadConfig(_)
            | Error::BadAxis { .. } => StatusCode::UNPROCESSABLE_ENTITY,
            _ => StatusCode::SERVICE_UNAVAILABLE,
        };
        let kind = format!("{:?}", e.kind());
        ApiError(status, e.to_string(), Some(kind))
    }
}

impl From<TestError> for ApiError {
    fn from(e: TestError) -> Self {
        match e {
            TestError::Request(m) => ApiError(StatusCode::BAD_REQUEST, m, None),
            TestError::NotReady(m) => ApiError(StatusCode::CONFLICT, m, None),
            TestError::Capture(m) => ApiError(StatusCode::INTERNAL_SERVER_ERROR, m, None),
            TestError::Aborted(m) => ApiError(StatusCode::UNPROCESSABLE_ENTITY, m, None),
            TestError::Card(e) => e.into(),
        }
    }
}

fn bad_json(r: JsonRejection) -> ApiError {
    ApiError(
        StatusCode::BAD_REQUEST,
        format!(
            "the request is not what this route takes: {}",
            r.body_text()
        ),
        None,
    )
}

/// Run the SDK's blocking `f` off the async workers.
async fn blocking<T: Send + 'static>(
    f: impl FnOnce() -> std::result::Result<T, ApiError> + Send + 'static,
) -> std::result::Result<T, ApiError> {
    tokio::task::spawn_blocking(f).await.unwrap_or_else(|e| {
        Err(ApiError(
            StatusCode::INTERNAL_SERVER_ERROR,
            format!("the request's worker failed: {e}"),
            None,
        ))
    })
}

const INDEX_HTML: &str = include_str!("serve/web/index.html");
const APP_JS: &str = include_str!("serve/web/app.js");
const SERVO_JS: &str = include_str!("serve/web/servo.js");
const BODE_JS: &str = include_str!("serve/web/bode.js");
const STYLE_CSS: &str = include_str!("serve/web/style.css");
const UPLOT_JS: &str = include_str!("serve/web/vendor/uPlot.iife.min.js");
const UPLOT_CSS: &str = include_str!("serve/web/vendor/uPlot.min.css");
const UPLOT_LICENSE: &str = include_str!("serve/web/vendor/uPlot.LICENSE");

fn file(body: &'static str, mime: &'static str) -> Response {
    (
        [
            (header::CONTENT_TYPE, mime),
            (header::CACHE_CONTROL, "no-cache"),
        ],
        body,
    )
        .into_response()
}

async fn info(State(app): State<Arc<App>>) -> Json<serde_json::Value> {
    let i = app.card.info();
    let v = i.firmware_version;
    let band = crate::tuning::Band::default();
    Json(json!({
        "uri": app.uri,
        "axis": app.axis,
        "axes": i.axes,
        "servo_rate_hz": i.servo_rate_hz,
        "firmware": format!("{}.{}.{}", v >> 16, (v >> 8) & 0xff, v & 0xff),
        "band": band,
        "pre_trigger": crate::tuning::run::PRE_TRIGGER,
        "max_capture_s": crate::tuning::run::MAX_CAPTURE,
        "defaults": {
            "step": DEFAULT_STEP,
            "distance": DEFAULT_DISTANCE,
            "limits": Limits::default(),
            // What the PID+FF form starts from on an axis that runs another law.
            "pidff": gains::Pidff::from(&crate::PidffSettings::default()),
        },
        "live": { "card_hz": live::CARD_HZ, "group": live::GROUP },
    }))
}

async fn live_stream(
    State(app): State<Arc<App>>,
) -> Sse<impl futures_util::Stream<Item = std::result::Result<Event, std::convert::Infallible>>> {
    use tokio::sync::broadcast::error::RecvError;
    let rx = app.live.subscribe();
    let events = futures_util::stream::unfold(rx, |mut rx| async move {
        loop {
            let ev = match rx.recv().await {
                Ok(LiveMsg::Samples(j)) => Event::default().event("samples").data(&*j),
                Ok(LiveMsg::Paused(what)) => Event::default()
                    .event("paused")
                    .data(json!({ "for": &*what }).to_string()),
                Ok(LiveMsg::Resumed) => Event::default().event("resumed").data("{}"),
                Ok(LiveMsg::Error(m)) => Event::default()
                    .event("failure")
                    .data(json!({ "error": &*m }).to_string()),
                // A page that fell behind misses batches; the plot shows the gap.
                Err(RecvError::Lagged(_)) => continue,
                Err(RecvError::Closed) => return None,
            };
            return Some((Ok(ev), rx));
        }
    });
    Sse::new(events).keep_alive(KeepAlive::default())
}

/// `POST /api/tests`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TestRequest {
    kind: TestKind,
    distance: f64,
    #[serde(default)]
    limits: Option<Limits>,
    #[serde(default = "yes")]
    enable: bool,
}

fn yes() -> bool {
    true
}

/// A JSON body already serialized.
fn json_body(body: Arc<str>) -> Response {
    (
        [(header::CONTENT_TYPE, "application/json")],
        body.to_string(),
    )
        .into_response()
}

async fn run_one(
    State(app): State<Arc<App>>,
    req: std::result::Result<Json<TestRequest>, JsonRejection>,
) -> std::result::Result<Response, ApiError> {
    let Json(req) = req.map_err(bad_json)?;
    let Ok(_running) = app.test.try_lock() else {
        return Err(ApiError(
            StatusCode::CONFLICT,
            "a test is running: wait for its figures".into(),
            None,
        ));
    };
    let spec = TestSpec {
        kind: req.kind,
        axis: app.axis,
        distance: req.distance,
        limits: req.limits.unwrap_or_default(),
        enable: req.enable,
    };
    let a = app.clone();
    let run: TestRun = blocking(move || {
        let what = match spec.kind {
            TestKind::Step => "step test",
            TestKind::Move => "move test",
        };
        let _lease = a
            .live
            .pause(what)
            .map_err(|m| ApiError(StatusCode::CONFLICT, m, None))?;
        Ok(run_test(&a.card, &a.scope, &spec)?)
    })
    .await?;
    let id = app
        .next_id
        .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let mut v = serde_json::to_value(&run).map_err(|e| {
        ApiError(
            StatusCode::INTERNAL_SERVER_ERROR,
            format!("the test's answer: {e}"),
            None,
        )
    })?;
    v["id"] = json!(id);
    let body: Arc<str> = v.to_string().into();
    let mut kept = app.kept.lock().unwrap_or_else(|e| e.into_inner());
    if kept.len() == KEPT_TESTS {
        kept.pop_front();
    }
    kept.push_back((id, body.clone()));
    drop(kept);
    Ok(json_body(body))
}

/// `GET /api/tests/{id}`: a kept test's answer again (`last`: the newest).
async fn kept_test(
    State(app): State<Arc<App>>,
    axum::extract::Path(which): axum::extract::Path<String>,
) -> std::result::Result<Response, ApiError> {
    let kept = app.kept.lock().unwrap_or_else(|e| e.into_inner());
    let found = match which.as_str() {
        "last" => kept.back(),
        n => match n.parse::<u64>() {
            Ok(id) => kept.iter().find(|(i, _)| *i == id),
            Err(_) => {
                return Err(ApiError(
                    StatusCode::BAD_REQUEST,
                    format!("`{n}` is not a test id (a number, or `last`)"),
                    None,
                ))
            }
        },
    };
    found.map(|(_, b)| json_body(b.clone())).ok_or_else(|| {
        ApiError(
            StatusCode::NOT_FOUND,
            format!("no test {which} (the last {KEPT_TESTS} are kept)"),
            None,
        )
    })
}

/// `POST /api/reset`: MC_Reset of the axis (ErrorStop to Standstill or Disabled), waited for
/// until the card shows it; answers `{"state"}`.
async fn reset_axis(
    State(app): State<Arc<App>>,
) -> std::result::Result<Json<serde_json::Value>, ApiError> {
    blocking(move || {
        let ax = app.card.axis(app.axis)?;
        ax.reset()?;
        let deadline = std::time::Instant::now() + Duration::from_secs(1);
        while ax.status()?.state == crate::AxisState::ErrorStop
            && std::time::Instant::now() < deadline
        {
            std::thread::sleep(Duration::from_millis(2));
        }
        Ok(Json(
            json!({ "state": crate::tuning::run::state_name(&ax)? }),
        ))
    })
    .await
}

async fn get_gains(State(app): State<Arc<App>>) -> std::result::Result<Json<Gains>, ApiError> {
    blocking(move || Ok(gains::get(&app.card, app.axis)?))
        .await
        .map(Json)
}

async fn post_gains(
    State(app): State<Arc<App>>,
    req: std::result::Result<Json<Apply>, JsonRejection>,
) -> std::result::Result<Json<Gains>, ApiError> {
    let Json(change) = req.map_err(bad_json)?;
    blocking(move || Ok(gains::apply(&app.card, app.axis, &change)?))
        .await
        .map(Json)
}

async fn get_filters(State(app): State<Arc<App>>) -> std::result::Result<Json<Filters>, ApiError> {
    blocking(move || Ok(servo_filters::get(&app.card, app.axis)?))
        .await
        .map(Json)
}

async fn post_filters(
    State(app): State<Arc<App>>,
    req: std::result::Result<Json<servo_filters::Change>, JsonRejection>,
) -> std::result::Result<Json<Filters>, ApiError> {
    let Json(change) = req.map_err(bad_json)?;
    blocking(move || {
        servo_filters::apply(&app.card, app.axis, &change).map_err(|e| match e {
            FilterError::Request(m) => ApiError(StatusCode::BAD_REQUEST, m, None),
            FilterError::Card(e) => e.into(),
        })
    })
    .await
    .map(Json)
}

/// `POST /api/freq`: a frequency sweep of the page's axis, one test at a time (a step or move
/// test running: 409, and a sweep holds off a test the same way).
async fn post_freq(
    State(app): State<Arc<App>>,
    req: std::result::Result<Json<sweep::SweepRequest>, JsonRejection>,
) -> std::result::Result<Json<serde_json::Value>, ApiError> {
    let Json(req) = req.map_err(bad_json)?;
    let Ok(_running) = app.test.try_lock() else {
        return Err(ApiError(
            StatusCode::CONFLICT,
            "a test or a sweep is running: wait for its end".into(),
            None,
        ));
    };
    let a = app.clone();
    blocking(move || Ok(sweep::run(&a.card, a.axis, &req)?))
        .await
        .map(Json)
}

/// A route of the server. The router is built from [`ROUTES`] alone and [`guard`] sees every
/// request before any route does (and the fallback's 404s), so no route escapes the checks.
pub struct Route {
    /// The path, in axum's syntax (`{which}`: a path parameter).
    pub path: &'static str,
    /// The methods it answers (a GET route answers HEAD too).
    pub methods: &'static [&'static str],
    /// One of the page's own files: GET and HEAD need no token (the files hold no secret).
    pub file: bool,
    handler: fn() -> MethodRouter<Arc<App>>,
}

/// Every route of the server: the page's files, then the API.
pub const ROUTES: &[Route] = &[
    Route {
        path: "/",
        methods: &["GET"],
        file: true,
        handler: || get(|| async { file(INDEX_HTML, "text/html; charset=utf-8") }),
    },
    Route {
        path: "/app.js",
        methods: &["GET"],
        file: true,
        handler: || get(|| async { file(APP_JS, "text/javascript; charset=utf-8") }),
    },
    Route {
        path: "/servo.js",
        methods: &["GET"],
        file: true,
        handler: || get(|| async { file(SERVO_JS, "text/javascript; charset=utf-8") }),
    },
    Route {
        path: "/bode.js",
        methods: &["GET"],
        file: true,
        handler: || get(|| async { file(BODE_JS, "text/javascript; charset=utf-8") }),
    },
    Route {
        path: "/style.css",
        methods: &["GET"],
        file: true,
        handler: || get(|| async { file(STYLE_CSS, "text/css; charset=utf-8") }),
    },
    Route {
        path: "/vendor/uPlot.iife.min.js",
        methods: &["GET"],
        file: true,
        handler: || get(|| async { file(UPLOT_JS, "text/javascript; charset=utf-8") }),
    },
    Route {
        path: "/vendor/uPlot.min.css",
        methods: &["GET"],
        file: true,
        handler: || get(|| async { file(UPLOT_CSS, "text/css; charset=utf-8") }),
    },
    Route {
        path: "/vendor/uPlot.LICENSE",
        methods: &["GET"],
        file: true,
        handler: || get(|| async { file(UPLOT_LICENSE, "text/plain; charset=utf-8") }),
    },
    Route {
        path: "/api/info",
        methods: &["GET"],
        file: false,
        handler: || get(info),
    },
    Route {
        path: LIVE,
        methods: &["GET"],
        file: false,
        handler: || get(live_stream),
    },
    Route {
        path: "/api/tests",
        methods: &["POST"],
        file: false,
        handler: || post(run_one),
    },
    Route {
        path: "/api/tests/{which}",
        methods: &["GET"],
        file: false,
        handler: || get(kept_test),
    },
    Route {
        path: "/api/gains",
        methods: &["GET", "POST"],
        file: false,
        handler: || get(get_gains).post(post_gains),
    },
    Route {
        path: "/api/filters",
        methods: &["GET", "POST"],
        file: false,
        handler: || get(get_filters).post(post_filters),
    },
    Route {
        path: "/api/freq",
        methods: &["POST"],
        file: false,
        handler: || post(post_freq),
    },
    Route {
        path: "/api/reset",
        methods: &["POST"],
        file: false,
        handler: || post(reset_axis),
    },
];

/// The event stream's path: the one route that also takes its token as `?token=`.
pub const LIVE: &str = "/api/live";

/// Anything else: 404 (behind the guard as every route).
async fn not_found() -> ApiError {
    ApiError(
        StatusCode::NOT_FOUND,
        "no such page or API route".into(),
        None,
    )
}

fn router(app: Arc<App>, guard: Arc<guard::Guard>) -> Router {
    let mut r = Router::new();
    for route in ROUTES {
        r = r.route(route.path, (route.handler)());
    }
    r.fallback(not_found)
        .with_state(app)
        .layer(axum::middleware::from_fn_with_state(guard, guard::check))
}

/// SIGINT or SIGTERM.
async fn shutdown_signal() {
    use tokio::signal::unix::{signal, SignalKind};
    match signal(SignalKind::terminate()) {
        Ok(mut term) => {
            tokio::select! {
                _ = tokio::signal::ctrl_c() => {}
                _ = term.recv() => {}
            }
        }
        Err(_) => {
            let _ = tokio::signal::ctrl_c().await;
        }
    }
}

fn io_error(context: String) -> impl FnOnce(std::io::Error) -> Error {
    move |source| Error::Io { context, source }
}

/// Serve the page for `card` until SIGINT or SIGTERM. Prints `listening on
/// http://ADDR/#token=TOKEN` (one line, flushed) once the port is open: the address to open,
/// with the token the page takes from it. A listening address beyond loopback is warned of on
/// stderr (the page is then reachable from the network, in clear text).
pub fn serve(card: &Card, opts: &Options) -> Result<String> {
    card.axis(opts.axis)?; // an axis the card has not: refused before anything listens
    let token = match &opts.token {
        Some(t) => t.clone(),
        None => Token::generate().map_err(io_error(
            "mcctl serve: a token from the OS's random source".into(),
        ))?,
    };
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(io_error("mcctl serve: the async runtime".into()))?;
    let scope = Arc::new(card.scope());
    let live = Live::start(card.clone(), scope.clone(), opts.axis)
        .map_err(io_error("mcctl serve: the live stream's thread".into()))?;
    let app = Arc::new(App {
        card: card.clone(),
        scope,
        axis: opts.axis,
        uri: opts.uri.clone(),
        live,
        test: tokio::sync::Mutex::new(()),
        kept: Mutex::new(std::collections::VecDeque::new()),
        next_id: std::sync::atomic::AtomicU64::new(1),
    });
    let served = rt.block_on(async {
        let listener = tokio::net::TcpListener::bind(opts.listen)
            .await
            .map_err(io_error(format!("mcctl serve: listen on {}", opts.listen)))?;
        let addr = listener
            .local_addr()
            .map_err(io_error("mcctl serve: the listening address".into()))?;
        let guard = Arc::new(guard::Guard {
            token: token.clone(),
            listen: addr,
            public: ROUTES.iter().filter(|r| r.file).map(|r| r.path).collect(),
            live: LIVE,
        });
        if !addr.ip().to_canonical().is_loopback() {
            let mut err = std::io::stderr().lock();
            let _ = writeln!(
                err,
                "mcctl serve: warning: {addr} is not a loopback address: the tuning page, which \
                 moves axis {axis}, is reachable from the network, without TLS (the token and \
                 everything else cross it in clear text; whoever reads the token drives the \
                 card).{generated} Browse to it by IP address: it answers no host name but \
                 localhost. Prefer --listen 127.0.0.1:{port} and an SSH tunnel (ssh -L \
                 {port}:127.0.0.1:{port} THIS-HOST).",
                axis = opts.axis,
                port = addr.port(),
                generated = if opts.token.is_none() {
                    " The token was generated for this run (--token sets one)."
                } else {
                    ""
                },
            );
        }
        let mut out = std::io::stdout().lock();
        let _ = writeln!(out, "listening on http://{addr}/#token={}", token.as_str());
        let _ = out.flush();
        drop(out);
        let service =
            router(app.clone(), guard).into_make_service_with_connect_info::<guard::Local>();
        tokio::select! {
            r = axum::serve(listener, service) => {
                r.map_err(io_error("mcctl serve".into()))
            }
            _ = shutdown_signal() => Ok(()),
        }
    });
    // Connections still open (a page's live stream) end with the runtime; a test still
    // running is given a moment, then the card closes under it.
    app.live.stop();
    rt.shutdown_timeout(Duration::from_secs(2));
    served.map(|()| String::new())
}
