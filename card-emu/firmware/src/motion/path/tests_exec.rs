//! The look-ahead's envelope and blocks (`exec.rs`): what a walk may pass without testing
//! each piece, against testing each.

use super::*;
use crate::testkit::rng::Rng;

/// A block of up to BLOCK segments as `append` enters them: each segment's geometric and
/// feed caps at its start x (from the block's start), the block's keys min(c² + 2·A_t·x).
fn block(rng: &mut Rng, at: f64) -> (Block, Vec<(f64, f64, f64)>) {
    let mut b = Block {
        geo: f64::INFINITY,
        feed: f64::INFINITY,
        len: 0.0,
        stop: false,
        kg: f64::INFINITY,
        kf: f64::INFINITY,
        lim: Lim::NONE,
    };
    let mut segs = vec![];
    for _ in 0..rng.int(1, BLOCK) {
        let (g, f) = (rng.log_uniform(1e2, 1e6), rng.log_uniform(1e2, 1e6));
        let x = b.len;
        b.len += rng.log_uniform(1.0, 1e4);
        b.geo = b.geo.min(g);
        b.feed = b.feed.min(f);
        b.kg = b.kg.min(g * g + 2.0 * at * x);
        b.kf = b.kf.min(f * f + 2.0 * at * x);
        segs.push((g, f, x));
    }
    (b, segs)
}

fn envelope(rng: &mut Rng, at: f64) -> Envelope {
    let v = rng.log_uniform(1e2, 1e6);
    Envelope {
        theta: v * v * rng.uniform(0.5, 3.0),
        // a halt may brake harder or softer than the rate the keys were made with
        dm: at * rng.uniform(0.2, 1.5),
        step: v * 1e-4 * rng.uniform(0.0, 1.0),
    }
}

#[test]
fn a_block_passed_by_its_keys_holds_no_piece_the_envelope_would_test() {
    let mut rng = Rng::new(0xb10c);
    let (mut passed, mut failed) = (0, 0);
    for _ in 0..200_000 {
        let at = rng.log_uniform(1e4, 1e8);
        let (b, segs) = block(&mut rng, at);
        let env = envelope(&mut rng, at);
        let ovr = rng.uniform(0.0, 2.0);
        let d = rng.log_uniform(1.0, 1e6);
        let low = env.block_low(&b, ovr, at);
        if low >= 0.0 && env.clears(low, d) {
            passed += 1;
            // every piece (a blend and a body share their segment's start or come after
            // it) clears on its own
            for &(g, f, x) in &segs {
                let raw = g.min(f * ovr);
                for extra in [0.0, rng.uniform(0.0, 1e3)] {
                    assert!(
                        env.clears(raw * raw, d + x + extra),
                        "block {b:?} at {d}, piece ({g}, {f}) at {x}: {env:?}, ovr {ovr}"
                    );
                }
            }
        } else {
            failed += 1;
        }
    }
    // the test sees both outcomes
    assert!(
        passed > 10_000 && failed > 10_000,
        "{passed} passed, {failed} not"
    );
}

#[test]
fn clears_all_covers_every_piece_with_a_key_at_least_its_bound() {
    let mut rng = Rng::new(0xc1ea);
    let mut seen = 0;
    for _ in 0..200_000 {
        let at = rng.log_uniform(1e4, 1e8);
        let env = envelope(&mut rng, at);
        let c = rng.log_uniform(1.0, 1e6);
        let d = rng.log_uniform(1e-3, 1e6);
        let key = c * c + 2.0 * env.dm * d;
        let far = rng.log_uniform(1.0, 1e9);
        let low = key * rng.uniform(0.5, 1.0);
        if env.clears_all(low, far) {
            seen += 1;
            assert!(env.clears(c * c, d), "{env:?} c {c} d {d} low {low}");
        }
    }
    assert!(seen > 10_000);
}
