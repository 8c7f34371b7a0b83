//! Post-interpolation acceleration/deceleration filters (per axis).
//!
//! The filters act on the per-tick position increments `f_i(k)` produced by an
//! interpolator (the "pulse/velocity data" of Kim 1991 and Shin, in encoder
//! counts per tick) and return the smoothed increments `f_o(k)`. Everything is
//! `f64`, counts and seconds.
//!
//! * [`LinearFilter`]: moving average of `m` samples, Kim eq 1
//!   (`f_o(k) = f_o(k-1) + [f_i(k) - f_i(k-m)]/m`), transfer function Kim eq 3,
//!   acceleration time Kim eq 2 (`t_acc = m·Ts`). Shin eq 39 is the same filter
//!   with `m = Nmax/Gain`.
//! * [`ExponentialFilter`]: first order lag, Kim eq 7–9 (with the correction
//!   of eq 9 noted in the papers' README) = Shin eq 35–36.
//! * [`BellFilter`]: linear followed by exponential, Shin eq 40.
//! * [`AccDecFilter`]: the interchangeable enum the axis code holds.
//!
//! # Distance conservation
//!
//! A filter must never lose or invent distance: once the input has stopped,
//! `Σ f_o = Σ f_i`. Both filters therefore keep the distance still inside
//! them (`pending = Σ f_i − Σ f_o`) in an error-free double-`f64`
//! accumulator ([`CompensatedSum`], TwoSum based) and, when the ideal filter
//! would be empty, emit that pending remainder as the output instead of the
//! recurrence's value:
//!
//! * linear: on the tick where the last non-zero input leaves the window
//!   (`m-1` ticks after it) the exact-arithmetic pending after the tick is 0, so
//!   the output is the whole pending (= `f_i/m` + float residue);
//! * exponential: its output decays forever, so once the input is zero and
//!   `|pending| <= SETTLE_THRESHOLD` (1e-9 counts), or after a bounded number of
//!   zero-input ticks ([`ExponentialFilter::settle_bound_ticks`]), the pending
//!   remainder is emitted.
//!
//! The linear filter's running window sum is also kept in a [`CompensatedSum`]
//! (so it does not drift; with integer-valued increments it is exact) and is
//! reset to exactly zero whenever the window holds only zeros.
//!
//! No per-tick function allocates, loops over `m`, or panics. Invalid inputs
//! to the per-tick functions are rejected by the `try_step` variants.
#![forbid(unsafe_code)]

use crate::math;
use core::fmt;

/// Capacity of the linear filter's delay line (samples).
pub const MAX_TAPS: usize = 4096;

/// Largest accepted input increment magnitude, counts per tick. Keeps every
/// internal sum far away from overflow.
pub const MAX_INCREMENT: f64 = 1.0e12;

/// Once the exponential filter's input is zero and its pending distance is at
/// most this many counts, the remainder is emitted and the filter settles.
pub const SETTLE_THRESHOLD: f64 = 1.0e-9;

/// Largest accepted `tau / ts` for the exponential filter (pole
/// `a = tau/(tau+ts)`). Bounds the settle length, see
/// [`ExponentialFilter::settle_bound_ticks`].
pub const MAX_TIME_CONSTANT_RATIO: f64 = 9.0e6;

/// Largest accepted pole for [`ExponentialFilter::from_pole`].
pub const MAX_POLE: f64 = 1.0 - 1.0e-7;

/// `ln(1e30)`: after `ceil(SETTLE_LOG_RANGE / -ln a)` zero-input ticks the
/// exponential filter's pending has shrunk by a factor 1e30 or more.
const SETTLE_LOG_RANGE: f64 = 69.1;

/// Errors of the filter constructors and of `try_step`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FilterError {
    /// Sample time not finite or `<= 0`.
    InvalidSampleTime,
    /// Time constant not finite, `<= 0`, or longer than the filter supports.
    InvalidTimeConstant,
    /// `m == 0`.
    InvalidTaps,
    /// `m > MAX_TAPS` (or `tau/ts` rounds to more than `MAX_TAPS`).
    TooManyTaps,
    /// Pole not in `[0, MAX_POLE]` (or not finite).
    InvalidPole,
    /// Input increment not finite or `|f_i| > MAX_INCREMENT`.
    InvalidInput,
}

impl fmt::Display for FilterError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = match self {
            FilterError::InvalidSampleTime => "sample time must be finite and > 0",
            FilterError::InvalidTimeConstant => {
                "time constant must be finite, > 0 and within range"
            }
            FilterError::InvalidTaps => "linear filter needs at least one tap",
            FilterError::TooManyTaps => "linear filter length exceeds MAX_TAPS",
            FilterError::InvalidPole => "exponential filter pole must be in [0, MAX_POLE]",
            FilterError::InvalidInput => "input increment must be finite and within MAX_INCREMENT",
        };
        f.write_str(s)
    }
}

impl core::error::Error for FilterError {}

fn check_ts(ts: f64) -> Result<(), FilterError> {
    if ts.is_finite() && ts > 0.0 {
        Ok(())
    } else {
        Err(FilterError::InvalidSampleTime)
    }
}

fn check_tau(tau: f64) -> Result<(), FilterError> {
    if tau.is_finite() && tau > 0.0 {
        Ok(())
    } else {
        Err(FilterError::InvalidTimeConstant)
    }
}

fn check_input(fi: f64) -> Result<f64, FilterError> {
    if fi.is_finite() && fi.abs() <= MAX_INCREMENT {
        Ok(fi)
    } else {
        Err(FilterError::InvalidInput)
    }
}

/// Rejected inputs of `step` are treated as a zero increment.
fn sanitize(fi: f64) -> f64 {
    check_input(fi).unwrap_or(0.0)
}

/// Knuth's TwoSum: `s = fl(a+b)` and the exact rounding error `e`,
/// `a + b = s + e` exactly.
#[inline]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    (s, e)
}

/// Error-free running sum held as an unevaluated pair `hi + lo` (double-f64,
/// ~106 bits). Each [`add`](Self::add) is O(1): two TwoSums.
///
/// Used inside the filters for the window sum and the pending distance, and
/// offered to callers for accumulating the commanded position from the
/// filter outputs without float drift.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CompensatedSum {
    hi: f64,
    lo: f64,
}

impl CompensatedSum {
    /// Zero.
    pub const fn new() -> Self {
        Self { hi: 0.0, lo: 0.0 }
    }

    /// Adds `x`.
    #[inline]
    pub fn add(&mut self, x: f64) {
        let (s, e) = two_sum(self.hi, x);
        let t = self.lo + e;
        let (hi, lo) = two_sum(s, t);
        self.hi = hi;
        self.lo = lo;
    }

    /// The sum rounded to one `f64`.
    #[inline]
    pub fn value(&self) -> f64 {
        self.hi + self.lo
    }

    /// True if the sum is exactly zero.
    #[inline]
    pub fn is_zero(&self) -> bool {
        self.hi == 0.0 && self.lo == 0.0
    }

    /// The sum as its unevaluated pair `(hi, lo)`, leaving zero behind.
    #[inline]
    pub fn take(&mut self) -> (f64, f64) {
        let pair = (self.hi, self.lo);
        *self = Self::new();
        pair
    }
}

/// How a filter empties once its input has stopped (see [`AccDecFilter::step_group`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Settle {
    /// On its own: the exponential stage emits its remainder once `|pending| <=
    /// SETTLE_THRESHOLD`; the remainder's sub-ulp part follows on the next tick.
    Own,
    /// As one of a group: the exponential stage emits its remainder only when the caller says
    /// `flush` (or after the bounded number of zero-input ticks); every remainder is emitted
    /// whole, as an unevaluated pair, on the tick the filter empties.
    Group { flush: bool },
}

/// The three kinds of acc/dec filter (plus none).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FilterKind {
    /// Pass-through.
    None,
    /// Moving average, Kim eq 1 / Shin eq 39.
    Linear,
    /// First order, Kim eq 7–9 / Shin eq 35–36.
    Exponential,
    /// Linear followed by exponential, Shin eq 40.
    Bell,
}

// ---------------------------------------------------------------------------
// Linear
// ---------------------------------------------------------------------------

/// Linear acc/dec: moving average of the last `m` input increments.
///
/// Kim eq 1: `f_o(k) = [f_i(k) - f_i(k-m)]/m + f_o(k-1)`, i.e.
/// `f_o(k) = S(k)/m` with the running window sum
/// `S(k) = S(k-1) + f_i(k) - f_i(k-m)` (O(1) per tick, no re-summation).
/// Transfer function Kim eq 3, `H(z) = z(1-z^-m)/(m(z-1))`; acceleration time
/// Kim eq 2, `t_acc = m·Ts`: a step of the input velocity becomes a linear
/// ramp of `m` ticks (trapezoidal velocity). Shin eq 39 is the same filter
/// with `m = Nmax/Gain`.
///
/// `S` is kept in a [`CompensatedSum`] (exact for integer-valued increments),
/// is reset to exactly 0 whenever the window holds only zeros, and the
/// distance still inside the filter is tracked exactly and emitted on the tick
/// where the last non-zero input leaves the window (see the module docs).
#[derive(Debug, Clone)]
pub struct LinearFilter {
    ring: [f64; MAX_TAPS],
    m: usize,
    /// Next slot of `ring` to overwrite (holds `f_i(k-m)` before the write).
    idx: usize,
    /// `S(k)`: sum of the inputs in the window.
    window: CompensatedSum,
    /// `Σ f_i − Σ f_o`.
    pending: CompensatedSum,
    /// Number of consecutive zero inputs up to and including the last tick.
    zero_run: usize,
}

impl LinearFilter {
    /// Filter of `m` taps (`1 <= m <= MAX_TAPS`); `m = 1` is a pass-through.
    pub fn new(m: usize) -> Result<Self, FilterError> {
        if m == 0 {
            return Err(FilterError::InvalidTaps);
        }
        if m > MAX_TAPS {
            return Err(FilterError::TooManyTaps);
        }
        Ok(Self {
            ring: [0.0; MAX_TAPS],
            m,
            idx: 0,
            window: CompensatedSum::new(),
            pending: CompensatedSum::new(),
            zero_run: usize::MAX,
        })
    }

    /// Filter with acceleration time `tau_s` (Kim eq 2: `m = round(tau_s/ts)`,
    /// at least 1). Errors: `ts`/`tau_s` not finite or `<= 0`, or `m > MAX_TAPS`.
    pub fn from_time_constant(tau_s: f64, ts: f64) -> Result<Self, FilterError> {
        check_ts(ts)?;
        check_tau(tau_s)?;
        let ratio = math::round(tau_s / ts);
        if !ratio.is_finite() || ratio > MAX_TAPS as f64 {
            return Err(FilterError::TooManyTaps);
        }
        // ratio is in [0, MAX_TAPS] here, so the cast is exact.
        Self::new((ratio as usize).max(1))
    }

    /// Number of taps `m`.
    pub fn taps(&self) -> usize {
        self.m
    }

    /// Acceleration time `m·ts` (Kim eq 2).
    pub fn time_constant(&self, ts: f64) -> f64 {
        self.m as f64 * ts
    }

    /// Advances one tick; rejected inputs (see [`try_step`](Self::try_step))
    /// are treated as 0.
    pub fn step(&mut self, fi: f64) -> f64 {
        self.advance(sanitize(fi))
    }

    /// Advances one tick. Errors (state untouched) if `fi` is not finite or
    /// `|fi| > MAX_INCREMENT`.
    pub fn try_step(&mut self, fi: f64) -> Result<f64, FilterError> {
        let fi = check_input(fi)?;
        Ok(self.advance(fi))
    }

    fn advance(&mut self, fi: f64) -> f64 {
        self.advance_mode(fi, Settle::Own).0
    }

    fn advance_mode(&mut self, fi: f64, mode: Settle) -> (f64, f64) {
        let m = self.m;
        // Delay line: read f_i(k-m), write f_i(k). No loop over m.
        let old = match self.ring.get_mut(self.idx) {
            Some(slot) => core::mem::replace(slot, fi),
            None => 0.0, // unreachable: idx < m <= MAX_TAPS
        };
        self.idx += 1;
        if self.idx >= m {
            self.idx = 0;
        }
        // Kim eq 1: S(k) = S(k-1) + f_i(k) - f_i(k-m).
        self.window.add(fi);
        self.window.add(-old);
        self.pending.add(fi);
        self.zero_run = if fi == 0.0 {
            self.zero_run.saturating_add(1)
        } else {
            0
        };
        if self.zero_run >= m {
            // Window holds only zeros: renormalise the running sum exactly.
            self.window = CompensatedSum::new();
        }
        if self.zero_run.saturating_add(1) >= m {
            // At most the oldest sample is non-zero and this tick is its last
            // contribution: in exact arithmetic the pending after this tick is
            // 0, so emit all of it (= f_i(k-m+1)/m + rounding residue).
            if let Settle::Group { .. } = mode {
                return self.pending.take();
            }
            let out = self.pending.value();
            self.pending.add(-out);
            return (out, 0.0);
        }
        // Kim eq 1: f_o(k) = S(k)/m.
        let out = self.window.value() / m as f64;
        self.pending.add(-out);
        (out, 0.0)
    }

    /// Clears the state (not a per-tick function: O(m)).
    pub fn reset(&mut self) {
        for v in self.ring.iter_mut().take(self.m) {
            *v = 0.0;
        }
        self.idx = 0;
        self.window = CompensatedSum::new();
        self.pending = CompensatedSum::new();
        self.zero_run = usize::MAX;
    }

    /// True when no distance is left inside the filter (and none will be
    /// emitted until new non-zero input arrives).
    pub fn is_settled(&self) -> bool {
        self.pending.is_zero() && self.zero_run.saturating_add(1) >= self.m
    }

    /// Distance still held inside the filter, `Σ f_i − Σ f_o` (counts).
    pub fn pending(&self) -> f64 {
        self.pending.value()
    }

    /// Upper bound on the number of zero-input ticks, counted from the tick
    /// after the last non-zero input, until [`is_settled`](Self::is_settled):
    /// `m` (the window drains in `m-1` ticks, plus one tick for a sub-ulp
    /// remainder).
    pub fn settle_bound_ticks(&self) -> u64 {
        self.m as u64
    }
}

// ---------------------------------------------------------------------------
// Exponential
// ---------------------------------------------------------------------------

/// Pole `a` of the exponential filter with time constant `tau_s` sampled at
/// `ts` (Kim eq 8): `a = 1/(1 + τ_K·T)` where Kim's `τ_K = f_a/2^n` (eq 7) is a
/// rate, the inverse of the time constant in seconds `tau_s = 2^n/f_a`
/// (Shin eq 16), so `a = tau_s/(tau_s + ts)`. Returns NaN for invalid
/// arguments.
pub fn exponential_pole(tau_s: f64, ts: f64) -> f64 {
    if check_ts(ts).is_err() || check_tau(tau_s).is_err() {
        return f64::NAN;
    }
    tau_s / (tau_s + ts)
}

/// Exponential (first order) acc/dec.
///
/// Continuous model Kim eq 4–7 / Shin eq 6–16: `H(s) = τ_K/(s + τ_K)`, step
/// response `1 − e^{−t/tau}` with the time constant `tau = 1/τ_K` seconds.
/// Backward difference (`s → (1 − z⁻¹)/T`) gives Kim eq 8,
/// `H(z) = (1−a)z/(z−a)`, `a = 1/(1+τ_K T) = tau/(tau+T)`, i.e. the
/// difference equation (Kim eq 9 as corrected: the gain is `1−a`, not `a`;
/// with gain `a ≈ 1` the step response would jump to ~1 in one tick, which
/// does not match eq 7):
///
/// `f_o(k) = f_o(k-1) + (1−a)·[f_i(k) − f_o(k-1)]`, gain `1−a = T/(tau+T)`,
///
/// which is Shin eq 36 with `Gain = 1−a` (Shin eq 35 has `Gain = 1/2^n =
/// T/tau`, the forward-difference value; identical to first order in `T/tau`).
/// The discrete step response is `1 − a^{k+1}`.
///
/// Implementation: the equivalent up/down-counter form of Shin eq 22–25
/// (`x̂ = x + f_i; f_o = Gain·x̂; x = x̂ − f_o`): the counter `x` is exactly the
/// pending distance, held in a [`CompensatedSum`]. With zero initial state it
/// produces the same sequence as eq 9/36 (substitute `x(k-1) =
/// (1−Gain)/Gain·f_o(k-1)`). When the input is zero and
/// `|x| <= SETTLE_THRESHOLD`, or after [`settle_bound_ticks`](Self::settle_bound_ticks)
/// zero-input ticks, the remainder `x` itself is emitted, so `Σ f_o = Σ f_i`.
#[derive(Debug, Clone)]
pub struct ExponentialFilter {
    pole: f64,
    gain: f64,
    pending: CompensatedSum,
    zero_run: u64,
    settle_ticks: u64,
}

impl ExponentialFilter {
    fn build(pole: f64, gain: f64) -> Self {
        // -ln a: ticks per e-fold of the decaying tail.
        let neg_ln_a = -math::ln(pole);
        let n = math::ceil(SETTLE_LOG_RANGE / neg_ln_a);
        // `as` saturates; n is at most ~7e8 for pole <= MAX_POLE.
        let settle_ticks = (n as u64).max(1);
        Self {
            pole,
            gain,
            pending: CompensatedSum::new(),
            zero_run: u64::MAX,
            settle_ticks,
        }
    }

    /// Filter with time constant `tau_s` seconds at sample time `ts`
    /// (`a = tau_s/(tau_s+ts)`, gain `ts/(tau_s+ts)`, Kim eq 8). Errors:
    /// `ts`/`tau_s` not finite or `<= 0`, or `tau_s/ts > MAX_TIME_CONSTANT_RATIO`.
    pub fn from_time_constant(tau_s: f64, ts: f64) -> Result<Self, FilterError> {
        check_ts(ts)?;
        check_tau(tau_s)?;
        let ratio = tau_s / ts;
        if !ratio.is_finite() || ratio > MAX_TIME_CONSTANT_RATIO {
            return Err(FilterError::InvalidTimeConstant);
        }
        let pole = tau_s / (tau_s + ts);
        let gain = ts / (tau_s + ts);
        Ok(Self::build(pole, gain))
    }

    /// Filter with pole `a` (`0 <= a <= MAX_POLE`, gain `1−a`; `a = 0` is a
    /// pass-through). This is the `a` of Kim eq 8/9 and eq 32.
    pub fn from_pole(a: f64) -> Result<Self, FilterError> {
        if !(a.is_finite() && (0.0..=MAX_POLE).contains(&a)) {
            return Err(FilterError::InvalidPole);
        }
        Ok(Self::build(a, 1.0 - a))
    }

    /// Pole `a` (Kim eq 8), the `a` to pass to
    /// `circle::exponential_filter_radial_error`.
    pub fn pole(&self) -> f64 {
        self.pole
    }

    /// Gain `1 − a` of Kim eq 9 (corrected) / Shin eq 36.
    pub fn gain(&self) -> f64 {
        self.gain
    }

    /// Time constant `tau = ts·a/(1−a)` seconds for sample time `ts`.
    pub fn time_constant(&self, ts: f64) -> f64 {
        ts * self.pole / self.gain
    }

    /// Advances one tick; rejected inputs are treated as 0.
    pub fn step(&mut self, fi: f64) -> f64 {
        self.advance(sanitize(fi))
    }

    /// Advances one tick. Errors (state untouched) if `fi` is not finite or
    /// `|fi| > MAX_INCREMENT`.
    pub fn try_step(&mut self, fi: f64) -> Result<f64, FilterError> {
        let fi = check_input(fi)?;
        Ok(self.advance(fi))
    }

    fn advance(&mut self, fi: f64) -> f64 {
        self.advance_mode((fi, 0.0), Settle::Own).0
    }

    /// One tick with the input `fi.0 + fi.1` (an unevaluated pair: the bell filter's linear
    /// stage hands over its whole remainder).
    fn advance_mode(&mut self, fi: (f64, f64), mode: Settle) -> (f64, f64) {
        // Shin eq 22: x̂(k) = x(k-1) + f_i(k).
        self.pending.add(fi.0);
        if fi.1 != 0.0 {
            self.pending.add(fi.1);
        }
        let zero_in = fi.0 == 0.0 && fi.1 == 0.0;
        self.zero_run = if zero_in {
            self.zero_run.saturating_add(1)
        } else {
            0
        };
        let x_hat = self.pending.value();
        let settle = match mode {
            Settle::Own => zero_in && x_hat.abs() <= SETTLE_THRESHOLD,
            Settle::Group { flush } => zero_in && flush,
        };
        if settle || self.zero_run >= self.settle_ticks {
            if let Settle::Group { .. } = mode {
                return self.pending.take();
            }
            // Settle: emit the remainder (any sub-ulp part follows next tick).
            self.pending.add(-x_hat);
            return (x_hat, 0.0);
        }
        // Shin eq 32 / Kim eq 9 (corrected): f_o(k) = (1−a)·x̂(k).
        let out = self.gain * x_hat;
        // Shin eq 25: x(k) = x̂(k) − f_o(k).
        self.pending.add(-out);
        (out, 0.0)
    }

    /// With a zero input now, would this filter settle on its own (its pending within
    /// `SETTLE_THRESHOLD`)?
    fn tail_ready(&self) -> bool {
        self.pending.value().abs() <= SETTLE_THRESHOLD
    }

    /// Clears the state.
    pub fn reset(&mut self) {
        self.pending = CompensatedSum::new();
        self.zero_run = u64::MAX;
    }

    /// True when no distance is left inside the filter.
    pub fn is_settled(&self) -> bool {
        self.pending.is_zero()
    }

    /// Distance still held inside the filter, `Σ f_i − Σ f_o` (counts).
    pub fn pending(&self) -> f64 {
        self.pending.value()
    }

    /// Upper bound on the number of zero-input ticks, counted from the tick
    /// after the last non-zero input, until [`is_settled`](Self::is_settled):
    /// `ceil(ln(1e30)/(−ln a)) + 1`. In practice it settles as soon as
    /// `|pending|·a^k <= SETTLE_THRESHOLD` (plus at most one tick).
    pub fn settle_bound_ticks(&self) -> u64 {
        self.settle_ticks.saturating_add(1)
    }
}

// ---------------------------------------------------------------------------
// Bell
// ---------------------------------------------------------------------------

/// Bell-shaped acc/dec, Shin eq 40: the linear filter (Shin eq 39 / Kim eq 1)
/// followed by the exponential filter (Shin eq 36 / Kim eq 9). Conserves
/// distance because both stages do.
#[derive(Debug, Clone)]
pub struct BellFilter {
    linear: LinearFilter,
    exponential: ExponentialFilter,
}

impl BellFilter {
    /// Composition of the two stages.
    pub fn new(linear: LinearFilter, exponential: ExponentialFilter) -> Self {
        Self {
            linear,
            exponential,
        }
    }

    /// Both stages with the same time constant `tau_s` (Shin eq 40 uses the
    /// same `Gain` in both stages): `m = round(tau_s/ts)` and exponential
    /// `a = tau_s/(tau_s+ts)`.
    pub fn from_time_constant(tau_s: f64, ts: f64) -> Result<Self, FilterError> {
        Self::from_time_constants(tau_s, tau_s, ts)
    }

    /// Separate time constants for the linear and the exponential stage.
    pub fn from_time_constants(
        tau_linear_s: f64,
        tau_exponential_s: f64,
        ts: f64,
    ) -> Result<Self, FilterError> {
        Ok(Self::new(
            LinearFilter::from_time_constant(tau_linear_s, ts)?,
            ExponentialFilter::from_time_constant(tau_exponential_s, ts)?,
        ))
    }

    /// The linear stage.
    pub fn linear(&self) -> &LinearFilter {
        &self.linear
    }

    /// The exponential stage.
    pub fn exponential(&self) -> &ExponentialFilter {
        &self.exponential
    }

    /// Advances one tick; rejected inputs are treated as 0.
    pub fn step(&mut self, fi: f64) -> f64 {
        self.advance(sanitize(fi))
    }

    /// Advances one tick. Errors (state untouched) on an invalid input.
    pub fn try_step(&mut self, fi: f64) -> Result<f64, FilterError> {
        let fi = check_input(fi)?;
        Ok(self.advance(fi))
    }

    fn advance(&mut self, fi: f64) -> f64 {
        self.advance_mode(fi, Settle::Own).0
    }

    fn advance_mode(&mut self, fi: f64, mode: Settle) -> (f64, f64) {
        // Shin eq 40: linear stage, its output feeds the exponential stage.
        let mid = self.linear.advance_mode(fi, mode);
        self.exponential.advance_mode(mid, mode)
    }

    /// Clears the state.
    pub fn reset(&mut self) {
        self.linear.reset();
        self.exponential.reset();
    }

    /// True when neither stage holds any distance.
    pub fn is_settled(&self) -> bool {
        self.linear.is_settled() && self.exponential.is_settled()
    }

    /// Distance still held inside both stages.
    pub fn pending(&self) -> f64 {
        self.linear.pending() + self.exponential.pending()
    }

    /// Sum of the two stages' bounds.
    pub fn settle_bound_ticks(&self) -> u64 {
        self.linear
            .settle_bound_ticks()
            .saturating_add(self.exponential.settle_bound_ticks())
    }
}

// ---------------------------------------------------------------------------
// Interchangeable filter
// ---------------------------------------------------------------------------

/// The interchangeable per-axis acc/dec filter (Kim §5: "interchangeable
/// acceleration/deceleration").
///
/// The variants hold fixed-capacity arrays (no heap), so the enum is large
/// (~33 KB): construct it once per axis and keep it in place.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone)]
pub enum AccDecFilter {
    /// Pass-through.
    None,
    /// Kim eq 1 / Shin eq 39.
    Linear(LinearFilter),
    /// Kim eq 9 (corrected) / Shin eq 36.
    Exponential(ExponentialFilter),
    /// Shin eq 40.
    Bell(BellFilter),
}

impl AccDecFilter {
    /// Builds a filter of `kind` with time constant `tau_s` seconds at sample
    /// time `ts` seconds: linear `m = round(tau_s/ts)` (Kim eq 2), exponential
    /// `a = tau_s/(tau_s+ts)` (Kim eq 8), bell both. For `FilterKind::None`
    /// only `ts` is checked.
    pub fn from_time_constant(kind: FilterKind, tau_s: f64, ts: f64) -> Result<Self, FilterError> {
        check_ts(ts)?;
        Ok(match kind {
            FilterKind::None => AccDecFilter::None,
            FilterKind::Linear => {
                AccDecFilter::Linear(LinearFilter::from_time_constant(tau_s, ts)?)
            }
            FilterKind::Exponential => {
                AccDecFilter::Exponential(ExponentialFilter::from_time_constant(tau_s, ts)?)
            }
            FilterKind::Bell => AccDecFilter::Bell(BellFilter::from_time_constant(tau_s, ts)?),
        })
    }

    /// The kind of this filter.
    pub fn kind(&self) -> FilterKind {
        match self {
            AccDecFilter::None => FilterKind::None,
            AccDecFilter::Linear(_) => FilterKind::Linear,
            AccDecFilter::Exponential(_) => FilterKind::Exponential,
            AccDecFilter::Bell(_) => FilterKind::Bell,
        }
    }

    /// One tick: input increment `fi` (counts this tick) → output increment.
    /// Non-finite inputs or `|fi| > MAX_INCREMENT` are treated as 0; use
    /// [`try_step`](Self::try_step) to detect them.
    pub fn step(&mut self, fi: f64) -> f64 {
        let fi = sanitize(fi);
        match self {
            AccDecFilter::None => fi,
            AccDecFilter::Linear(f) => f.advance(fi),
            AccDecFilter::Exponential(f) => f.advance(fi),
            AccDecFilter::Bell(f) => f.advance(fi),
        }
    }

    /// One tick; errors (state untouched) on an invalid input.
    pub fn try_step(&mut self, fi: f64) -> Result<f64, FilterError> {
        let fi = check_input(fi)?;
        Ok(self.step(fi))
    }

    /// One tick of a filter that empties together with the other axes of its group.
    ///
    /// The output is an unevaluated pair `hi + lo`: `lo` is non-zero only on the tick the
    /// filter empties and holds the sub-ulp part of its remainder, so a caller that adds both
    /// to an error-free sum ([`CompensatedSum`]) gets exactly `Σ f_i` once the filter is
    /// settled, on that tick and not one later.
    ///
    /// An exponential stage does not settle by itself when its pending distance falls under
    /// `SETTLE_THRESHOLD` (that tick depends on the axis's distance: a short axis would come
    /// to rest before a long one). It emits its remainder when `flush` is set, which the group
    /// does on the tick every member's input is zero and every member is
    /// [`tail_ready`](Self::tail_ready), so the axes of a synchronised move end on the same tick
    /// (Kim eq 10–14); the bound of [`settle_bound_ticks`](Self::settle_bound_ticks) still holds.
    /// The linear filter empties `m−1` ticks after its last input, as with [`step`](Self::step).
    pub fn step_group(&mut self, fi: f64, flush: bool) -> (f64, f64) {
        let fi = sanitize(fi);
        let mode = Settle::Group { flush };
        match self {
            AccDecFilter::None => (fi, 0.0),
            AccDecFilter::Linear(f) => f.advance_mode(fi, mode),
            AccDecFilter::Exponential(f) => f.advance_mode((fi, 0.0), mode),
            AccDecFilter::Bell(f) => f.advance_mode(fi, mode),
        }
    }

    /// Would this filter, given a zero input from now on, settle on its own this tick: its
    /// exponential stage (if any) holds at most `SETTLE_THRESHOLD` and nothing is left to
    /// reach it from a linear stage? Always true for the linear filter and the pass-through,
    /// which settle on a fixed tick. See [`step_group`](Self::step_group).
    pub fn tail_ready(&self) -> bool {
        match self {
            AccDecFilter::None | AccDecFilter::Linear(_) => true,
            AccDecFilter::Exponential(f) => f.tail_ready(),
            AccDecFilter::Bell(f) => f.linear.is_settled() && f.exponential.tail_ready(),
        }
    }

    /// Clears the state.
    pub fn reset(&mut self) {
        match self {
            AccDecFilter::None => {}
            AccDecFilter::Linear(f) => f.reset(),
            AccDecFilter::Exponential(f) => f.reset(),
            AccDecFilter::Bell(f) => f.reset(),
        }
    }

    /// True when no distance is left inside the filter.
    pub fn is_settled(&self) -> bool {
        match self {
            AccDecFilter::None => true,
            AccDecFilter::Linear(f) => f.is_settled(),
            AccDecFilter::Exponential(f) => f.is_settled(),
            AccDecFilter::Bell(f) => f.is_settled(),
        }
    }

    /// Distance still held inside the filter, `Σ inputs − Σ outputs`.
    pub fn pending(&self) -> f64 {
        match self {
            AccDecFilter::None => 0.0,
            AccDecFilter::Linear(f) => f.pending(),
            AccDecFilter::Exponential(f) => f.pending(),
            AccDecFilter::Bell(f) => f.pending(),
        }
    }

    /// Upper bound on zero-input ticks after the last non-zero input until
    /// settled.
    pub fn settle_bound_ticks(&self) -> u64 {
        match self {
            AccDecFilter::None => 0,
            AccDecFilter::Linear(f) => f.settle_bound_ticks(),
            AccDecFilter::Exponential(f) => f.settle_bound_ticks(),
            AccDecFilter::Bell(f) => f.settle_bound_ticks(),
        }
    }
}

// ---------------------------------------------------------------------------
// Presets per feed type (Shin Table 1)
// ---------------------------------------------------------------------------

/// Feed type (Shin §4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FeedType {
    /// Rapid traverse, G00.
    Rapid,
    /// Cutting feed, G01/G02/G03.
    Cutting,
    /// Manual jog.
    Jog,
}

/// Filter kind and time constant for one feed type.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FeedFilter {
    /// Filter kind.
    pub kind: FilterKind,
    /// Time constant, seconds (linear: `m·Ts`; exponential: `tau`; bell:
    /// both stages).
    pub time_constant_s: f64,
}

/// One experiment row of Shin Table 1 ("Experimental condition", vertical
/// machining center, inertia ratio 60 %): time constants in ms for the
/// conditions (a), (b), (c).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShinTable1Row {
    /// Feed type of the experiment.
    pub feed: FeedType,
    /// Filter kind of the experiment.
    pub kind: FilterKind,
    /// Figure of the paper showing the result.
    pub figure: u8,
    /// Feedrate of the experiment, m/min.
    pub feedrate_m_per_min: f64,
    /// x and y axis time constants (ms) for (a), (b), (c).
    pub xy_ms: [f64; 3],
    /// z axis time constants (ms) for (a), (b), (c).
    pub z_ms: [f64; 3],
}

/// Shin Table 1 (feed-type experiments), completed from the figure captions
/// (Fig. 6–11), which the OCR'd table garbles (it shifts the row labels:
/// Fig. 9 is the cutting exponential row, Figs. 10/11 the jog rows).
pub const SHIN_TABLE1: [ShinTable1Row; 6] = [
    ShinTable1Row {
        feed: FeedType::Rapid,
        kind: FilterKind::Linear,
        figure: 6,
        feedrate_m_per_min: 30.0,
        xy_ms: [40.0, 55.0, 70.0],
        z_ms: [40.0, 55.0, 70.0],
    },
    ShinTable1Row {
        feed: FeedType::Rapid,
        kind: FilterKind::Bell,
        figure: 7,
        feedrate_m_per_min: 30.0,
        xy_ms: [20.0, 25.0, 35.0],
        z_ms: [45.0, 65.0, 85.0],
    },
    ShinTable1Row {
        feed: FeedType::Cutting,
        kind: FilterKind::Linear,
        figure: 8,
        feedrate_m_per_min: 1.0,
        xy_ms: [10.0, 20.0, 30.0],
        z_ms: [20.0, 30.0, 40.0],
    },
    ShinTable1Row {
        feed: FeedType::Cutting,
        kind: FilterKind::Exponential,
        figure: 9,
        feedrate_m_per_min: 1.0,
        xy_ms: [10.0, 20.0, 30.0],
        z_ms: [20.0, 30.0, 40.0],
    },
    ShinTable1Row {
        feed: FeedType::Jog,
        kind: FilterKind::Linear,
        figure: 10,
        feedrate_m_per_min: 0.75,
        xy_ms: [25.0, 50.0, 70.0],
        z_ms: [20.0, 40.0, 60.0],
    },
    ShinTable1Row {
        feed: FeedType::Jog,
        kind: FilterKind::Exponential,
        figure: 11,
        feedrate_m_per_min: 0.75,
        xy_ms: [25.0, 50.0, 70.0],
        z_ms: [20.0, 40.0, 60.0],
    },
];

/// Shin Table 1, corner-cutting rows (G01, 1 m/min, x = y = z, Fig. 12):
/// conventional 15 ms and proposed 30 ms, for both linear and exponential;
/// the proposed value cut the corner error from ±70 to ±9 µm (linear) and
/// from ±60 to ±8 µm (exponential).
pub const SHIN_CORNER_CUTTING_MS: (f64, f64) = (15.0, 30.0);

/// Filter kind and time constant per feed type.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterPreset {
    /// G00.
    pub rapid: FeedFilter,
    /// G01/G02/G03.
    pub cutting: FeedFilter,
    /// Jog.
    pub jog: FeedFilter,
}

impl FilterPreset {
    /// Values from Shin Table 1 for the x and y axes, choosing in each feed
    /// type the condition the paper's text finds best:
    ///
    /// | feed | kind | tau | source |
    /// | --- | --- | --- | --- |
    /// | Rapid (G00, 30 m/min) | Bell | 35 ms | Table 1 / Fig. 7(c); §4.1 "x, y = 35 optimal" |
    /// | Cutting (G01, 1 m/min) | Linear | 30 ms | Table 1 corner-cutting rows / Fig. 12(b), "proposed" (±70 → ±9 µm) |
    /// | Jog (0.75 m/min) | Exponential | 50 ms | Table 1 / Fig. 11(b); §4.3 "x, y optimal 50–70" |
    ///
    /// All candidate values are in [`SHIN_TABLE1`] and
    /// [`SHIN_CORNER_CUTTING_MS`].
    pub fn shin_table1() -> Self {
        Self {
            rapid: FeedFilter {
                kind: FilterKind::Bell,
                time_constant_s: 0.035,
            },
            cutting: FeedFilter {
                kind: FilterKind::Linear,
                time_constant_s: 0.030,
            },
            jog: FeedFilter {
                kind: FilterKind::Exponential,
                time_constant_s: 0.050,
            },
        }
    }

    /// As [`shin_table1`](Self::shin_table1) for the z axis: rapid Bell 85 ms
    /// (Fig. 7(c), "z 70–85 optimal"), cutting Linear 30 ms (Fig. 12(b),
    /// x = y = z), jog Exponential 40 ms (Fig. 11(b), "z 40–60 optimal").
    pub fn shin_table1_z() -> Self {
        Self {
            rapid: FeedFilter {
                kind: FilterKind::Bell,
                time_constant_s: 0.085,
            },
            cutting: FeedFilter {
                kind: FilterKind::Linear,
                time_constant_s: 0.030,
            },
            jog: FeedFilter {
                kind: FilterKind::Exponential,
                time_constant_s: 0.040,
            },
        }
    }

    /// Setting for one feed type.
    pub fn get(&self, feed: FeedType) -> FeedFilter {
        match feed {
            FeedType::Rapid => self.rapid,
            FeedType::Cutting => self.cutting,
            FeedType::Jog => self.jog,
        }
    }

    /// Builds the filter for `feed` at sample time `ts`.
    pub fn build(&self, feed: FeedType, ts: f64) -> Result<AccDecFilter, FilterError> {
        let f = self.get(feed);
        AccDecFilter::from_time_constant(f.kind, f.time_constant_s, ts)
    }
}

// ---------------------------------------------------------------------------
// Tests
// ---------------------------------------------------------------------------

#[cfg(test)]
mod tests;
