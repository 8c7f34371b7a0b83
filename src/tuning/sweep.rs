//! The frequency sweep the tuning page runs (layout 1.12): a [`SweepRequest`] as the page's
//! form posts it, turned into the SDK's [`FreqSweep`] and run on the page's axis with
//! [`crate::Axis::frequency_response`] (as `mcctl freq` runs it), answered as `mcctl freq
//! --json` prints it ([`crate::cli::freq::to_json`]). The card's refusals (`FreqRange`,
//! `FreqAmplitude`, `FreqLimits`, `FreqBusy`, `NotFinite`) come back as the SDK's error,
//! nothing started; a sweep the card ended early (a stop, the axis leaving Standstill) as
//! [`TestError::Aborted`].

use super::run::{ready, TestError};
use crate::{Card, Error, FreqMode, FreqSweep};
use serde::Deserialize;

/// Where the sine enters: `closed_loop` (the position reference, user units) or `plant` (the
/// servo output, volts).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SweepMode {
    /// [`FreqMode::Reference`].
    ClosedLoop,
    /// [`FreqMode::Output`].
    Plant,
}

/// What the page posts: `{"mode": "closed_loop", "from_hz": 5, "to_hz": 200, "points": 20,
/// "amplitude": 100}`, with `cycles`, `settle_s`, `enable` and `axis` optional.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepRequest {
    /// The axis; if given, it must be the page's.
    #[serde(default)]
    pub axis: Option<usize>,
    /// Where the sine enters.
    pub mode: SweepMode,
    /// The first frequency, Hz.
    pub from_hz: f64,
    /// The last frequency, Hz.
    pub to_hz: f64,
    /// Points, log-spaced.
    pub points: usize,
    /// User units (closed loop) or volts (plant).
    pub amplitude: f64,
    /// Periods measured per point (default as `mcctl freq`: 4).
    #[serde(default = "default_cycles")]
    pub cycles: u32,
    /// The least settling time before each point, s (default as `mcctl freq`: 0.2).
    #[serde(default = "default_settle")]
    pub settle_s: f64,
    /// Power the axis on first if it is disabled.
    #[serde(default)]
    pub enable: bool,
}

fn default_cycles() -> u32 {
    FreqSweep::default().cycles
}

fn default_settle() -> f64 {
    FreqSweep::default().settle_s
}

impl SweepRequest {
    /// The SDK's sweep.
    pub fn sweep(&self) -> FreqSweep {
        FreqSweep {
            mode: match self.mode {
                SweepMode::ClosedLoop => FreqMode::Reference,
                SweepMode::Plant => FreqMode::Output,
            },
            from_hz: self.from_hz,
            to_hz: self.to_hz,
            points: self.points,
            amplitude: self.amplitude,
            cycles: self.cycles,
            settle_s: self.settle_s,
        }
    }
}

/// Run the sweep on `axis` (the page's) to its end; `mcctl freq --json`'s object.
pub fn run(card: &Card, axis: usize, req: &SweepRequest) -> Result<serde_json::Value, TestError> {
    if let Some(a) = req.axis.filter(|&a| a != axis) {
        return Err(TestError::Request(format!(
            "this page tunes axis {axis}, not axis {a}: serve axis {a} with `mcctl serve --axis {a}`"
        )));
    }
    let ax = card.axis(axis)?;
    ready(card, &ax, req.enable)?;
    let r = crate::cli::freq::freq(card, axis, &req.sweep()).map_err(|e| match e {
        e @ Error::Aborted { .. } => TestError::Aborted(e.to_string()),
        e => e.into(),
    })?;
    Ok(crate::cli::freq::to_json(&r))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn card() -> Card {
        Card::open_sim(crate::SimOptions {
            clock: crate::Clock::Stepped,
            emu: Default::default(),
        })
        .unwrap()
    }

    fn req(json: &str) -> SweepRequest {
        serde_json::from_str(json).unwrap()
    }

    #[test]
    fn a_sweep_answers_mcctl_freqs_json_and_bad_ones_are_refused_with_the_sdks_error() {
        let card = card();
        let small = r#"{"mode":"closed_loop","from_hz":10,"to_hz":40,"points":3,"amplitude":50,
            "settle_s":0.05,"cycles":2}"#;
        // Disabled, not told to power on: refused, nothing started.
        assert!(
            matches!(run(&card, 0, &req(small)), Err(TestError::NotReady(m)) if m.contains("disabled"))
        );
        let mut on = req(small);
        on.enable = true;
        let j = run(&card, 0, &on).unwrap();
        assert_eq!(j["mode"], "closed_loop");
        assert_eq!(j["complete"], true);
        let pts = j["points"].as_array().unwrap();
        assert_eq!(pts.len(), 3);
        let hz: Vec<f64> = pts.iter().map(|p| p["hz"].as_f64().unwrap()).collect();
        // As asked, to the whole number of ticks the card runs each in (half a tick in at
        // least 1000).
        for (h, w) in hz.iter().zip(crate::sweep_frequencies(10.0, 40.0, 3)) {
            assert!((h / w - 1.0).abs() <= 5e-4, "{hz:?}");
        }
        // Well below the loop's bandwidth the closed loop follows: near 0 dB.
        assert!(pts[0]["gain_db"].as_f64().unwrap().abs() < 3.0, "{j}");
        // From above to: the card's refusal.
        let mut back = on;
        (back.from_hz, back.to_hz) = (40.0, 10.0);
        match run(&card, 0, &back) {
            Err(TestError::Card(e)) => assert_eq!(e.kind(), crate::ErrorKind::FreqRange),
            other => panic!("{other:?}"),
        }
        // Another axis than the page's.
        let mut other = on;
        other.axis = Some(1);
        assert!(
            matches!(run(&card, 0, &other), Err(TestError::Request(m)) if m.contains("axis 1"))
        );
        assert!(serde_json::from_str::<SweepRequest>(
            r#"{"mode":"open","from_hz":1,"to_hz":2,"points":2,"amplitude":1}"#
        )
        .is_err());
        assert!(serde_json::from_str::<SweepRequest>(
            r#"{"mode":"plant","from_hz":1,"to_hz":2,"points":2,"amplitude":1,"gain":3}"#
        )
        .is_err());
    }
}
