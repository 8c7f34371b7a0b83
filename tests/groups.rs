//! Axes groups on the stepped emulated card: states, interpolation geometry, filters, nacks.
mod common;

use common::stepped_card;
use motioncard::{
    AccDec, ArcSpec, AxisState, Card, ErrorKind, FilterKind, FilterSettings, GroupSettings,
    GroupState, Interpolator, MoveLimits, MoveOptions, PathLimits, Plane,
};
use std::time::Duration;

const T: Duration = Duration::from_secs(30);

fn lim() -> PathLimits {
    PathLimits::new(50_000.0, 5e5, 5e7)
}

/// A card with axes `axes` enabled and group 0 over them, enabled.
fn group_card(axes: &[usize], accdec: AccDec) -> (Card, motioncard::Group) {
    let card = stepped_card();
    for &a in axes {
        card.axis(a).unwrap().enable().unwrap();
    }
    let g = card.group(0).unwrap();
    g.configure(&GroupSettings {
        accdec,
        ..GroupSettings::new(axes)
    })
    .unwrap();
    g.enable().unwrap();
    (card, g)
}

fn cmd(card: &Card, a: usize) -> f64 {
    card.axis(a).unwrap().status().unwrap().raw.cmd_pos
}

#[test]
fn linear_move_follows_the_line_and_ends_on_target() {
    for accdec in [AccDec::Pre, AccDec::Post, AccDec::Both] {
        let (card, g) = group_card(&[0, 1, 2], accdec);
        let sim = card.sim().unwrap();
        let target = [30_000.0, -40_000.0, 12_000.0];
        let len = (target.iter().map(|x| x * x).sum::<f64>()).sqrt();
        let m = g
            .move_linear(&target, &lim(), MoveOptions::default())
            .unwrap();
        let mut worst: f64 = 0.0;
        let mut ticks = 0;
        while g.status().unwrap().0 == GroupState::Moving && ticks < 200_000 {
            sim.step(1);
            ticks += 1;
            let p: Vec<f64> = (0..3).map(|a| cmd(&card, a)).collect();
            // Distance of the commanded point from the line through 0 and target.
            let along: f64 = p.iter().zip(&target).map(|(x, t)| x * t).sum::<f64>() / len;
            let off = p
                .iter()
                .zip(&target)
                .map(|(x, t)| (x - along * t / len).powi(2))
                .sum::<f64>()
                .sqrt();
            worst = worst.max(off);
        }
        m.wait(T).unwrap();
        for (a, t) in target.iter().enumerate() {
            assert_eq!(cmd(&card, a), *t, "{accdec:?}: commanded end of axis {a}");
            let act = card.axis(a).unwrap().status().unwrap().actual_position;
            assert!((act - t).abs() <= 1.0, "{accdec:?}: axis {a} at {act}");
        }
        // Linear interpolation through any filter has no path error beyond rounding (Kim §4).
        assert!(
            worst < 1e-6,
            "{accdec:?}: commanded path left the line by {worst} counts"
        );
        for a in 0..3 {
            assert_eq!(
                card.axis(a).unwrap().status().unwrap().state,
                AxisState::Standstill
            );
        }
    }
}
