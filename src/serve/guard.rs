//! Who may use the tuning page: one middleware (`check`) in front of the whole router, its
//! fallback included, so that no route can be missed. A request is answered only when all of
//! these hold, in this order:
//!
//! 1. **Host** (403 otherwise): exactly one `Host` header naming this server with its port:
//!    the address the request came in on (an IP literal, `127.0.0.1:PORT`, `[::1]:PORT`), the
//!    listening address itself, or `localhost:PORT` when the request came in on a loopback
//!    address. Any other name (`evil.example:PORT`, resolved to 127.0.0.1 by a page's DNS
//!    rebinding) and a missing Host are refused. A request line in absolute form must name
//!    the same server.
//! 2. **Origin** (403): a request other than GET or HEAD carries an `Origin` of this same
//!    origin (`http://` and the Host it was sent to); a GET or HEAD may leave it out (a page's
//!    own reads do) but one it carries is held to the same rule. `null`, another scheme, host
//!    or port are refused, and no CORS header is ever sent, so a browser lets no other page
//!    read an answer.
//! 3. **Token** (403): everything but a GET or HEAD of the page's files carries the server's
//!    token ([`Token`]) as `Authorization: Bearer TOKEN`, or, for the event stream alone (a
//!    browser's `EventSource` sets no header), as `?token=TOKEN`. It is compared in constant
//!    time.
//! 4. **Content type** (415): a request other than GET or HEAD says `Content-Type:
//!    application/json` (a cross-site form or `text/plain` "simple request" cannot).
//!
//! Refusals are `{"error", "kind": null}` as every other error of the API. Every answer also
//! says `X-Content-Type-Options: nosniff` and that no other page may frame it
//! (`X-Frame-Options: DENY`, `Content-Security-Policy: frame-ancestors 'none'`).

use axum::extract::connect_info::{ConnectInfo, Connected};
use axum::extract::{Request, State};
use axum::http::{header, HeaderMap, HeaderValue, Method, StatusCode};
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde_json::json;
use std::net::{IpAddr, Ipv4Addr, Ipv6Addr, SocketAddr};
use std::sync::Arc;

/// The server's secret: every API request carries it. Generated from the OS's random source
/// for each `mcctl serve` unless given (`--token`); printed in the address the server prints
/// (`http://ADDR/#token=TOKEN`: a fragment, which the browser never sends in a request line
/// or a `Referer`). Its `Debug` does not show it.
#[derive(Clone)]
pub struct Token(String);

impl Token {
    /// The shortest token accepted from the command line.
    pub const MIN_LEN: usize = 16;
    /// The longest (it travels in a header and a URL).
    pub const MAX_LEN: usize = 256;
    /// Random bytes in a generated token (128 bits), written as 32 hex digits.
    pub const RANDOM_BYTES: usize = 16;

    /// A new token from the OS's random source (`getrandom`).
    pub fn generate() -> std::io::Result<Token> {
        let mut b = [0u8; Self::RANDOM_BYTES];
        getrandom::fill(&mut b)?;
        Ok(Token(b.iter().map(|x| format!("{x:02x}")).collect()))
    }

    /// The token as it travels.
    pub fn as_str(&self) -> &str {
        &self.0
    }

    /// Whether `given` is this token, in time independent of where they differ.
    pub fn matches(&self, given: &[u8]) -> bool {
        let mine = self.0.as_bytes();
        if mine.len() != given.len() {
            return false;
        }
        let diff = mine.iter().zip(given).fold(0u8, |d, (a, b)| d | (a ^ b));
        std::hint::black_box(diff) == 0
    }
}

impl std::fmt::Debug for Token {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Token(<hidden>)")
    }
}

impl std::str::FromStr for Token {
    type Err = String;

    /// A token given on the command line: 16 to 256 characters from `A-Z a-z 0-9 - . _ ~`
    /// (they travel unescaped in a URL and a header).
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = s
            .chars()
            .find(|c| !(c.is_ascii_alphanumeric() || "-._~".contains(*c)));
        if let Some(c) = bad {
            return Err(format!(
                "the token may hold only A-Z, a-z, 0-9, `-`, `.`, `_` and `~` (it travels in a \
                 URL and a header), not {c:?}"
            ));
        }
        let n = s.chars().count();
        if !(Self::MIN_LEN..=Self::MAX_LEN).contains(&n) {
            return Err(format!(
                "the token has {n} characters: it needs {} to {} (leave --token out and \
                 mcctl serve generates one of {} random bits)",
                Self::MIN_LEN,
                Self::MAX_LEN,
                Self::RANDOM_BYTES * 8
            ));
        }
        Ok(Token(s.to_string()))
    }
}

/// The address a connection came in on (its local end), for the Host check.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Local(pub Option<SocketAddr>);

impl Connected<axum::serve::IncomingStream<'_, tokio::net::TcpListener>> for Local {
    fn connect_info(stream: axum::serve::IncomingStream<'_, tokio::net::TcpListener>) -> Self {
        Local(stream.io().local_addr().ok())
    }
}

/// What [`check`] checks against.
pub(crate) struct Guard {
    pub token: Token,
    /// The bound address (its port resolved).
    pub listen: SocketAddr,
    /// Paths whose GET and HEAD need no token: the page's own files.
    pub public: Vec<&'static str>,
    /// The event stream: the one route that takes the token as `?token=`.
    pub live: &'static str,
}

/// A host of a `Host` or `Origin`: an IP literal or a name (lower case).
#[derive(Debug, Clone, PartialEq, Eq)]
enum Name {
    Ip(IpAddr),
    Dns(String),
}

/// `host[:port]` (port 80 when left out, as HTTP's default); None: not an authority.
fn authority(s: &str) -> Option<(Name, u16)> {
    let (host, port) = if let Some(rest) = s.strip_prefix('[') {
        let (v6, after) = rest.split_once(']')?;
        let ip: Ipv6Addr = v6.parse().ok()?;
        (Name::Ip(IpAddr::V6(ip)), after)
    } else {
        let (h, after) = match s.find(':') {
            Some(i) => (&s[..i], &s[i..]),
            None => (s, ""),
        };
        let ok = !h.is_empty()
            && h.bytes()
                .all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'.');
        if !ok {
            return None;
        }
        match h.parse::<Ipv4Addr>() {
            Ok(ip) => (Name::Ip(IpAddr::V4(ip)), after),
            Err(_) => (Name::Dns(h.to_ascii_lowercase()), after),
        }
    };
    let port = match port {
        "" => 80,
        p => {
            let digits = p.strip_prefix(':')?;
            if digits.is_empty() || digits.len() > 5 || !digits.bytes().all(|b| b.is_ascii_digit())
            {
                return None;
            }
            digits.parse().ok()?
        }
    };
    Some((host, port))
}

/// Whether `host:port` names this server for a request that came in on `local`.
fn names_this_server(host: &Name, port: u16, local: SocketAddr, listen: SocketAddr) -> bool {
    if port != local.port() {
        return false;
    }
    let local_ip = local.ip().to_canonical();
    match host {
        Name::Ip(ip) => {
            let ip = ip.to_canonical();
            ip == local_ip || ip == listen.ip().to_canonical()
        }
        Name::Dns(n) => n == "localhost" && local_ip.is_loopback(),
    }
}

fn refuse(status: StatusCode, message: String) -> Response {
    (status, Json(json!({ "error": message, "kind": null }))).into_response()
}

/// The one value of header `name`; Err: more than one, or not visible ASCII.
fn one<'a>(h: &'a HeaderMap, name: &header::HeaderName) -> Result<Option<&'a str>, String> {
    let mut all = h.get_all(name).iter();
    let (first, second) = (all.next(), all.next());
    match (first, second) {
        (None, _) => Ok(None),
        (Some(_), Some(_)) => Err(format!("more than one {name} header")),
        (Some(v), None) => v
            .to_str()
            .map(Some)
            .map_err(|_| format!("a {name} header that is not plain ASCII")),
    }
}

/// The token a request carries: `Authorization: Bearer TOKEN`, or `?token=TOKEN` where
/// `query_ok`. Err: why there is none.
fn carried(req: &Request, query_ok: bool) -> Result<&str, String> {
    if let Some(auth) = one(req.headers(), &header::AUTHORIZATION)? {
        let (scheme, t) = auth.trim().split_once(' ').unwrap_or((auth, ""));
        if !scheme.eq_ignore_ascii_case("bearer") || t.trim().is_empty() {
            return Err("an Authorization header that is not `Bearer TOKEN`".into());
        }
        return Ok(t.trim());
    }
    if query_ok {
        let mut found = req
            .uri()
            .query()
            .unwrap_or("")
            .split('&')
            .filter_map(|kv| kv.strip_prefix("token="));
        if let (Some(t), None) = (found.next(), found.next()) {
            return Ok(t);
        }
    }
    Err("no token".into())
}

/// The middleware: answer the request only if it passes every check of this module.
pub(crate) async fn check(State(g): State<Arc<Guard>>, req: Request, next: Next) -> Response {
    let mut res = match admit(&g, &req) {
        Ok(()) => next.run(req).await,
        Err((status, message)) => refuse(status, message),
    };
    let h = res.headers_mut();
    h.insert(
        header::X_CONTENT_TYPE_OPTIONS,
        HeaderValue::from_static("nosniff"),
    );
    h.insert(header::X_FRAME_OPTIONS, HeaderValue::from_static("DENY"));
    h.insert(
        header::CONTENT_SECURITY_POLICY,
        HeaderValue::from_static("frame-ancestors 'none'"),
    );
    res
}

fn admit(g: &Guard, req: &Request) -> Result<(), (StatusCode, String)> {
    let forbidden = |m: String| (StatusCode::FORBIDDEN, m);
    let local = req
        .extensions()
        .get::<ConnectInfo<Local>>()
        .and_then(|c| c.0 .0)
        .unwrap_or(g.listen);
    let port = local.port();
    let expected = if local.ip().to_canonical().is_loopback() {
        format!("{local} or localhost:{port}")
    } else {
        local.to_string()
    };

    // 1. Host.
    let headers = req.headers();
    let host = one(headers, &header::HOST)
        .map_err(|m| forbidden(format!("refused: {m}")))?
        .ok_or_else(|| {
            forbidden(format!(
                "refused: no Host header (this server answers only requests addressed to \
                 {expected})"
            ))
        })?;
    let named = authority(host).filter(|(h, p)| names_this_server(h, *p, local, g.listen));
    let Some((host_name, host_port)) = named else {
        return Err(forbidden(format!(
            "refused: the Host `{host}` does not name this server, which answers only \
             {expected} (a page of another site, its name pointed at this address, is refused \
             so)"
        )));
    };
    if let Some(a) = req.uri().authority() {
        if authority(a.as_str()) != Some((host_name.clone(), host_port)) {
            return Err(forbidden(format!(
                "refused: the request line names `{a}`, the Host header `{host}`"
            )));
        }
    }

    // 2. Origin.
    let safe = req.method() == Method::GET || req.method() == Method::HEAD;
    let origin = one(headers, &header::ORIGIN).map_err(|m| forbidden(format!("refused: {m}")))?;
    match origin {
        None if safe => {}
        None => {
            return Err(forbidden(format!(
                "refused: a {} needs an Origin header of this page's origin (http://{host})",
                req.method()
            )))
        }
        Some(o) => {
            let same = o
                .get(..7)
                .filter(|s| s.eq_ignore_ascii_case("http://"))
                .and_then(|_| authority(&o[7..]))
                == Some((host_name, host_port));
            if !same {
                return Err(forbidden(format!(
                    "refused: a request from the origin `{o}`; this server answers only its own \
                     page (http://{host})"
                )));
            }
        }
    }

    // 3. Token.
    let path = req.uri().path();
    let public = safe && g.public.contains(&path);
    if !public {
        let query_ok = safe && path == g.live;
        let given = carried(req, query_ok).map_err(|why| {
            forbidden(format!(
                "refused: {why}: {} {path} needs this server's token (in the address \
                 `mcctl serve` printed, after #token=), as `Authorization: Bearer TOKEN`",
                req.method()
            ))
        })?;
        if !g.token.matches(given.as_bytes()) {
            return Err(forbidden(
                "refused: the token is not this server's (each `mcctl serve` has its own, \
                 printed in its address after #token=, unless given with --token)"
                    .into(),
            ));
        }
    }

    // 4. Content type.
    if !safe {
        let ct = one(headers, &header::CONTENT_TYPE)
            .map_err(|m| (StatusCode::UNSUPPORTED_MEDIA_TYPE, format!("refused: {m}")))?;
        let json = ct.is_some_and(|c| {
            c.split(';')
                .next()
                .is_some_and(|t| t.trim().eq_ignore_ascii_case("application/json"))
        });
        if !json {
            return Err((
                StatusCode::UNSUPPORTED_MEDIA_TYPE,
                format!(
                    "refused: a {} takes `Content-Type: application/json`, not {}",
                    req.method(),
                    ct.map_or("none".to_string(), |c| format!("`{c}`"))
                ),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sa(s: &str) -> SocketAddr {
        s.parse().unwrap()
    }

    fn names(host: &str, local: &str, listen: &str) -> bool {
        authority(host).is_some_and(|(h, p)| names_this_server(&h, p, sa(local), sa(listen)))
    }

    #[test]
    fn hosts_name_the_listening_address_or_localhost_with_the_port() {
        let (l, b) = ("127.0.0.1:8080", "127.0.0.1:8080");
        assert!(names("127.0.0.1:8080", l, b));
        assert!(names("localhost:8080", l, b));
        assert!(names("LocalHost:8080", l, b));
        for bad in [
            "evil.example:8080",
            "localhost.evil.example:8080",
            "localhost.:8080",
            "localhost",
            "127.0.0.1",
            "127.0.0.1:8081",
            "localhost:8081",
            "127.1:8080",
            "127.0.0.2:8080",
            "[::1]:8080",
            "user@127.0.0.1:8080",
            "127.0.0.1:8080:8080",
            "127.0.0.1:+8080",
            "127.0.0.1:",
            ":8080",
            "",
        ] {
            assert!(!names(bad, l, b), "{bad}");
        }
        // IPv6 loopback.
        let (l6, b6) = ("[::1]:9000", "[::1]:9000");
        assert!(names("[::1]:9000", l6, b6));
        assert!(names("[0:0:0:0:0:0:0:1]:9000", l6, b6));
        assert!(names("localhost:9000", l6, b6));
        assert!(!names("127.0.0.1:9000", l6, b6));
        assert!(!names("[::1]", l6, b6));
        // Port 80: HTTP's default, left out by browsers.
        assert!(names("localhost", "127.0.0.1:80", "127.0.0.1:80"));
        // All interfaces: the address the request came in on (or the listening one itself);
        // localhost only over loopback.
        let any = "0.0.0.0:7000";
        assert!(names("192.168.1.5:7000", "192.168.1.5:7000", any));
        assert!(names("0.0.0.0:7000", "192.168.1.5:7000", any));
        assert!(!names("localhost:7000", "192.168.1.5:7000", any));
        assert!(!names("192.168.1.6:7000", "192.168.1.5:7000", any));
        assert!(!names("mybox.lan:7000", "192.168.1.5:7000", any));
        assert!(names("localhost:7000", "127.0.0.1:7000", any));
        // A v4 client of a dual-stack socket.
        assert!(names(
            "192.168.1.5:7000",
            "[::ffff:192.168.1.5]:7000",
            "[::]:7000"
        ));
    }

    #[test]
    fn tokens_compare_whole_and_generated_ones_differ() {
        let t: Token = "abcdefghijklmnop".parse().unwrap();
        assert!(t.matches(b"abcdefghijklmnop"));
        assert!(!t.matches(b"abcdefghijklmnoq"));
        assert!(!t.matches(b"abcdefghijklmno"));
        assert!(!t.matches(b"abcdefghijklmnopq"));
        assert!(!t.matches(b""));
        assert_eq!(format!("{t:?}"), "Token(<hidden>)");
        let (a, b) = (Token::generate().unwrap(), Token::generate().unwrap());
        assert_eq!(a.as_str().len(), 32);
        assert!(a.as_str().bytes().all(|c| c.is_ascii_hexdigit()));
        assert_ne!(a.as_str(), b.as_str());
        let short = "abc".parse::<Token>().unwrap_err();
        assert!(short.contains("3 characters"), "{short}");
        let bad = "abcdefghijklmnop qrs".parse::<Token>().unwrap_err();
        assert!(bad.contains("' '"), "{bad}");
        assert!("a".repeat(257).parse::<Token>().is_err());
        assert!("a".repeat(256).parse::<Token>().is_ok());
    }
}
