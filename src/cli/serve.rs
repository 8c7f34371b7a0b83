//! `mcctl serve`: the tuning page for one axis, a local web server ([`crate::serve`]) until
//! interrupted.

use super::on_card;
use clap::Args as ClapArgs;
use std::process::ExitCode;

/// `mcctl serve`.
#[derive(ClapArgs)]
pub struct Args {
    /// Address and port to listen on (port 0: any free port). An address beyond loopback
    /// (0.0.0.0, a network interface's) makes the page reachable from the network, without
    /// TLS: mcctl warns so on stderr.
    #[arg(long, default_value = "127.0.0.1:8080")]
    pub listen: std::net::SocketAddr,
    /// The token the API requires (16 to 256 characters of A-Z a-z 0-9 - . _ ~), e.g. to
    /// keep one address across restarts; by default a new one of 128 random bits each
    /// run. Other users of this machine can read a command line: prefer the default.
    #[arg(long, value_name = "TOKEN")]
    pub token: Option<crate::serve::Token>,
    /// The axis the page tunes.
    #[arg(long, default_value_t = 0)]
    pub axis: usize,
}

/// Serve until interrupted.
pub fn run(uri: &str, a: Args) -> ExitCode {
    let opts = crate::serve::Options {
        listen: a.listen,
        token: a.token,
        axis: a.axis,
        uri: uri.to_string(),
    };
    on_card(uri, |c| crate::serve::serve(c, &opts))
}
