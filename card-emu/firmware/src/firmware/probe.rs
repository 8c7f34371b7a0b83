//! Touch probes: PLCopen MC_TouchProbe and MC_AbortTrigger (layout 1.7).
//!
//! A channel captures one axis's position at an edge of a digital input, or at the axis's
//! encoder index pulse. The encoder interface timestamps an input edge within the tick (the
//! FPGA's edge capture); the position at that instant is interpolated between the counts at
//! the tick's two ends, each count `n` taken as the middle of its cell (`n + 0.5`), as the
//! comparator does (`compare::crossing`). The index is latched by the encoder interface at
//! its exact count (the cell's middle is reported too). An optional window keeps only edges
//! whose position lies in `[lo, hi]`; the others are counted (`outside`). Single shot ends after
//! the first capture; continuous keeps capturing into a ring of [`PROBE_QUEUE`] positions in
//! the status, each capture also an `MC_EV_PROBE`.
//!
//! Pure logic over plain numbers: no window, no clock, no allocation.

use firmware_proto::cmd;
use firmware_proto::{raw, NackCode, INPUTS, MAX_POSITION, PROBE_QUEUE};

/// The probe's trigger input: an input number, or the encoder index.
pub const INDEX: u32 = raw::MC_PROBE_INDEX;

/// An armed probe's parameters, validated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProbeArm {
    /// The axis captured.
    pub axis: usize,
    /// The input (0..`INPUTS`) or [`INDEX`].
    pub input: u32,
    /// Capture on a rising (becoming active) edge.
    pub rising: bool,
    /// Capture on a falling edge.
    pub falling: bool,
    /// Keep capturing after the first.
    pub continuous: bool,
    /// Only edges with the position in `[lo, hi]` count.
    pub window: Option<(f64, f64)>,
    /// A capture halts the axis's motion (`MC_PROBE_HALT`).
    pub halt: bool,
    /// The arm command's seq.
    pub seq: u32,
}

/// Validate `MC_OP_PROBE_ARM`'s window (decoding checked the channel, the flags and the
/// input): finite, in the position range, `lo <= hi`.
pub fn validate_arm(axis: usize, p: &cmd::ProbeArm, seq: u32) -> Result<ProbeArm, NackCode> {
    let window = match p.window {
        Some((lo, hi)) => {
            if !(lo.is_finite() && hi.is_finite()) {
                return Err(NackCode::NotFinite);
            }
            if lo.abs() > MAX_POSITION || hi.abs() > MAX_POSITION {
                return Err(NackCode::OutOfRange);
            }
            if lo > hi {
                return Err(NackCode::ProbeInput);
            }
            Some((lo, hi))
        }
        None => None,
    };
    Ok(ProbeArm {
        axis,
        input: u32::from(p.input),
        rising: p.rising,
        falling: p.falling,
        continuous: p.continuous,
        window,
        halt: p.halt,
        seq,
    })
}

/// What triggered in a tick, as the encoder interface saw it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Trigger {
    /// An input edge at this fraction of the tick just ended, rising (`true`) or falling.
    Edge {
        /// The instant, a fraction of the period in `[0, 1]`.
        frac: f64,
        /// Rising (became active).
        rising: bool,
    },
    /// The index pulse, latched at this position (the axis frame, the cell's middle).
    Index {
        /// The latched position.
        position: f64,
    },
}

/// One capture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Capture {
    /// The capture number since the arm (1, 2, …).
    pub number: u32,
    /// The position, counts.
    pub position: f64,
    /// The arm's seq.
    pub seq: u32,
}

/// One touch-probe channel.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Probe {
    arm: Option<ProbeArm>,
    done: bool,
    captures: u32,
    outside: u32,
    queue: [f64; PROBE_QUEUE],
    last_tick: f64,
}

impl Probe {
    /// The armed parameters, if armed.
    pub fn armed(&self) -> Option<&ProbeArm> {
        self.arm.as_ref().filter(|_| !self.done)
    }

    /// MC_TouchProbe: (re)arm.
    pub fn start(&mut self, arm: ProbeArm) {
        *self = Self {
            arm: Some(arm),
            ..Self::default()
        };
    }

    /// MC_AbortTrigger.
    pub fn abort(&mut self) {
        self.arm = None;
        self.done = false;
    }

    /// One tick: the axis moved from `x0` to `x1` (cell middles) over the tick ending at
    /// `tick`, and `trigger` is what its input did.
    pub fn tick(
        &mut self,
        x0: f64,
        x1: f64,
        tick: u64,
        trigger: Option<Trigger>,
    ) -> Option<Capture> {
        self.tick_wrapped(x0, x1, tick, trigger, |x| x)
    }

    /// [`Probe::tick`] on an axis whose captured position is reported as `wrap` makes it (a
    /// modulo axis's, layout 1.10: into [0, modulo); the window is checked on it).
    pub fn tick_wrapped(
        &mut self,
        x0: f64,
        x1: f64,
        tick: u64,
        trigger: Option<Trigger>,
        wrap: impl Fn(f64) -> f64,
    ) -> Option<Capture> {
        let arm = *self.armed()?;
        let (position, frac) = match trigger? {
            Trigger::Edge { frac, rising } => {
                if !(rising && arm.rising || !rising && arm.falling) {
                    return None;
                }
                (x0 + frac * (x1 - x0), frac)
            }
            Trigger::Index { position } => {
                let frac = if x1 != x0 {
                    ((position - x0) / (x1 - x0)).clamp(0.0, 1.0)
                } else {
                    1.0
                };
                (position, frac)
            }
        };
        let position = wrap(position);
        if let Some((lo, hi)) = arm.window {
            if !(lo..=hi).contains(&position) {
                self.outside = self.outside.wrapping_add(1);
                return None;
            }
        }
        self.queue[self.captures as usize % PROBE_QUEUE] = position;
        self.captures = self.captures.wrapping_add(1);
        self.last_tick = tick as f64 - 1.0 + frac;
        self.done = !arm.continuous;
        Some(Capture {
            number: self.captures,
            position,
            seq: arm.seq,
        })
    }

    /// The status block.
    #[inline]
    pub fn status(&self) -> raw::mc_probe_status {
        let state = match self.arm {
            None => raw::MC_IO_IDLE,
            Some(_) if self.done => raw::MC_IO_DONE,
            Some(_) => raw::MC_IO_ARMED,
        };
        raw::mc_probe_status {
            state,
            axis: self.arm.map_or(0, |a| a.axis as u32),
            captures: self.captures,
            outside: self.outside,
            position: self.queue,
            last_tick: self.last_tick,
            _reserved: 0.0,
        }
    }
}

const _: () = assert!(INDEX as usize == INPUTS);

#[cfg(test)]
mod tests {
    use super::*;

    /// `MC_OP_PROBE_ARM` with these flags and arguments (after the channel, 0), decoded as the
    /// card decodes it, then validated.
    fn validate_arm(axis: usize, flags: u32, args: &[f64], seq: u32) -> Result<ProbeArm, NackCode> {
        use firmware_proto::cmd::Args;
        let mut a = [0.0; firmware_proto::CMD_ARGS];
        a[1..1 + args.len()].copy_from_slice(args);
        let arm = cmd::ProbeArm::decode(flags, &a).map_err(|e| e.nack)?;
        super::validate_arm(axis, &arm, seq)
    }

    fn arm(flags: u32, window: [f64; 2]) -> ProbeArm {
        validate_arm(1, flags, &[4.0, window[0], window[1]], 9).unwrap()
    }

    #[test]
    fn an_edge_is_captured_at_its_interpolated_position_once() {
        let mut p = Probe::default();
        p.start(arm(raw::MC_PROBE_RISING, [0.0, 0.0]));
        let fall = Trigger::Edge {
            frac: 0.5,
            rising: false,
        };
        assert_eq!(p.tick(0.5, 200.5, 1, Some(fall)), None, "the other edge");
        let rise = Trigger::Edge {
            frac: 0.25,
            rising: true,
        };
        let c = p.tick(200.5, 400.5, 2, Some(rise)).unwrap();
        assert_eq!((c.number, c.position, c.seq), (1, 250.5, 9));
        assert_eq!(p.status().last_tick, 1.25);
        assert_eq!(p.status().state, raw::MC_IO_DONE);
        assert_eq!(p.tick(400.5, 600.5, 3, Some(rise)), None, "single shot");
    }

    #[test]
    fn continuous_capture_fills_the_ring_and_the_window_filters() {
        let flags = raw::MC_PROBE_RISING
            | raw::MC_PROBE_FALLING
            | raw::MC_PROBE_CONTINUOUS
            | raw::MC_PROBE_WINDOW;
        let mut p = Probe::default();
        p.start(arm(flags, [100.0, 1000.0]));
        let mut taken = Vec::new();
        for k in 0..20u64 {
            let x0 = 0.5 + 100.0 * k as f64;
            let t = Trigger::Edge {
                frac: 0.5,
                rising: k % 2 == 0,
            };
            if let Some(c) = p.tick(x0, x0 + 100.0, k + 1, Some(t)) {
                taken.push(c.position);
            }
        }
        assert_eq!(taken.len(), 9, "{taken:?}"); // 150.5 .. 950.5
        let s = p.status();
        assert_eq!((s.captures, s.outside, s.state), (9, 11, raw::MC_IO_ARMED));
        assert_eq!(s.position[8 % PROBE_QUEUE], 950.5);
        p.abort();
        assert_eq!(p.status().state, raw::MC_IO_IDLE);
    }

    #[test]
    fn the_arm_is_validated() {
        let v = |flags, args: [f64; 3]| validate_arm(0, flags, &args, 1).map(|_| ());
        let r = raw::MC_PROBE_RISING;
        assert_eq!(v(r, [16.0, 0.0, 0.0]), Ok(()));
        assert_eq!(v(r, [17.0, 0.0, 0.0]), Err(NackCode::ProbeInput));
        assert_eq!(v(r, [-1.0, 0.0, 0.0]), Err(NackCode::ProbeInput));
        assert_eq!(v(r, [0.5, 0.0, 0.0]), Err(NackCode::ProbeInput));
        assert_eq!(v(r, [f64::NAN, 0.0, 0.0]), Err(NackCode::NotFinite));
        assert_eq!(v(0, [1.0, 0.0, 0.0]), Err(NackCode::ProbeInput));
        assert_eq!(v(r | 1 << 7, [1.0, 0.0, 0.0]), Err(NackCode::ProbeInput));
        let w = r | raw::MC_PROBE_WINDOW;
        assert_eq!(v(w, [1.0, 5.0, 4.0]), Err(NackCode::ProbeInput));
        assert_eq!(v(w, [1.0, f64::INFINITY, 4.0]), Err(NackCode::NotFinite));
        assert_eq!(v(w, [1.0, -1e300, 4.0]), Err(NackCode::OutOfRange));
        assert_eq!(
            v(r, [1.0, f64::NAN, 4.0]),
            Ok(()),
            "no window: its words are not read"
        );
    }
}
