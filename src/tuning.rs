//! Tuning figures: what a step or a move did, measured from the card's scope samples.
//!
//! [`figures`] takes one capture ([`Response`]: per sample its time, the commanded position,
//! the actual position and the following error, one servo tick per sample) and measures:
//!
//! | figure | definition |
//! |---|---|
//! | step `S` | the commanded position's last value minus its first (`x1 − x0`) |
//! | command start `t0` | the time of the first sample whose command differs from `x0` |
//! | rise time | from the actual's first crossing of `x0 + 10 % S` to its first crossing of `x0 + 90 % S`, each crossing interpolated linearly between the two samples around it |
//! | overshoot | the actual's largest excursion beyond `x1` (in the direction of `S`) after `t0`, in % of `|S|`; 0 when it never passes `x1` |
//! | settling band | `±max(2 % · |S|, 2 counts)` around `x1` ([`Band::default`]) |
//! | settling time | from `t0` until the actual enters the band for good: after the last sample outside it, the crossing of its edge interpolated between that sample and the next; none when the last sample is outside |
//! | peak following error | the largest `|following error|` of any sample, with its time |
//!
//! Rise time and settling time are measured from the samples, so their resolution is the
//! interpolation between two servo ticks; the command start is a sample (the first tick
//! whose command has moved). The figures do not depend on where the capture's trigger was,
//! only on the samples.
//!
//! The card side (arming the scope, running the step or the move, capturing until settled)
//! is [`run`]; the gains the page shows and applies are [`gains`], the servo output's filters
//! [`servo_filters`], the frequency sweep it runs [`sweep`].

pub mod gains;
pub mod run;
pub mod servo_filters;
pub mod sweep;

use serde::Serialize;

/// One capture, sample by sample (equal lengths): time in seconds, positions and following
/// error in counts.
#[derive(Debug, Clone, Copy)]
pub struct Response<'a> {
    /// The samples' times, s, increasing.
    pub t: &'a [f64],
    /// Commanded position.
    pub cmd: &'a [f64],
    /// Actual position.
    pub act: &'a [f64],
    /// Following error (commanded − actual), as the card computed it.
    pub ferr: &'a [f64],
}

/// The settling band: `±max(fraction · |S|, min)` around the final command.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Band {
    /// Fraction of the step, e.g. 0.02.
    pub fraction: f64,
    /// The smallest half-width, counts (the encoder's resolution makes a band of a fraction of
    /// a count meaningless).
    pub min: f64,
}

impl Default for Band {
    /// ±2 % of the step, at least ±2 counts.
    fn default() -> Self {
        Self {
            fraction: 0.02,
            min: 2.0,
        }
    }
}

impl Band {
    /// The band's half-width for a step of `step` counts.
    pub fn half_width(&self, step: f64) -> f64 {
        (self.fraction * step.abs()).max(self.min)
    }
}

/// What [`figures`] measured. Times in seconds, positions in counts.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Figures {
    /// The commanded position before the step or move, `x0`.
    pub start: f64,
    /// The commanded position at the end, `x1`.
    pub target: f64,
    /// `x1 − x0`.
    pub step: f64,
    /// Index of the first sample whose command differs from `x0`.
    pub start_index: usize,
    /// Its time, `t0`.
    pub start_time: f64,
    /// Time of the first sample whose command is `x1` for good (the command's end).
    pub command_end_time: f64,
    /// 10 % → 90 % of the step; `None` if the actual never reached 90 %.
    pub rise_time: Option<f64>,
    /// Largest excursion beyond `x1` after `t0`, % of `|S|` (0 when none).
    pub overshoot_pct: f64,
    /// The settling band's half-width, counts.
    pub band: f64,
    /// From `t0` until the actual stays within the band; `None` if the last sample is
    /// outside it.
    pub settling_time: Option<f64>,
    /// How long the capture went on after the actual settled (the evidence that it stays).
    pub settled_for: Option<f64>,
    /// Largest `|following error|`.
    pub peak_following_error: f64,
    /// The time of that sample.
    pub peak_following_error_time: f64,
    /// The actual position of the last sample.
    pub final_actual: f64,
}

/// Why [`figures`] could not measure a capture.
#[derive(Debug, Clone, PartialEq)]
pub enum FigureError {
    /// No samples, or the channels have different lengths.
    Shape(String),
    /// A value is NaN or infinite.
    NotFinite(&'static str, usize),
    /// Times do not increase.
    Time(usize),
    /// The command ends where it started: there is no step to measure.
    NoStep,
}

impl std::fmt::Display for FigureError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FigureError::Shape(s) => write!(f, "the capture's channels do not fit: {s}"),
            FigureError::NotFinite(what, i) => write!(f, "sample {i}: {what} is not finite"),
            FigureError::Time(i) => write!(f, "sample {i}: time does not increase"),
            FigureError::NoStep => write!(f, "the command ends where it started: no step"),
        }
    }
}

impl std::error::Error for FigureError {}

/// Linear interpolation of the time at which `y` crosses `level`, between samples `i − 1`
/// and `i` (or `t[i]` when `i` is the first sample or the two are equal).
fn crossing(t: &[f64], y: impl Fn(usize) -> f64, i: usize, level: f64) -> f64 {
    if i == 0 {
        return t[0];
    }
    let (y0, y1) = (y(i - 1), y(i));
    if y1 == y0 {
        return t[i];
    }
    let f = ((level - y0) / (y1 - y0)).clamp(0.0, 1.0);
    t[i - 1] + f * (t[i] - t[i - 1])
}

/// Measure a capture; see the [module](self) for the definitions.
pub fn figures(r: &Response, band: Band) -> Result<Figures, FigureError> {
    let n = r.t.len();
    if n == 0 {
        return Err(FigureError::Shape("no samples".into()));
    }
    if r.cmd.len() != n || r.act.len() != n || r.ferr.len() != n {
        return Err(FigureError::Shape(format!(
            "{n} times, {} commands, {} actuals, {} following errors",
            r.cmd.len(),
            r.act.len(),
            r.ferr.len()
        )));
    }
    for (what, v) in [
        ("time", r.t),
        ("command", r.cmd),
        ("actual", r.act),
        ("following error", r.ferr),
    ] {
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(FigureError::NotFinite(what, i));
        }
    }
    if let Some(i) = (1..n).find(|&i| r.t[i] <= r.t[i - 1]) {
        return Err(FigureError::Time(i));
    }
    let (x0, x1) = (r.cmd[0], r.cmd[n - 1]);
    let step = x1 - x0;
    if step == 0.0 {
        return Err(FigureError::NoStep);
    }
    let dir = step.signum();
    let start_index = r
        .cmd
        .iter()
        .position(|&c| c != x0)
        .ok_or(FigureError::NoStep)?;
    let t0 = r.t[start_index];
    let end_index = (0..n).rev().find(|&i| r.cmd[i] != x1).map_or(0, |i| i + 1);
    // The actual as a fraction of the step, in the step's direction.
    let frac = |i: usize| (r.act[i] - x0) / step;
    let first_at = |level: f64| (start_index..n).find(|&i| frac(i) >= level);
    let rise_time = match (first_at(0.1), first_at(0.9)) {
        (Some(i10), Some(i90)) => {
            Some(crossing(r.t, frac, i90, 0.9) - crossing(r.t, frac, i10, 0.1))
        }
        _ => None,
    };
    let beyond = (start_index..n)
        .map(|i| (r.act[i] - x1) * dir)
        .fold(0.0_f64, f64::max);
    let overshoot_pct = 100.0 * beyond / step.abs();
    let half = band.half_width(step);
    let err = |i: usize| r.act[i] - x1;
    let last_out = (start_index..n).rev().find(|&i| err(i).abs() > half);
    let settled_at = match last_out {
        None => Some(t0),
        Some(k) if k + 1 == n => None,
        Some(k) => {
            // Entering the band across the edge on the side the actual was.
            let edge = half * err(k).signum();
            Some(crossing(r.t, err, k + 1, edge))
        }
    };
    let (mut peak, mut peak_i) = (0.0_f64, 0);
    for (i, e) in r.ferr.iter().enumerate() {
        if e.abs() > peak {
            (peak, peak_i) = (e.abs(), i);
        }
    }
    Ok(Figures {
        start: x0,
        target: x1,
        step,
        start_index,
        start_time: t0,
        command_end_time: r.t[end_index.min(n - 1)],
        rise_time,
        overshoot_pct,
        band: half,
        settling_time: settled_at.map(|t| t - t0),
        settled_for: settled_at.map(|t| r.t[n - 1] - t),
        peak_following_error: peak,
        peak_following_error_time: r.t[peak_i],
        final_actual: r.act[n - 1],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A response sampled every `dt` from `-pre · dt`: the command steps from `x0` by `s` at
    /// t = 0, the actual is `x0 + s · y(t)` (`y(t)` = 0 before 0).
    struct Synth {
        t: Vec<f64>,
        cmd: Vec<f64>,
        act: Vec<f64>,
        ferr: Vec<f64>,
    }

    fn synth(x0: f64, s: f64, dt: f64, pre: usize, n: usize, y: impl Fn(f64) -> f64) -> Synth {
        let t: Vec<f64> = (0..n).map(|k| (k as f64 - pre as f64) * dt).collect();
        let cmd: Vec<f64> = t
            .iter()
            .map(|&t| if t < 0.0 { x0 } else { x0 + s })
            .collect();
        let act: Vec<f64> = t
            .iter()
            .map(|&t| if t < 0.0 { x0 } else { x0 + s * y(t) })
            .collect();
        let ferr = cmd.iter().zip(&act).map(|(c, a)| c - a).collect();
        Synth { t, cmd, act, ferr }
    }

    impl Synth {
        fn response(&self) -> Response<'_> {
            Response {
                t: &self.t,
                cmd: &self.cmd,
                act: &self.act,
                ferr: &self.ferr,
            }
        }
    }

    /// The first time at or after `from` (searching forward in steps of `h`) that `f` crosses
    /// zero, refined by bisection: an answer independent of the sampled figures.
    fn root_after(f: impl Fn(f64) -> f64, from: f64, h: f64) -> f64 {
        let mut a = from;
        while f(a).signum() == f(a + h).signum() {
            a += h;
        }
        let mut b = a + h;
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            if f(m).signum() == f(a).signum() {
                a = m;
            } else {
                b = m;
            }
        }
        0.5 * (a + b)
    }

    #[test]
    fn first_order_rise_is_tau_ln9_and_settling_tau_ln50() {
        let tau = 0.01;
        let dt = 1e-4;
        for (x0, s) in [(0.0, 1000.0), (5000.0, -1000.0)] {
            let r = synth(x0, s, dt, 50, 2000, |t| 1.0 - (-t / tau).exp());
            let f = figures(&r.response(), Band::default()).unwrap();
            assert_eq!(f.step, s);
            assert_eq!(f.start_index, 50);
            assert_eq!(f.start_time, 0.0);
            let rise = f.rise_time.unwrap();
            // Interpolating an exponential over 0.1 ms: within 1 µs of the exact τ·ln 9.
            assert!((rise - tau * 9f64.ln()).abs() < 1e-6, "{rise}");
            assert_eq!(f.overshoot_pct, 0.0);
            assert_eq!(f.band, 20.0);
            let settle = f.settling_time.unwrap();
            assert!((settle - tau * 50f64.ln()).abs() < 1e-6, "{settle}");
            // The following error is the whole step at the first tick of the command.
            assert_eq!(f.peak_following_error, 1000.0);
            assert_eq!(f.peak_following_error_time, 0.0);
        }
    }

    #[test]
    fn second_order_underdamped_overshoot_rise_and_settling() {
        let dt = 1e-4;
        for zeta in [0.2_f64, 0.3, 0.5, 0.7] {
            let wn = 200.0;
            let wd = wn * (1.0 - zeta * zeta).sqrt();
            let y = |t: f64| {
                1.0 - (-zeta * wn * t).exp()
                    * ((wd * t).cos() + zeta / (1.0 - zeta * zeta).sqrt() * (wd * t).sin())
            };
            let r = synth(-300.0, 2000.0, dt, 100, 4000, y);
            let f = figures(&r.response(), Band::default()).unwrap();
            // Overshoot exp(-ζπ/√(1-ζ²)), at the peak time π/ωd; sampled, the peak may fall
            // between two samples: within the curvature over half a sample.
            let want = 100.0 * (-zeta * std::f64::consts::PI / (1.0 - zeta * zeta).sqrt()).exp();
            assert!((f.overshoot_pct - want).abs() < 0.01, "ζ {zeta}: {f:?}");
            // Rise and settling against the analytic response's own crossings.
            let t10 = root_after(|t| y(t) - 0.1, 0.0, 1e-5);
            let t90 = root_after(|t| y(t) - 0.9, 0.0, 1e-5);
            let rise = f.rise_time.unwrap();
            assert!(
                (rise - (t90 - t10)).abs() < 2e-6,
                "ζ {zeta}: {rise} vs {}",
                t90 - t10
            );
            // The last time |y - 1| = 2 %: scan back from the end for the last excursion.
            let band = 0.02;
            let mut t = 0.3;
            while (y(t) - 1.0).abs() <= band {
                t -= 1e-5;
            }
            let side = (y(t) - 1.0).signum();
            let ts = root_after(|u| y(u) - 1.0 - side * band, t, 1e-5);
            let settle = f.settling_time.unwrap();
            assert!((settle - ts).abs() < 5e-6, "ζ {zeta}: {settle} vs {ts}");
            assert!(f.settled_for.unwrap() > 0.0);
        }
    }

    #[test]
    fn a_response_that_ends_outside_the_band_has_not_settled() {
        // A ramp that reaches only 95 % by the end of the capture.
        let r = synth(0.0, 1000.0, 1e-4, 10, 1000, |t| (t / 0.1).min(0.95));
        let f = figures(&r.response(), Band::default()).unwrap();
        assert_eq!(f.settling_time, None);
        assert_eq!(f.settled_for, None);
        assert!((f.rise_time.unwrap() - 0.08).abs() < 1e-9, "{f:?}");
        // Never reaching 90 %: no rise time.
        let r = synth(0.0, 1000.0, 1e-4, 10, 1000, |_| 0.5);
        let f = figures(&r.response(), Band::default()).unwrap();
        assert_eq!(f.rise_time, None);
    }

    #[test]
    fn the_band_is_never_narrower_than_its_minimum() {
        // A 10-count step: 2 % would be 0.2 count; the band is 2 counts.
        let r = synth(0.0, 10.0, 1e-4, 5, 500, |t| 1.0 - (-t / 0.005).exp());
        let f = figures(&r.response(), Band::default()).unwrap();
        assert_eq!(f.band, 2.0);
        // |y - 1| = 0.2 at t = τ ln 5.
        let settle = f.settling_time.unwrap();
        assert!((settle - 0.005 * 5f64.ln()).abs() < 1e-6, "{settle}");
        // Inside the band from the start: settled at the command's start.
        let r = synth(0.0, 1.0, 1e-4, 5, 50, |_| 0.0);
        let f = figures(&r.response(), Band::default()).unwrap();
        assert_eq!(f.settling_time, Some(0.0));
    }

    #[test]
    fn an_s_curve_command_starts_at_its_first_moved_sample() {
        // The command ramps over 10 ms from t = 0 (the first moved sample is t = 0.1 ms), the
        // actual follows 1 ms behind.
        let dt = 1e-4;
        let t: Vec<f64> = (-20..400).map(|k| k as f64 * dt).collect();
        let ramp = |t: f64| 1000.0 * (t / 0.01).clamp(0.0, 1.0);
        let cmd: Vec<f64> = t.iter().map(|&t| ramp(t)).collect();
        let act: Vec<f64> = t.iter().map(|&t| ramp(t - 0.001)).collect();
        let ferr: Vec<f64> = cmd.iter().zip(&act).map(|(c, a)| c - a).collect();
        let f = figures(
            &Response {
                t: &t,
                cmd: &cmd,
                act: &act,
                ferr: &ferr,
            },
            Band::default(),
        )
        .unwrap();
        assert_eq!(f.start_index, 21);
        assert!((f.start_time - 1e-4).abs() < 1e-12);
        assert!((f.command_end_time - 0.01).abs() < 1e-9, "{f:?}");
        assert!((f.rise_time.unwrap() - 0.008).abs() < 1e-9, "{f:?}");
        // Within 20 counts of 1000 at 0.0108 s, 0.0107 s after the command's start.
        assert!((f.settling_time.unwrap() - 0.0107).abs() < 1e-9, "{f:?}");
        assert!((f.peak_following_error - 100.0).abs() < 1e-9);
    }

    #[test]
    fn bad_captures_are_refused_with_the_reason() {
        let ok = synth(0.0, 100.0, 1e-4, 2, 10, |_| 1.0);
        let r = ok.response();
        assert!(matches!(
            figures(
                &Response {
                    t: &[],
                    cmd: &[],
                    act: &[],
                    ferr: &[]
                },
                Band::default()
            ),
            Err(FigureError::Shape(_))
        ));
        assert!(matches!(
            figures(
                &Response {
                    act: &r.act[1..],
                    ..r
                },
                Band::default()
            ),
            Err(FigureError::Shape(_))
        ));
        let flat = vec![7.0; 10];
        assert_eq!(
            figures(&Response { cmd: &flat, ..r }, Band::default()),
            Err(FigureError::NoStep)
        );
        let mut nan = ok.act.clone();
        nan[3] = f64::NAN;
        assert_eq!(
            figures(&Response { act: &nan, ..r }, Band::default()),
            Err(FigureError::NotFinite("actual", 3))
        );
        let mut back = ok.t.clone();
        back[4] = back[3];
        assert_eq!(
            figures(&Response { t: &back, ..r }, Band::default()),
            Err(FigureError::Time(4))
        );
    }
}
