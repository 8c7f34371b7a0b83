//! Layout 1.12: the frequency response measured on the card, and its analysis.
//!
//! The card injects a stepped sine into an axis's servo loop and correlates, at the servo
//! rate, the sine `d`, the encoder position `x` and the DAC output `u` over whole periods (a
//! single-bin DFT: `mc_dpram.h` before `MC_OP_FREQ_START`). From those phasors, at each
//! frequency (`z = e^{jωT}` of the servo period):
//!
//! - the closed loop `T = X/D` (the sine on the position reference, [`FreqMode::Reference`]):
//!   how the position follows a reference;
//! - the plant `P = X/U`, user units per volt, in either mode: DAC to encoder, the drive, the
//!   motor, the mechanics (and the sample-and-hold of the DAC over a servo period);
//! - the open loop `L`. With the sine on the servo output ([`FreqMode::Output`]) it is measured
//!   directly: the output is `u = d + u_fb` with `u_fb = −L·u`, so `L = (D − U)/U`. With the
//!   sine on the reference it is `T/(1 − T)`, exact for a law that acts on the error
//!   `r − x` alone (PID+FF at rest, PD+); FFPIV's velocity loop acts on the encoder alone
//!   (`u = C₁·r − C₂·x`), so there `T/(1 − T) = P·C₁/(1 + P·C₂ − P·C₁)` is not its loop gain:
//!   measure `L` with [`FreqMode::Output`].
//!
//! Resonances are the peaks of the gain (the plant's with its rigid-body `1/ω²` taken out, so
//! a compliance's peak stands out of the slope), at least [`PEAK_DB`] above the lower of the
//! minima on either side before a higher point.

use crate::card::Axis;
use crate::error::{Error, Result, Target};
use firmware_proto::cmd::{AxisCmd, FreqStart};
pub use firmware_proto::cmd::{FreqMode, FREQ_POINTS_MAX};
use firmware_proto::{layout, raw};
use std::time::Duration;

/// A peak (or a dip) counts as a resonance when it stands this far out of its neighbours, dB.
pub const PEAK_DB: f64 = 3.0;

/// A sweep: where the sine enters, the frequencies, its amplitude.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreqSweep {
    /// Where the sine enters the loop.
    pub mode: FreqMode,
    /// The first frequency, Hz (at least 0.1).
    pub from_hz: f64,
    /// The last frequency, Hz (at most a quarter of the servo rate).
    pub to_hz: f64,
    /// Points, log-spaced, 1..=[`FREQ_POINTS_MAX`].
    pub points: usize,
    /// User units ([`FreqMode::Reference`]) or volts ([`FreqMode::Output`]).
    pub amplitude: f64,
    /// Periods measured per point (the card measures at least 1,000 ticks).
    pub cycles: u32,
    /// The least settling time before each point's measured window, s.
    pub settle_s: f64,
}

impl Default for FreqSweep {
    /// The closed loop from 5 Hz to 1 kHz in 40 points, 100 units, 4 cycles, 0.2 s settling.
    fn default() -> Self {
        Self {
            mode: FreqMode::Reference,
            from_hz: 5.0,
            to_hz: 1000.0,
            points: 40,
            amplitude: 100.0,
            cycles: 4,
            settle_s: 0.2,
        }
    }
}

/// A complex number (a phasor), the little arithmetic the analysis needs.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Phasor {
    /// Real part.
    pub re: f64,
    /// Imaginary part.
    pub im: f64,
}

impl Phasor {
    /// `re + j·im`.
    pub const fn new(re: f64, im: f64) -> Self {
        Self { re, im }
    }
    /// `|z|`.
    pub fn abs(self) -> f64 {
        self.re.hypot(self.im)
    }
    /// `arg z`, radians.
    pub fn arg(self) -> f64 {
        self.im.atan2(self.re)
    }
    /// `20·log10|z|`, dB.
    pub fn db(self) -> f64 {
        20.0 * self.abs().log10()
    }
    /// `e^{jθ}`.
    pub fn unit(theta: f64) -> Self {
        Self::new(theta.cos(), theta.sin())
    }
}

impl std::ops::Mul for Phasor {
    type Output = Self;
    fn mul(self, b: Self) -> Self {
        Self::new(
            self.re * b.re - self.im * b.im,
            self.re * b.im + self.im * b.re,
        )
    }
}

impl std::ops::Div for Phasor {
    type Output = Self;
    fn div(self, b: Self) -> Self {
        let n = b.re * b.re + b.im * b.im;
        Self::new(
            (self.re * b.re + self.im * b.im) / n,
            (self.im * b.re - self.re * b.im) / n,
        )
    }
}

impl std::ops::Add for Phasor {
    type Output = Self;
    fn add(self, b: Self) -> Self {
        Self::new(self.re + b.re, self.im + b.im)
    }
}

impl std::ops::Sub for Phasor {
    type Output = Self;
    fn sub(self, b: Self) -> Self {
        Self::new(self.re - b.re, self.im - b.im)
    }
}

/// One frequency as the card measured it: the phasors of the sine, the position and the DAC
/// output (position and sine in user units, except the sine in volts under
/// [`FreqMode::Output`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreqPoint {
    /// The frequency run, Hz.
    pub hz: f64,
    /// The injected sine.
    pub d: Phasor,
    /// The encoder position (less the position held).
    pub x: Phasor,
    /// The DAC output, V.
    pub u: Phasor,
    /// The measured window, servo ticks.
    pub window: u32,
}

/// A transfer function's value at a frequency.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bode {
    /// Hz.
    pub hz: f64,
    /// `20·log10|H|`, dB.
    pub gain_db: f64,
    /// `arg H`, degrees in (−180, 180].
    pub phase_deg: f64,
    /// `H` itself.
    pub value: Phasor,
}

impl Bode {
    fn of(hz: f64, h: Phasor) -> Self {
        Self {
            hz,
            gain_db: h.db(),
            phase_deg: h.arg().to_degrees(),
            value: h,
        }
    }
}

/// A resonance (a peak) or an anti-resonance (a dip) found in a response.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resonance {
    /// Its frequency, Hz (refined between the points by a parabola in log frequency).
    pub hz: f64,
    /// The response's gain at the point nearest it, dB.
    pub gain_db: f64,
    /// How far it stands out of its neighbours, dB.
    pub height_db: f64,
    /// A dip (anti-resonance) rather than a peak.
    pub anti: bool,
}

impl Resonance {
    /// "resonance at 24.1 Hz (+12.3 dB)", "anti-resonance at 15.2 Hz (-9.8 dB)".
    pub fn name(&self) -> String {
        format!(
            "{} at {:.1} Hz ({}{:.1} dB)",
            if self.anti {
                "anti-resonance"
            } else {
                "resonance"
            },
            self.hz,
            if self.anti { "-" } else { "+" },
            self.height_db
        )
    }
}

/// A sweep's result: the points measured and the responses from them.
#[derive(Debug, Clone, PartialEq)]
pub struct FreqResponse {
    /// Where the sine entered.
    pub mode: FreqMode,
    /// The points measured, in frequency order.
    pub points: Vec<FreqPoint>,
    /// Every point asked for was measured (false: the sweep was stopped).
    pub complete: bool,
}

impl FreqResponse {
    /// The response of the mode: the closed loop ([`FreqMode::Reference`]) or the plant
    /// ([`FreqMode::Output`]).
    pub fn response(&self) -> Vec<Bode> {
        match self.mode {
            FreqMode::Reference => self.closed_loop(),
            FreqMode::Output => self.plant(),
        }
    }

    /// `T = X/D` (meaningful under [`FreqMode::Reference`]; under [`FreqMode::Output`] this is
    /// `P/(1 + L)`, position per volt of disturbance).
    pub fn closed_loop(&self) -> Vec<Bode> {
        self.map(|p| p.x / p.d)
    }

    /// `P = X/U`, user units per volt.
    pub fn plant(&self) -> Vec<Bode> {
        self.map(|p| p.x / p.u)
    }

    /// `L`: `(D − U)/U` under [`FreqMode::Output`], `T/(1 − T)` under
    /// [`FreqMode::Reference`] (see the module's head for when that is the loop gain).
    pub fn open_loop(&self) -> Vec<Bode> {
        match self.mode {
            FreqMode::Output => self.map(|p| (p.d - p.u) / p.u),
            FreqMode::Reference => self.map(|p| {
                let t = p.x / p.d;
                t / (Phasor::new(1.0, 0.0) - t)
            }),
        }
    }

    fn map(&self, f: impl Fn(&FreqPoint) -> Phasor) -> Vec<Bode> {
        self.points.iter().map(|p| Bode::of(p.hz, f(p))).collect()
    }

    /// The peaks (and dips) of [`FreqResponse::response`]: under [`FreqMode::Output`] the
    /// plant's with `40·log10 f` added (its rigid-body slope taken out).
    pub fn resonances(&self) -> Vec<Resonance> {
        match self.mode {
            FreqMode::Reference => find_resonances(&self.closed_loop(), 0.0),
            FreqMode::Output => self.plant_resonances(),
        }
    }

    /// The plant's peaks and dips, its rigid-body `1/ω²` slope taken out.
    pub fn plant_resonances(&self) -> Vec<Resonance> {
        find_resonances(&self.plant(), 40.0)
    }
}

/// The peaks and dips of `curve` (in frequency order) standing out by at least [`PEAK_DB`],
/// after adding `slope_db·log10 f` to it.
pub fn find_resonances(curve: &[Bode], slope_db: f64) -> Vec<Resonance> {
    let g: Vec<f64> = curve
        .iter()
        .map(|b| b.gain_db + slope_db * b.hz.log10())
        .collect();
    let mut out = Vec::new();
    for anti in [false, true] {
        let s = if anti { -1.0 } else { 1.0 };
        let v: Vec<f64> = g.iter().map(|x| s * x).collect();
        for i in 1..v.len().saturating_sub(1) {
            if !(v[i] > v[i - 1] && v[i] >= v[i + 1]) {
                continue;
            }
            // The lowest point on each side before one higher than this peak.
            let side = |it: &mut dyn Iterator<Item = usize>| {
                let mut low = v[i];
                for j in it {
                    if v[j] > v[i] {
                        break;
                    }
                    low = low.min(v[j]);
                }
                low
            };
            let left = side(&mut (0..i).rev());
            let right = side(&mut (i + 1..v.len()));
            let height = v[i] - left.max(right);
            if height < PEAK_DB {
                continue;
            }
            // A parabola through the three points in log f.
            let (x0, x1, x2) = (curve[i - 1].hz.ln(), curve[i].hz.ln(), curve[i + 1].hz.ln());
            let (y0, y1, y2) = (v[i - 1], v[i], v[i + 1]);
            let d1 = (y1 - y0) / (x1 - x0);
            let d2 = (y2 - y1) / (x2 - x1);
            let a = (d2 - d1) / (x2 - x0);
            let x = if a < 0.0 {
                ((x0 + x1) / 2.0 - d1 / (2.0 * a)).clamp(x0, x2)
            } else {
                x1
            };
            out.push(Resonance {
                hz: x.exp(),
                gain_db: curve[i].gain_db,
                height_db: height,
                anti,
            });
        }
    }
    out.sort_by(|a, b| a.hz.total_cmp(&b.hz));
    out
}

/// The sweep's state (`freq_status`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FreqProgress {
    /// `MC_FREQ_*`.
    pub state: u32,
    /// The axis swept.
    pub axis: usize,
    /// Points measured.
    pub done: usize,
    /// Points asked for.
    pub points: usize,
    /// The start command's seq.
    pub seq: u32,
}

impl Axis {
    /// Start a sweep of this axis (enabled, at rest) and return at once; read it with
    /// [`Axis::freq_progress`] and [`Axis::freq_result`], or use
    /// [`Axis::frequency_response`]. Refused, nothing changed: `FreqRange`, `FreqAmplitude`,
    /// `FreqLimits`, `FreqBusy`, `NotFinite`, `AxisDisabled`, `InvalidState`.
    pub fn start_frequency_sweep(&self, s: &FreqSweep) -> Result<u32> {
        let scale = match s.mode {
            FreqMode::Reference => self.scale(),
            FreqMode::Output => 1.0,
        };
        let range = |x: usize, max: usize| u16::try_from(x.min(max + 1)).unwrap_or(u16::MAX);
        let start = FreqStart {
            mode: s.mode,
            from_hz: s.from_hz,
            to_hz: s.to_hz,
            points: range(s.points, FREQ_POINTS_MAX),
            amplitude: s.amplitude * scale,
            cycles: range(s.cycles as usize, raw::MC_FREQ_CYCLES_MAX as usize),
            settle_s: s.settle_s,
        };
        self.run(self.cmd(AxisCmd::FreqStart(start)), "frequency sweep")
    }

    /// Stop the card's sweep (whichever axis it runs on; none: nothing happens).
    pub fn stop_frequency_sweep(&self) -> Result<()> {
        self.run(self.cmd(AxisCmd::FreqStop), "stop frequency sweep")
            .map(|_| ())
    }

    /// The card's sweep's state.
    pub fn freq_progress(&self) -> FreqProgress {
        let b = layout::FREQ_STATUS.read(self.card().window());
        FreqProgress {
            state: b.state,
            axis: b.axis as usize,
            done: (b.done as usize).min(FREQ_POINTS_MAX),
            points: b.points as usize,
            seq: b.seq,
        }
    }

    /// The points the card's last sweep measured (of this axis: else an empty result).
    pub fn freq_result(&self) -> FreqResponse {
        let b = layout::FREQ_STATUS.read(self.card().window());
        let mode = FreqMode::from_code(b.mode).unwrap_or(FreqMode::Reference);
        let pos = 1.0 / self.scale();
        let dscale = match mode {
            FreqMode::Reference => pos,
            FreqMode::Output => 1.0,
        };
        let n = if b.axis as usize == self.index() {
            (b.done as usize).min(FREQ_POINTS_MAX)
        } else {
            0
        };
        let points = b.point[..n]
            .iter()
            .map(|p| FreqPoint {
                hz: p.hz,
                d: Phasor::new(p.d_re * dscale, p.d_im * dscale),
                x: Phasor::new(p.x_re * pos, p.x_im * pos),
                u: Phasor::new(p.u_re, p.u_im),
                window: p.window,
            })
            .collect();
        FreqResponse {
            mode,
            points,
            complete: b.state == raw::MC_FREQ_DONE && n == b.points as usize,
        }
    }

    /// Run a sweep to its end (up to `timeout`; emulated time on a stepped card) and return
    /// what it measured. A sweep ended early (a stop, a safety stop): `Aborted`.
    pub fn frequency_response(&self, s: &FreqSweep, timeout: Duration) -> Result<FreqResponse> {
        let seq = self.start_frequency_sweep(s)?;
        let w = self.card().window();
        let state = self.card().wait_window(timeout, || {
            let b = layout::FREQ_STATUS.read(w);
            (b.seq == seq && b.state != raw::MC_FREQ_RUNNING).then_some(Ok(b.state))
        });
        let state = match state {
            Ok(s) => s,
            Err(e) => {
                let _ = self.stop_frequency_sweep();
                return Err(e);
            }
        };
        if state != raw::MC_FREQ_DONE {
            return Err(Error::Aborted {
                target: Target::Axis(self.index()),
                by: "a stop, or the axis leaving Standstill, before the sweep's end".into(),
            });
        }
        Ok(self.freq_result())
    }
}

/// Log-spaced frequencies as the card asks for them (point `k` of `n` from `from` to `to`).
pub fn sweep_frequencies(from: f64, to: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| {
            if n <= 1 {
                from
            } else {
                from * (to / from).powf(k as f64 / (n - 1) as f64)
            }
        })
        .collect()
}

/// Seconds a sweep runs at `rate_hz` (each point: settle windows and a measured one).
pub fn sweep_duration(s: &FreqSweep, rate_hz: u32) -> f64 {
    let rate = rate_hz as f64;
    sweep_frequencies(s.from_hz, s.to_hz, s.points)
        .into_iter()
        .map(|f| {
            let per = rate / f;
            let c = (s.cycles as f64).max((raw::MC_FREQ_WINDOW_MIN as f64 / per).ceil());
            let m = (c * per).round().max(4.0);
            let settle = (s.settle_s * rate / m).ceil().max(1.0);
            (settle + 1.0) * m / rate
        })
        .sum()
}
