//! The simulated plant of one axis: 12-bit ±10 V DAC, current-mode amplifier, motor and load,
//! quantised incremental encoder with its index (Z) channel, limit and home switches, and the
//! mechanical end stops.
//!
//! The motor is the rigid body of Thinh Fig 5: `J dω/dt = K_t·i − b·ω − T_c·sgn(ω) − T_d`, with
//! the amplifier `i = clamp(K_a·u, ±I_max)`. Over one servo period the input is held (zero-order
//! hold), so the linear part is integrated exactly; Coulomb friction is handled piecewise: the
//! motor sticks while the drive torque cannot overcome it, and a velocity that would cross zero
//! inside the period stops at zero first.

pub mod analog;
pub mod aux;
pub mod faults;
pub mod io;
pub mod leadscrew;

use core::f64::consts::TAU;
use firmware_proto::Io;

/// Parameters of one axis's motor, load, amplifier and encoder (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotorParams {
    /// Total inertia J, kg·m².
    pub inertia: f64,
    /// Viscous damping b, N·m·s/rad.
    pub damping: f64,
    /// Torque constant K_t, N·m/A.
    pub kt: f64,
    /// Coulomb friction T_c, N·m.
    pub coulomb: f64,
    /// Amplifier transconductance K_a, A/V.
    pub amp_gain: f64,
    /// Amplifier current limit, A.
    pub current_limit: f64,
    /// Encoder counts per revolution (after quadrature).
    pub counts_per_rev: u32,
    /// Optional resonance: a load coupled to the motor through a spring (two-mass model).
    /// `inertia` is then the motor side; the encoder is on the motor (semi-closed loop)
    /// unless the resonance puts it on the load ([`Resonance::encoder_on_load`]).
    pub resonance: Option<Resonance>,
}

/// A compliant coupling to a second inertia: `J_m ω_m' = τ − k(θ_m − θ_l) − c(ω_m − ω_l) − …`,
/// `J_l ω_l' = k(θ_m − θ_l) + c(ω_m − ω_l)`. Resonance at `sqrt(k (1/J_m + 1/J_l))`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resonance {
    /// Load inertia J_l, kg·m².
    pub load_inertia: f64,
    /// Coupling stiffness k, N·m/rad.
    pub stiffness: f64,
    /// Coupling damping c, N·m·s/rad.
    pub damping: f64,
    /// The encoder reads the load (a linear scale on the table: full closed loop), not the
    /// motor. Seen from the motor the coupling is a pair: an anti-resonance at
    /// `sqrt(k/J_l)` below the resonance, the drive's torque and the encoder on the same
    /// shaft (collocated), so the phase never falls below the rigid body's −180° and a loop
    /// closed on the motor does not ring at the resonance. Seen from the load there is no
    /// anti-resonance: past the resonance the phase falls by another 180°, and a loop whose
    /// gain there is near 1 rings at it (the case a notch is for).
    pub encoder_on_load: bool,
}

impl Resonance {
    /// A coupling that resonates at `hz` with damping ratio `zeta`, for motor inertia `jm` and
    /// load inertia `jl`.
    pub fn at(hz: f64, zeta: f64, jm: f64, jl: f64) -> Self {
        let w = 2.0 * core::f64::consts::PI * hz;
        let k = w * w / (1.0 / jm + 1.0 / jl);
        let j_eq = jm * jl / (jm + jl);
        Self {
            load_inertia: jl,
            stiffness: k,
            damping: 2.0 * zeta * w * j_eq,
            encoder_on_load: false,
        }
    }

    /// The same coupling read on the load ([`Resonance::encoder_on_load`]).
    pub fn on_load(self) -> Self {
        Self {
            encoder_on_load: true,
            ..self
        }
    }
}

impl MotorParams {
    /// The default axis: a 400 W class servo with its load. 10,000 counts/rev, 3 N·m peak at
    /// 10 V, J = 5·10⁻⁴ kg·m² (about 9.5·10⁶ counts/s² at full output).
    pub const fn default_servo() -> Self {
        Self {
            inertia: 5e-4,
            damping: 1e-4,
            kt: 0.3,
            coulomb: 0.01,
            amp_gain: 1.0,
            current_limit: 10.0,
            counts_per_rev: 10_000,
            resonance: None,
        }
    }

    /// Encoder counts per radian.
    pub fn counts_per_rad(&self) -> f64 {
        self.counts_per_rev as f64 / TAU
    }

    /// Volts per count/s² that produce an acceleration (ideal acceleration feed-forward).
    pub fn volts_per_accel(&self) -> f64 {
        self.total_inertia() / (self.counts_per_rad() * self.kt * self.amp_gain)
    }

    /// Motor plus load inertia, kg·m².
    pub fn total_inertia(&self) -> f64 {
        self.inertia + self.resonance.map_or(0.0, |r| r.load_inertia)
    }

    /// An axis of Yeh's die bonder (Table 1): the first-order speed model of Yeh eq 2.2,
    /// `dw/dt = −w/τ + (K_c/τ)·u`, realised as an inertia with viscous damping b = J/τ and a
    /// torque constant K_c·b per volt; no friction; 10,000 counts/rev (K_e = 10000/2π). `kc_per_volt`
    /// is K_c in (rad/s)/V: Table 1's K_c in (rad/s)/DU divided by 10 (1 DU = 10 V, the DAC's
    /// full scale, so Umax = 1 DU = 10 V).
    pub fn die_bonder(kc_per_volt: f64, tau: f64) -> Self {
        let inertia = 1e-4;
        let damping = inertia / tau;
        Self {
            inertia,
            damping,
            kt: kc_per_volt * damping,
            coulomb: 0.0,
            amp_gain: 1.0,
            current_limit: 1e9,
            counts_per_rev: 10_000,
            resonance: None,
        }
    }

    /// The machine-tool axis of the Shin corner experiment: the default servo driving a table
    /// through a compliant coupling that resonates at `hz` (ζ = 0.03); 1 count = 1 µm (10 mm
    /// lead, 10,000 counts/rev). Motor 2·10⁻⁴, table 3·10⁻⁴ kg·m² (total as the default).
    pub fn machine_table(hz: f64) -> Self {
        let (jm, jl) = (2e-4, 3e-4);
        Self {
            inertia: jm,
            resonance: Some(Resonance::at(hz, 0.03, jm, jl)),
            ..Self::default_servo()
        }
    }

    /// Velocity, counts/s, per volt per second at the motor (loop-gain scale for tuning).
    pub fn accel_per_volt(&self) -> f64 {
        1.0 / self.volts_per_accel()
    }

    /// Are the parameters physically meaningful?
    pub fn is_valid(&self) -> bool {
        let pos = |x: f64| x.is_finite() && x > 0.0;
        let nonneg = |x: f64| x.is_finite() && x >= 0.0;
        pos(self.inertia)
            && nonneg(self.damping)
            && pos(self.kt)
            && nonneg(self.coulomb)
            && pos(self.amp_gain)
            && pos(self.current_limit)
            && self.counts_per_rev > 0
    }
}

impl Default for MotorParams {
    fn default() -> Self {
        Self::default_servo()
    }
}

/// Mechanical end stops (hard stops) of an axis, in encoder counts: the shaft cannot pass them.
/// Running into one stops the shaft dead (an inelastic stop) and the motor stalls there, whatever
/// torque it makes. Infinite (the default): none.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EndStops {
    /// The negative end stop, counts (`−∞`: none).
    pub neg: f64,
    /// The positive end stop, counts (`+∞`: none).
    pub pos: f64,
}

impl Default for EndStops {
    fn default() -> Self {
        Self {
            neg: f64::NEG_INFINITY,
            pos: f64::INFINITY,
        }
    }
}

/// One axis's mechanical state.
#[derive(Debug, Clone, Copy)]
pub struct Motor {
    /// Parameters.
    pub params: MotorParams,
    /// The mechanical end stops (on the motor shaft, where the encoder is).
    pub end_stops: EndStops,
    /// Shaft angle, rad.
    pub theta: f64,
    /// Shaft speed, rad/s.
    pub omega: f64,
    /// External disturbance torque T_d, N·m (opposes positive motion when positive).
    pub disturbance: f64,
    /// Load angle and speed (two-mass model only; equal to the motor's otherwise).
    pub load_theta: f64,
    /// Load speed, rad/s.
    pub load_omega: f64,
    /// The last exponent of the viscous decay and its `exp` (`integrate`): every full period
    /// of a motor with unchanged parameters takes the same one, and `exp` is a library call.
    /// Not part of the state (equality ignores it).
    decay_memo: (f64, f64),
}

impl PartialEq for Motor {
    fn eq(&self, other: &Self) -> bool {
        let Self {
            params,
            end_stops,
            theta,
            omega,
            disturbance,
            load_theta,
            load_omega,
            decay_memo: _,
        } = self;
        (
            *params,
            *end_stops,
            *theta,
            *omega,
            *disturbance,
            *load_theta,
            *load_omega,
        ) == (
            other.params,
            other.end_stops,
            other.theta,
            other.omega,
            other.disturbance,
            other.load_theta,
            other.load_omega,
        )
    }
}

impl Motor {
    /// At rest at angle 0.
    pub fn new(params: MotorParams) -> Self {
        Self {
            params,
            end_stops: EndStops::default(),
            theta: 0.0,
            omega: 0.0,
            disturbance: 0.0,
            load_theta: 0.0,
            load_omega: 0.0,
            decay_memo: (0.0, 1.0),
        }
    }

    /// The angle the encoder reads: the motor's, or the load's when the resonance puts the
    /// encoder there.
    #[inline]
    pub fn sensed_theta(&self) -> f64 {
        match self.params.resonance {
            Some(r) if r.encoder_on_load => self.load_theta,
            _ => self.theta,
        }
    }

    /// The encoder reading: the angle quantised to whole counts.
    #[inline]
    pub fn encoder(&self) -> i64 {
        floor_i64(self.sensed_theta() * self.params.counts_per_rad())
    }

    /// Position in (unquantised) counts, where the encoder reads it.
    pub fn position_counts(&self) -> f64 {
        self.sensed_theta() * self.params.counts_per_rad()
    }

    /// The shaft's position and encoder reading now, [`Reading::of`].
    #[inline]
    pub fn reading(&self) -> Reading {
        Reading::of(self)
    }

    /// Advance by `dt` seconds with the amplifier input `volts` held.
    pub fn step(&mut self, volts: f64, dt: f64) {
        let p = self.params;
        let volts = if volts.is_finite() { volts } else { 0.0 };
        let current = (p.amp_gain * volts).clamp(-p.current_limit, p.current_limit);
        let drive = p.kt * current - self.disturbance;
        if let Some(r) = p.resonance {
            self.step_two_mass(drive, &r, dt);
            self.end_stop();
            return;
        }
        self.step_rigid(drive, dt);
        self.end_stop();
    }

    /// A shaft past an end stop is put back on it, stopped (what moved it into the stop
    /// pushes on without moving it: the motor stalls).
    fn end_stop(&mut self) {
        if self.end_stops == EndStops::default() {
            return; // none: no angle is beyond ±∞ (the checks below would find nothing)
        }
        let c = self.params.counts_per_rad();
        let (lo, hi) = (self.end_stops.neg / c, self.end_stops.pos / c);
        if self.theta > hi {
            self.theta = hi;
            self.omega = self.omega.min(0.0);
        } else if self.theta < lo {
            self.theta = lo;
            self.omega = self.omega.max(0.0);
        }
    }

    /// The rigid body over `dt` with the drive torque `drive` held, Coulomb friction piecewise.
    fn step_rigid(&mut self, drive: f64, dt: f64) {
        let p = self.params;
        let mut left = dt;
        // At most three pieces: move, stop at zero, break away the other way.
        for _ in 0..3 {
            if left <= 0.0 {
                break;
            }
            if self.omega == 0.0 {
                if drive.abs() <= p.coulomb {
                    return; // stiction holds
                }
                let sign = drive.signum();
                left -= self.integrate(drive - sign * p.coulomb, sign, left);
            } else {
                let sign = self.omega.signum();
                left -= self.integrate(drive - sign * p.coulomb, sign, left);
            }
        }
    }

    /// Two-mass model: semi-implicit Euler in sub-steps of at most 20 µs (the resonance is
    /// tens of Hz: ω·h ≪ 1). Coulomb friction acts on the motor, with stiction.
    fn step_two_mass(&mut self, drive: f64, r: &Resonance, dt: f64) {
        let p = self.params;
        let n = (dt / 20e-6).ceil().clamp(1.0, 1000.0);
        let h = dt / n;
        for _ in 0..n as usize {
            let coupling = r.stiffness * (self.theta - self.load_theta)
                + r.damping * (self.omega - self.load_omega);
            let net = drive - p.damping * self.omega - coupling;
            let acc_m = if self.omega == 0.0 && net.abs() <= p.coulomb {
                0.0
            } else {
                let sign = if self.omega != 0.0 {
                    self.omega.signum()
                } else {
                    net.signum()
                };
                (net - sign * p.coulomb) / p.inertia
            };
            let w = self.omega + acc_m * h;
            // Friction stops the motor; it does not reverse it within a sub-step.
            self.omega = if self.omega != 0.0 && w.signum() != self.omega.signum() {
                0.0
            } else {
                w
            };
            self.load_omega += coupling / r.load_inertia * h;
            self.theta += self.omega * h;
            self.load_theta += self.load_omega * h;
        }
    }

    /// Where the load is, in encoder counts (the tool of a machine; equal to the motor's
    /// position for a rigid axis).
    pub fn load_position_counts(&self) -> f64 {
        match self.params.resonance {
            Some(_) => self.load_theta * self.params.counts_per_rad(),
            None => self.position_counts(),
        }
    }

    /// Integrate `J ω' = tau − b ω` exactly for up to `dt`, stopping early if ω reaches zero
    /// against `sign` (the direction friction was computed for). Returns the time used.
    fn integrate(&mut self, tau: f64, sign: f64, dt: f64) -> f64 {
        let (j, b) = (self.params.inertia, self.params.damping);
        let w0 = self.omega;
        // Time at which ω would reach zero, if it decelerates through it.
        let t_zero = if b > 0.0 {
            let w_inf = tau / b;
            // ω(t) = w_inf + (w0 − w_inf)·e^{−bt/J} = 0  ⇒  t = (J/b)·ln((w_inf − w0)/w_inf)
            let ratio = (w_inf - w0) / w_inf;
            if w0 != 0.0 && w_inf * sign < 0.0 && ratio > 1.0 {
                (j / b) * ratio.ln()
            } else {
                f64::INFINITY
            }
        } else if w0 != 0.0 && tau * sign < 0.0 {
            -w0 * j / tau
        } else {
            f64::INFINITY
        };
        let t = dt.min(t_zero);
        if b > 0.0 {
            let w_inf = tau / b;
            let x = -b * t / j;
            if x.to_bits() != self.decay_memo.0.to_bits() {
                self.decay_memo = (x, x.exp());
            }
            let decay = self.decay_memo.1;
            self.theta += w_inf * t + (w0 - w_inf) * (j / b) * (1.0 - decay);
            self.omega = w_inf + (w0 - w_inf) * decay;
        } else {
            let a = tau / j;
            self.theta += w0 * t + 0.5 * a * t * t;
            self.omega = w0 + a * t;
        }
        if t_zero <= dt {
            self.omega = 0.0;
        }
        t
    }
}

/// `x.floor() as i64` for every `x`, inline (`f64::floor` is a call on the baseline x86-64,
/// and the plant takes four encoder readings an axis a period). The cast truncates towards
/// zero and saturates (NaN gives 0); a truncation above `x` is a negative `x` with a fraction,
/// whose floor is one lower. The truncated value is exact as an `f64` wherever `x` has a
/// fraction (|x| < 2⁵²), and beyond that `x` is an integer, so the comparison is exact too.
#[inline]
pub(crate) fn floor_i64(x: f64) -> i64 {
    let t = x as i64;
    if t as f64 > x {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// A shaft's position in counts ([`Motor::position_counts`]) and its encoder reading
/// ([`Motor::encoder`]), with the angle and resolution they were taken at. The emulator reads
/// every shaft at the end of a period and again at the start of the next (a division each);
/// a shaft nothing moved in between reads the same, and [`Reading::again`] reuses the reading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reading {
    theta: f64,
    counts_per_rev: u32,
    /// Position, counts.
    pub position: f64,
    /// The encoder count.
    pub count: i64,
}

impl Reading {
    /// The reading of `m` now.
    #[inline]
    pub fn of(m: &Motor) -> Self {
        let position = m.position_counts();
        Self {
            theta: m.sensed_theta(),
            counts_per_rev: m.params.counts_per_rev,
            position,
            count: floor_i64(position),
        }
    }

    /// This reading if it was taken of `m` as it is now (the same angle, to the bit, and
    /// resolution), else a new one.
    #[inline]
    pub fn again(self, m: &Motor) -> Self {
        if self.theta.to_bits() == m.sensed_theta().to_bits()
            && self.counts_per_rev == m.params.counts_per_rev
        {
            self
        } else {
            Self::of(m)
        }
    }
}

/// The home switch of an axis, in the geometries of CiA 402's homing methods, at positions in
/// encoder counts.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum HomeSwitch {
    /// No home switch.
    #[default]
    None,
    /// Active at and above this position: CiA 402's "positive home switch" (methods 3, 4, 19,
    /// 20).
    Above(f64),
    /// Active at and below this position: the "negative home switch" (methods 5, 6, 21, 22).
    Below(f64),
    /// Active from `lower` to `upper`: a switch of some width, with a lower and an upper edge
    /// (methods 7–14, 23–30).
    Between {
        /// The lower edge, counts.
        lower: f64,
        /// The upper edge, counts.
        upper: f64,
    },
}

impl HomeSwitch {
    /// Is the switch active at position `counts`?
    pub fn active(&self, counts: f64) -> bool {
        match *self {
            HomeSwitch::None => false,
            HomeSwitch::Above(p) => counts >= p,
            HomeSwitch::Below(p) => counts <= p,
            HomeSwitch::Between { lower, upper } => (lower..=upper).contains(&counts),
        }
    }
}

/// The switches along an axis's travel, at positions in encoder counts. A limit switch is
/// active at and beyond its position; the home switch as [`HomeSwitch`] says. Infinite limit
/// positions and [`HomeSwitch::None`] (the default) mean no switch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Switches {
    /// Positive limit switch, counts (`+∞`: none).
    pub limit_pos: f64,
    /// Negative limit switch, counts (`−∞`: none).
    pub limit_neg: f64,
    /// The home switch.
    pub home: HomeSwitch,
}

impl Default for Switches {
    fn default() -> Self {
        Self {
            limit_pos: f64::INFINITY,
            limit_neg: f64::NEG_INFINITY,
            home: HomeSwitch::None,
        }
    }
}

impl Switches {
    /// Limits at `neg` and `pos`, no home switch.
    pub fn limits(neg: f64, pos: f64) -> Self {
        Self {
            limit_neg: neg,
            limit_pos: pos,
            ..Self::default()
        }
    }

    /// The same switches with this home switch.
    pub fn with_home(self, home: HomeSwitch) -> Self {
        Self { home, ..self }
    }

    /// The input bits at position `counts`.
    pub fn inputs(&self, counts: f64) -> Io {
        let mut bits = Io::empty();
        if counts >= self.limit_pos {
            bits |= Io::LIMIT_POS;
        }
        if counts <= self.limit_neg {
            bits |= Io::LIMIT_NEG;
        }
        if self.home.active(counts) {
            bits |= Io::HOME;
        }
        bits
    }
}

/// The index (zero, Z) channel of an axis's incremental encoder: a pulse once per revolution,
/// one count wide, at the counts `offset + k·counts_per_rev`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IndexPulse {
    /// Counts from one pulse to the next; 0: the motor's counts per revolution
    /// ([`MotorParams::counts_per_rev`]).
    pub counts_per_rev: u32,
    /// The count of one pulse (any of them).
    pub offset: i64,
    /// The encoder has an index channel (`false`: no pulse ever comes).
    pub present: bool,
}

impl Default for IndexPulse {
    /// A pulse per motor revolution, at count 0 and its multiples.
    fn default() -> Self {
        Self {
            counts_per_rev: 0,
            offset: 0,
            present: true,
        }
    }
}

/// An encoder's index channel as the card's encoder interface sees it, with its hardware latch:
/// on each index pulse the latch captures the encoder count and bumps a counter, so an index
/// crossed between two servo ticks is never missed and its count is exact.
///
/// The pulse occupies one count `p`; the latch fires when the count enters `p`, from below or
/// from above, and holds `p`: the same count in both directions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct IndexChannel {
    pulse: IndexPulse,
    last: Option<i64>,
    /// The count latched at the last pulse.
    pub count: i64,
    /// Pulses latched since power-up (wrapping).
    pub latches: u32,
    /// Counts strictly between two neighbouring pulses (empty at first): a move within them
    /// crosses none, which the channel sees without the divisions that find the pulses.
    clear: (i64, i64),
}

impl IndexChannel {
    /// A latch on this channel (the period resolved: `counts_per_rev` is never 0 here).
    pub fn new(pulse: IndexPulse, motor_counts_per_rev: u32) -> Self {
        let n = match pulse.counts_per_rev {
            0 => motor_counts_per_rev,
            n => n,
        };
        Self {
            pulse: IndexPulse {
                counts_per_rev: n.max(1),
                ..pulse
            },
            last: None,
            count: 0,
            latches: 0,
            clear: (0, 0),
        }
    }

    /// The encoder moved to `count` since the last sample: latch the pulses it crossed.
    /// `signal`: the index signal reaches the card (a lost encoder latches nothing).
    pub fn sample(&mut self, count: i64, signal: bool) {
        let last = self.last.replace(count);
        let Some(from) = last else { return };
        if !(signal && self.pulse.present) || from == count {
            return;
        }
        let (lo, hi) = self.clear;
        if lo < from.min(count) && from.max(count) < hi {
            return;
        }
        let n = self.pulse.counts_per_rev as i64;
        let off = self.pulse.offset;
        // The first pulse above `count`, and the one before it.
        let above = count + 1 + (off - (count + 1)).rem_euclid(n);
        self.clear = (above - n, above);
        // The pulses entered: from < p <= count going up, count <= p < from going down.
        let (first, last, step) = if count > from {
            let p = from + 1 + (off - (from + 1)).rem_euclid(n);
            if p > count {
                return;
            }
            (p, count - (count - p).rem_euclid(n), 1)
        } else {
            let p = from - 1 - (from - 1 - off).rem_euclid(n);
            if p < count {
                return;
            }
            (p, count + (p - count).rem_euclid(n), -1)
        };
        let crossed = (last - first) / n * step + 1;
        self.count = last;
        self.latches = self.latches.wrapping_add(crossed as u32);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `floor_i64` is `floor` then the saturating cast, for every kind of `f64`.
    #[test]
    fn floor_i64_is_floor_then_cast() {
        let same = |x: f64| assert_eq!(floor_i64(x), x.floor() as i64, "{x:e}");
        let edges = [
            0.0,
            0.5,
            1.0,
            4_503_599_627_370_495.5,
            4_503_599_627_370_496.0,
            9_007_199_254_740_993.0,
            9.223_372_036_854_775e18,
            f64::MAX,
            f64::INFINITY,
            f64::NAN,
            5e-324,
        ];
        for x in edges {
            for y in [
                x,
                f64::from_bits(x.to_bits() + 1),
                f64::from_bits(x.to_bits().saturating_sub(1)),
            ] {
                same(y);
                same(-y);
            }
        }
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        for _ in 0..200_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let m = (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            let e = (x % 140) as i32 - 70;
            same(m * 2f64.powi(e));
        }
    }

    /// The servo's default tuning assumes this plant's default motor: they agree.
    #[test]
    fn the_default_tuning_is_for_the_default_motor() {
        let m = MotorParams::default_servo();
        let k = crate::servo::ffpiv::DEFAULT_ACCEL_PER_VOLT;
        assert!((m.accel_per_volt() - k).abs() <= 1e-12 * k);
    }

    #[test]
    fn constant_torque_matches_closed_form_without_friction() {
        let params = MotorParams {
            coulomb: 0.0,
            ..MotorParams::default_servo()
        };
        let mut m = Motor::new(params);
        // 1 V for 1 s in 10,000 steps.
        for _ in 0..10_000 {
            m.step(1.0, 1e-4);
        }
        let (j, b, tau) = (params.inertia, params.damping, params.kt * params.amp_gain);
        let w = tau / b * (1.0 - (-b / j).exp());
        let th = tau / b * (1.0 - j / b * (1.0 - (-b / j).exp()));
        assert!((m.omega - w).abs() < 1e-9 * w, "{} vs {}", m.omega, w);
        assert!((m.theta - th).abs() < 1e-9 * th, "{} vs {}", m.theta, th);
    }

    #[test]
    fn stiction_holds_and_friction_stops_without_reversing() {
        let mut m = Motor::new(MotorParams::default_servo());
        let below = 0.9 * m.params.coulomb / (m.params.kt * m.params.amp_gain);
        m.step(below, 1e-3);
        assert_eq!((m.theta, m.omega), (0.0, 0.0));
        m.omega = 1.0;
        for _ in 0..1000 {
            m.step(0.0, 1e-3);
            assert!(m.omega >= 0.0);
        }
        assert_eq!(m.omega, 0.0);
        // Coasting distance with friction and damping is positive and bounded by ω²J/(2T_c).
        let bound = m.params.inertia / (2.0 * m.params.coulomb);
        assert!(m.theta > 0.0 && m.theta <= bound);
    }

    #[test]
    fn switches_follow_position() {
        let s = Switches::limits(-1000.0, 2000.0).with_home(HomeSwitch::Between {
            lower: -5.0,
            upper: 5.0,
        });
        assert_eq!(s.inputs(0.0), Io::HOME);
        assert_eq!(s.inputs(5.0), Io::HOME);
        assert_eq!(s.inputs(5.5), Io::empty());
        assert_eq!(s.inputs(500.0), Io::empty());
        assert_eq!(s.inputs(2000.0), Io::LIMIT_POS);
        assert_eq!(s.inputs(-1e9), Io::LIMIT_NEG);
        assert_eq!(Switches::default().inputs(1e300), Io::empty());
        let above = Switches::default().with_home(HomeSwitch::Above(100.5));
        assert_eq!(above.inputs(100.0), Io::empty());
        assert_eq!(above.inputs(1e9), Io::HOME);
        let below = Switches::default().with_home(HomeSwitch::Below(100.5));
        assert_eq!(below.inputs(100.0), Io::HOME);
        assert_eq!(below.inputs(101.0), Io::empty());
    }

    /// The latch holds the pulse's own count whichever way it was crossed, counts every pulse
    /// crossed between two samples (several in one sample too), and latches nothing without a
    /// signal or an index channel.
    #[test]
    fn the_index_latch_holds_the_pulse_count_in_both_directions() {
        let pulse = IndexPulse {
            offset: 250,
            ..IndexPulse::default()
        };
        let mut l = IndexChannel::new(pulse, 10_000);
        l.sample(0, true);
        l.sample(249, true);
        assert_eq!(l.latches, 0);
        l.sample(250, true);
        assert_eq!((l.count, l.latches), (250, 1));
        l.sample(251, true);
        l.sample(250, true); // entering 250 from above
        assert_eq!((l.count, l.latches), (250, 2));
        l.sample(-9_751, true); // down across -9,750 only (250 itself is not entered again)
        assert_eq!((l.count, l.latches), (-9_750, 3));
        l.sample(30_300, true); // up across -9,750, 250, 10,250, 20,250, 30,250
        assert_eq!((l.count, l.latches), (30_250, 8));
        l.sample(0, false);
        assert_eq!(l.latches, 8, "no signal, no latch");
        let mut none = IndexChannel::new(
            IndexPulse {
                present: false,
                ..pulse
            },
            10_000,
        );
        none.sample(0, true);
        none.sample(100_000, true);
        assert_eq!(none.latches, 0);
        // Its own period, not the motor's.
        let mut short = IndexChannel::new(
            IndexPulse {
                counts_per_rev: 1000,
                offset: 0,
                present: true,
            },
            10_000,
        );
        short.sample(-1, true);
        short.sample(2_500, true);
        assert_eq!((short.count, short.latches), (2_000, 3));
    }

    /// Small moves back and forth near pulses (the channel's shortcut between two pulses, and
    /// moves that start or end on one) latch what counting every pulse entered latches.
    #[test]
    fn the_index_latch_counts_the_pulses_of_a_random_walk() {
        let (n, off) = (97i64, 13i64);
        let mut l = IndexChannel::new(
            IndexPulse {
                counts_per_rev: n as u32,
                offset: off,
                present: true,
            },
            10_000,
        );
        let (mut pos, mut latches, mut held) = (0i64, 0u32, 0i64);
        let mut x = 0x2545_F491_4F6C_DD1Du64;
        l.sample(pos, true);
        for _ in 0..20_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let to = pos + (x % 61) as i64 - 30;
            let pulses = |a: i64, b: i64| (a..=b).filter(|p| (p - off).rem_euclid(n) == 0);
            let entered: Vec<i64> = match to.cmp(&pos) {
                core::cmp::Ordering::Greater => pulses(pos + 1, to).collect(),
                core::cmp::Ordering::Less => pulses(to, pos - 1).collect(),
                core::cmp::Ordering::Equal => Vec::new(),
            };
            latches += entered.len() as u32;
            // The latch holds the last one entered: the highest going up, the lowest going down.
            let last = if to > pos {
                entered.last()
            } else {
                entered.first()
            };
            if let Some(&p) = last {
                held = p;
            }
            l.sample(to, true);
            pos = to;
            assert_eq!((l.latches, l.count), (latches, held), "at {pos}");
        }
        assert!(latches > 100, "the walk crossed pulses: {latches}");
    }

    /// A mechanical end stop: the shaft runs into it and stalls there at full torque, and
    /// leaves it when driven the other way.
    #[test]
    fn an_end_stop_stalls_the_motor() {
        let mut m = Motor::new(MotorParams::default_servo());
        m.end_stops = EndStops {
            neg: -100.5,
            pos: 2_000.5,
        };
        for _ in 0..10_000 {
            m.step(3.0, 1e-4);
            assert!(m.position_counts() <= 2_000.5 + 1e-9);
        }
        assert_eq!(m.encoder(), 2_000);
        assert_eq!(m.omega, 0.0);
        for _ in 0..10_000 {
            m.step(-3.0, 1e-4);
        }
        assert_eq!(m.encoder(), -101);
    }

    #[test]
    fn encoder_quantises_down() {
        let mut m = Motor::new(MotorParams::default_servo());
        m.theta = 1.5 / m.params.counts_per_rad();
        assert_eq!(m.encoder(), 1);
        m.theta = -0.5 / m.params.counts_per_rad();
        assert_eq!(m.encoder(), -1);
    }
}

#[cfg(test)]
mod two_mass_tests {
    use super::*;

    /// Free vibration of the coupling rings at the designed frequency and decays at ζ.
    #[test]
    fn coupling_rings_at_its_resonance() {
        let mut params = MotorParams::machine_table(33.0);
        params.coulomb = 0.0;
        params.damping = 0.0;
        let mut m = Motor::new(params);
        m.load_theta = 1e-3; // twist the coupling, release
        let dt = 1e-4;
        let mut crossings = Vec::new();
        let mut prev = m.theta - m.load_theta;
        for k in 0..20_000 {
            m.step(0.0, dt);
            let tw = m.theta - m.load_theta;
            if prev < 0.0 && tw >= 0.0 {
                crossings.push(k as f64 * dt);
            }
            prev = tw;
        }
        let period = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
        assert!(
            (1.0 / period - 33.0).abs() < 0.2,
            "rings at {} Hz",
            1.0 / period
        );
        // Momentum is conserved (no external torque): the centre of mass does not drift.
        let (jm, jl) = (params.inertia, params.resonance.unwrap().load_inertia);
        assert!((jm * m.omega + jl * m.load_omega).abs() < 1e-9);
    }
}
