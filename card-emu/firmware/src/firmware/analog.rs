//! Analog I/O and the path-speed output (layout 1.11): the card's 8 analog inputs (a 16-bit
//! ±10 V ADC sampled every tick, a first-order filter and a threshold with hysteresis each),
//! its 4 spare DAC outputs (the axes' 12-bit DAC), and the PSO: an output proportional to a
//! group's actual tangential speed, gated by a digital output the path sets (M62–M65).
//!
//! [`AnalogUnit::tick`] runs once per servo tick after the groups' path step (the gate's bit
//! of this tick is in the outputs word) and after the axes sensed their encoders (the PSO
//! takes this tick's velocity estimates). It allocates nothing; its events (at most one per
//! input) go to a queue posted with the I/O unit's.

use super::axis::Axis;
use super::dac::Dac;
use super::outbox::EventQueue;
use super::quiet::REWRITE_TICKS;
use crate::math;
use firmware_proto::cmd::{AnalogInput, AnalogOutput, Pso, PsoOutput};
use firmware_proto::{
    layout, raw, Event, EventKind, Mem, NackCode, ANALOG_INPUTS, ANALOG_OUTPUTS, MAX_AXES,
};

/// The ADC's step, V (20 V over 16 bits).
pub const ADC_LSB: f64 = raw::MC_ADC_LSB;

/// The 16-bit bipolar ADC: the sample of a pin at `volts`, `code · ADC_LSB` with the code
/// `round(volts / ADC_LSB)` saturated to `-32768..=32767` (a NaN pin reads 0).
pub fn adc_sample(volts: f64) -> f64 {
    if volts.is_nan() {
        return 0.0;
    }
    math::round(volts / ADC_LSB).clamp(-32768.0, 32767.0) * ADC_LSB
}

/// One analog input's configuration and state.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Input {
    cfg: Option<AnalogInput>,
    /// The filter's gain per tick (1: no filter).
    alpha: f64,
    /// The ADC's sample of the tick, V.
    sample: f64,
    /// The filtered value, V.
    value: f64,
    above: bool,
}

impl Input {
    fn threshold(&self) -> (f64, f64) {
        self.cfg.map_or((0.0, 0.0), |c| (c.threshold, c.hysteresis))
    }

    /// Above from `y`, given the state before: at or over the threshold, and not yet back
    /// down to `threshold - hysteresis`.
    fn above_at(&self, y: f64) -> bool {
        let (t, h) = self.threshold();
        if self.above {
            y > t - h
        } else {
            y >= t
        }
    }
}

/// The PSO as configured, on group `group`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PsoRun {
    /// The group whose speed it follows.
    pub group: usize,
    /// Its configuration.
    pub cfg: Pso,
    /// The speed filter's gain per tick (1: none).
    beta: f64,
    /// Each card axis's filtered velocity, counts/s (the group's axes).
    w: [f64; MAX_AXES],
    /// The filter has its first value.
    primed: bool,
}

/// The PSO's output of a tick.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PsoTick {
    /// `MC_PSO_*`.
    pub state: u32,
    /// The group's actual tangential speed, counts/s.
    pub speed: f64,
    /// The output: V (quantised by the DAC) or the PWM's duty.
    pub value: f64,
}

/// Events one tick can raise at most.
const ANALOG_EVENTS: usize = ANALOG_INPUTS;

/// The analog inputs and outputs and the PSO.
#[derive(Debug)]
pub struct AnalogUnit {
    pins: [f64; ANALOG_INPUTS],
    inputs: [Input; ANALOG_INPUTS],
    /// What each spare DAC puts out, V.
    outputs: [f64; ANALOG_OUTPUTS],
    pso: Option<PsoRun>,
    pso_tick: PsoTick,
    events: EventQueue<ANALOG_EVENTS>,
    /// The status block as last written (`publish` writes only a block that differs).
    published: Option<raw::mc_analog_status>,
}

impl Default for AnalogUnit {
    fn default() -> Self {
        Self::new()
    }
}

/// The output of a PSO at speed `v`, gate open: `clamp(min + (max − min)·v/v_ref, min, max)`,
/// then as its output makes it (a DAC quantises).
pub fn pso_value(p: &Pso, v: f64) -> f64 {
    let x = (p.min + (p.max - p.min) * (v / p.v_ref)).clamp(p.min, p.max);
    match p.output {
        PsoOutput::Dac(_) => Dac::output(x).0,
        PsoOutput::Pwm { .. } => x,
    }
}

/// A first-order low-pass's gain per tick for the cut-off `hz` at the servo rate `rate_hz`
/// (0: no filter, gain 1).
fn smoothing(hz: f64, rate_hz: u32) -> f64 {
    if hz == 0.0 {
        1.0
    } else {
        1.0 - math::exp(-2.0 * core::f64::consts::PI * hz / f64::from(rate_hz))
    }
}

/// The check of an analog input's settings (decoded) at servo rate `rate_hz` beyond its
/// decoding: a cut-off above half the rate is `MC_NACK_ANALOG_FILTER`.
pub fn input_nack(a: &AnalogInput, rate_hz: u32) -> Result<(), NackCode> {
    if a.cutoff_hz > f64::from(rate_hz) / 2.0 {
        return Err(NackCode::AnalogFilter);
    }
    Ok(())
}

/// The check of a PSO's settings (decoded) at servo rate `rate_hz` beyond its decoding: a speed
/// filter above half the rate is `MC_NACK_PSO_CONFIG`.
pub fn pso_nack(p: &Pso, rate_hz: u32) -> Result<(), NackCode> {
    if p.filter_hz > f64::from(rate_hz) / 2.0 {
        return Err(NackCode::PsoConfig);
    }
    Ok(())
}

impl AnalogUnit {
    /// Boot state: no filter, thresholds at 0 V without events, outputs at 0 V, no PSO.
    pub fn new() -> Self {
        Self {
            pins: [0.0; ANALOG_INPUTS],
            inputs: [Input {
                alpha: 1.0,
                ..Input::default()
            }; ANALOG_INPUTS],
            outputs: [0.0; ANALOG_OUTPUTS],
            pso: None,
            pso_tick: PsoTick::default(),
            events: EventQueue::new(),
            published: None,
        }
    }

    /// The analog input pins for the next tick, V.
    pub fn set_pins(&mut self, volts: [f64; ANALOG_INPUTS]) {
        self.pins = volts;
    }

    /// `MC_OP_ANALOG_INPUT` at servo rate `rate_hz`: a cut-off above half the rate is refused
    /// (`MC_NACK_ANALOG_FILTER`); the filter keeps its value, the state is taken again from it
    /// (no event).
    pub fn configure_input(&mut self, a: &AnalogInput, rate_hz: u32) -> Result<(), NackCode> {
        input_nack(a, rate_hz)?;
        let i = &mut self.inputs[a.input as usize];
        i.alpha = smoothing(a.cutoff_hz, rate_hz);
        i.cfg = Some(*a);
        i.above = false;
        i.above = i.above_at(i.value);
        Ok(())
    }

    /// `MC_OP_ANALOG_OUTPUT`: refused on the DAC the PSO drives (`MC_NACK_ANALOG_CHANNEL`);
    /// the volts are clamped to the DAC's range and quantised.
    pub fn set_output(&mut self, o: &AnalogOutput) -> Result<f64, NackCode> {
        if self.pso_dac() == Some(o.output as usize) {
            return Err(NackCode::AnalogChannel);
        }
        let v = Dac::output(o.volts).0;
        self.outputs[o.output as usize] = v;
        Ok(v)
    }

    /// The spare DAC the PSO drives.
    fn pso_dac(&self) -> Option<usize> {
        match self.pso?.cfg.output {
            PsoOutput::Dac(d) => Some(d as usize),
            PsoOutput::Pwm { .. } => None,
        }
    }

    /// `MC_OP_PSO` on group `group` (checked by the caller) at servo rate `rate_hz`: a filter
    /// above half the rate is refused (`MC_NACK_PSO_CONFIG`); else it replaces the PSO
    /// running, whose output goes to 0 first.
    pub fn start_pso(&mut self, group: usize, cfg: Pso, rate_hz: u32) -> Result<(), NackCode> {
        pso_nack(&cfg, rate_hz)?;
        let beta = smoothing(cfg.filter_hz, rate_hz);
        self.stop_pso();
        self.pso = Some(PsoRun {
            group,
            cfg,
            beta,
            w: [0.0; MAX_AXES],
            primed: false,
        });
        self.pso_tick = PsoTick {
            state: raw::MC_PSO_CLOSED,
            ..PsoTick::default()
        };
        Ok(())
    }

    /// Can the input filters and the PSO's speed filter as configured run at the servo rate
    /// `rate_hz`? (A cut-off above half of it: `MC_NACK_ANALOG_FILTER`, `MC_NACK_PSO_CONFIG`.)
    pub fn check_rate(&self, rate_hz: u32) -> Result<(), NackCode> {
        for a in self.inputs.iter().filter_map(|i| i.cfg.as_ref()) {
            input_nack(a, rate_hz)?;
        }
        match &self.pso {
            Some(p) => pso_nack(&p.cfg, rate_hz),
            None => Ok(()),
        }
    }

    /// The servo rate is now `rate_hz` (checked with [`AnalogUnit::check_rate`]): each filter's
    /// gain per tick designed again for the same cut-off, its value kept.
    pub fn set_rate(&mut self, rate_hz: u32) {
        for i in &mut self.inputs {
            if let Some(a) = &i.cfg {
                i.alpha = smoothing(a.cutoff_hz, rate_hz);
            }
        }
        if let Some(p) = &mut self.pso {
            p.beta = smoothing(p.cfg.filter_hz, rate_hz);
        }
    }

    /// `MC_OP_PSO_OFF`: the PSO's output goes to 0.
    pub fn stop_pso(&mut self) {
        if let Some(d) = self.pso_dac() {
            self.outputs[d] = 0.0;
        }
        self.pso = None;
        self.pso_tick = PsoTick::default();
    }

    /// The PSO, if configured.
    pub fn pso(&self) -> Option<&PsoRun> {
        self.pso.as_ref()
    }

    /// The PSO's output of the last tick.
    pub fn pso_tick(&self) -> PsoTick {
        self.pso_tick
    }

    /// The PWM the PSO runs: (digital output, duty, Hz).
    pub fn pwm(&self) -> Option<(usize, f64, f64)> {
        match self.pso?.cfg.output {
            PsoOutput::Pwm { output, hz } => Some((output as usize, self.pso_tick.value, hz)),
            PsoOutput::Dac(_) => None,
        }
    }

    /// The digital outputs the PWM holds on (its bit while the duty is above 0).
    pub fn pwm_outputs(&self) -> u32 {
        match self.pwm() {
            Some((o, duty, _)) if duty > 0.0 => 1 << o,
            _ => 0,
        }
    }

    /// One tick (ending at `tick`): sample and filter the inputs, post threshold crossings;
    /// the PSO from the axes' velocity estimates (`axes`) of its group's `members` and the
    /// digital outputs word `outputs` (its gate).
    pub fn tick(&mut self, tick: u64, axes: &[Axis], members: &[usize], outputs: u32) {
        self.events.clear();
        for (k, (i, &pin)) in self.inputs.iter_mut().zip(&self.pins).enumerate() {
            i.sample = adc_sample(pin);
            i.value += i.alpha * (i.sample - i.value);
            let above = i.above_at(i.value);
            if above != i.above {
                i.above = above;
                let (rise, fall) = i
                    .cfg
                    .map_or((false, false), |c| (c.rise_event, c.fall_event));
                if (above && rise) || (!above && fall) {
                    self.events.push(Event {
                        seq: 0,
                        kind: EventKind::Analog as u16,
                        axis: k as u16,
                        code: i32::from(above),
                        tick,
                        value: i.value,
                    });
                }
            }
        }
        let Some(run) = self.pso.as_mut() else {
            return;
        };
        // Each group axis's velocity estimate through the PSO's filter (started from the first
        // estimate: no ramp up from 0 at the start), then the vector's length.
        let mut v2 = 0.0;
        for &a in members.iter().take(MAX_AXES) {
            if let Some(ax) = axes.get(a) {
                let v = ax.velocity_estimate();
                let w = &mut run.w[a];
                *w = if run.primed {
                    *w + run.beta * (v - *w)
                } else {
                    v
                };
                v2 += *w * *w;
            }
        }
        run.primed = true;
        let run = *run;
        let speed = math::sqrt(v2);
        let open = outputs & (1 << run.cfg.gate) != 0;
        let value = if open {
            pso_value(&run.cfg, speed)
        } else {
            0.0
        };
        self.pso_tick = PsoTick {
            state: if open {
                raw::MC_PSO_ON
            } else {
                raw::MC_PSO_CLOSED
            },
            speed,
            value,
        };
        if let PsoOutput::Dac(d) = run.cfg.output {
            self.outputs[d as usize] = value;
        }
    }

    /// Event `i` of the last tick.
    pub fn event(&self, i: usize) -> Option<Event> {
        self.events.get(i)
    }

    /// Events of the last tick.
    pub fn events_len(&self) -> usize {
        self.events.len()
    }

    /// Input `i`'s filtered value, V.
    pub fn input(&self, i: usize) -> f64 {
        self.inputs.get(i).map_or(0.0, |x| x.value)
    }

    /// Spare DAC `i`'s output, V.
    pub fn output(&self, i: usize) -> f64 {
        self.outputs.get(i).copied().unwrap_or(0.0)
    }

    /// The spare DACs' outputs, V.
    pub fn outputs(&self) -> [f64; ANALOG_OUTPUTS] {
        self.outputs
    }

    /// Write the status block of tick `tick` when it differs from the one last written (most
    /// ticks of a card whose inputs stand still: not), and whole every [`REWRITE_TICKS`]
    /// ticks: the card is its only writer, and the rewrite bounds how long a stray write into
    /// it could stay (as the I/O unit's blocks, a quarter period from the groups' turns).
    pub fn publish<M: Mem>(&mut self, mem: &M, tick: u64) {
        let mut b = raw::mc_analog_status::default();
        for (k, i) in self.inputs.iter().enumerate() {
            b.input_raw[k] = i.sample;
            b.input[k] = i.value;
            b.above |= u32::from(i.above) << k;
            if let Some(c) = i.cfg {
                b.rise_events |= u32::from(c.rise_event) << k;
                b.fall_events |= u32::from(c.fall_event) << k;
                b.cutoff_hz[k] = c.cutoff_hz;
                b.threshold[k] = c.threshold;
                b.hysteresis[k] = c.hysteresis;
            }
        }
        b.output = self.outputs;
        b.pso_state = self.pso_tick.state;
        b.pso_speed = self.pso_tick.speed;
        b.pso_value = self.pso_tick.value;
        if let Some(p) = self.pso {
            b.pso_group = p.group as u32;
            b.pso_gate = u32::from(p.cfg.gate);
            b.pso_min = p.cfg.min;
            b.pso_max = p.cfg.max;
            b.pso_v_ref = p.cfg.v_ref;
            b.pso_filter_hz = p.cfg.filter_hz;
            match p.cfg.output {
                PsoOutput::Dac(d) => b.pso_output = u32::from(d),
                PsoOutput::Pwm { output, hz } => {
                    b.pso_output = u32::from(output);
                    b.pso_flags = raw::MC_PSO_PWM;
                    b.pso_pwm_hz = hz;
                }
            }
        }
        let due = tick
            .wrapping_add(REWRITE_TICKS / 4)
            .is_multiple_of(REWRITE_TICKS);
        if self.published == Some(b) && !due {
            return;
        }
        self.published = Some(b);
        layout::ANALOG_STATUS.write(mem, &b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn input(cutoff_hz: f64, threshold: f64, hysteresis: f64) -> AnalogInput {
        AnalogInput {
            input: 0,
            cutoff_hz,
            threshold,
            hysteresis,
            rise_event: true,
            fall_event: true,
        }
    }

    /// The ADC: 16 bits over ±10 V, rounded to the nearest code, saturating.
    #[test]
    fn the_adc_quantises_to_16_bits_and_saturates() {
        assert_eq!(ADC_LSB, 20.0 / 65536.0);
        assert_eq!(adc_sample(0.0), 0.0);
        assert_eq!(adc_sample(1.0), 3277.0 * ADC_LSB); // 3276.8 codes
        assert_eq!(adc_sample(-1.0), -3277.0 * ADC_LSB);
        assert_eq!(adc_sample(0.4 * ADC_LSB), 0.0);
        assert_eq!(adc_sample(12.0), 32767.0 * ADC_LSB);
        assert_eq!(adc_sample(-12.0), -10.0);
        assert_eq!(adc_sample(f64::NAN), 0.0);
    }

    /// The filter's step response is the continuous first-order one at the sample instants,
    /// and the threshold's crossings come on the ticks the analytic response says, with the
    /// hysteresis.
    #[test]
    fn filter_step_response_and_threshold_ticks() {
        let mut u = AnalogUnit::new();
        let rate = 10_000;
        u.configure_input(&input(50.0, 3.0, 1.0), rate).unwrap();
        let v = 5.0;
        let s = adc_sample(v);
        u.set_pins([v, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        let w = 2.0 * core::f64::consts::PI * 50.0 / f64::from(rate);
        // Above at the first n with s (1 - e^{-wn}) >= 3.
        let first = (1..)
            .find(|&n| s * (1.0 - (-w * n as f64).exp()) >= 3.0)
            .unwrap();
        let mut rose = None;
        for n in 1..=200u64 {
            u.tick(n, &[], &[], 0);
            let exact = s * (1.0 - (-w * n as f64).exp());
            assert!((u.input(0) - exact).abs() < 1e-12, "tick {n}");
            if u.events_len() > 0 {
                assert!(rose.is_none());
                let e = u.event(0).unwrap();
                assert_eq!((e.kind, e.axis, e.code), (EventKind::Analog as u16, 0, 1));
                rose = Some(n);
            }
        }
        assert_eq!(rose, Some(first));
        // Back down: the fall comes at y <= 2 V (threshold - hysteresis), not at 3 V.
        u.set_pins([0.0; ANALOG_INPUTS]);
        let y0 = u.input(0);
        let fall = (1..).find(|&n| y0 * (-w * n as f64).exp() <= 2.0).unwrap();
        let mut fell = None;
        for n in 1..=200u64 {
            u.tick(200 + n, &[], &[], 0);
            if u.events_len() > 0 {
                assert_eq!(u.event(0).unwrap().code, 0);
                fell = Some(n);
                break;
            }
        }
        assert_eq!(fell, Some(fall));
    }

    #[test]
    fn a_cut_off_above_nyquist_is_refused_and_changes_nothing() {
        let mut u = AnalogUnit::new();
        assert_eq!(
            u.configure_input(&input(5000.5, 0.0, 0.0), 10_000),
            Err(NackCode::AnalogFilter)
        );
        assert_eq!(u.inputs[0].cfg, None);
        assert!(u.configure_input(&input(5000.0, 0.0, 0.0), 10_000).is_ok());
    }

    /// A new servo rate: each filter keeps its cut-off in Hz (its gain per tick designed again:
    /// the step response at the new rate is the continuous one at the new sample instants),
    /// and a rate under twice a cut-off is refused by the check.
    #[test]
    fn a_new_servo_rate_keeps_each_filters_cut_off() {
        let mut u = AnalogUnit::new();
        u.configure_input(&input(50.0, 0.0, 0.0), 10_000).unwrap();
        assert_eq!(u.check_rate(2_000), Ok(()));
        u.set_rate(2_000);
        let w = 2.0 * core::f64::consts::PI * 50.0 / 2_000.0;
        u.set_pins([5.0; ANALOG_INPUTS]);
        for n in 1..=50u64 {
            u.tick(n, &[], &[], 0);
            let exact = adc_sample(5.0) * (1.0 - (-w * n as f64).exp());
            assert!((u.input(0) - exact).abs() < 1e-12, "tick {n}");
        }
        u.configure_input(&input(900.0, 0.0, 0.0), 2_000).unwrap();
        assert_eq!(u.check_rate(1_000), Err(NackCode::AnalogFilter));
        let pso = Pso {
            output: PsoOutput::Dac(0),
            gate: 0,
            min: 0.0,
            max: 1.0,
            v_ref: 1000.0,
            filter_hz: 600.0,
        };
        let mut p = AnalogUnit::new();
        p.start_pso(0, pso, 10_000).unwrap();
        assert_eq!(p.check_rate(1_000), Err(NackCode::PsoConfig));
        p.set_rate(2_000);
        let beta = p.pso.unwrap().beta;
        assert!(
            (beta - (1.0 - (-2.0 * core::f64::consts::PI * 600.0 / 2_000.0).exp())).abs() < 1e-15
        );
    }

    /// The block is written when it changes, left alone while it stands still, and rewritten
    /// whole every 64 ticks (a stray write into it is gone within that).
    #[test]
    fn the_status_block_is_written_on_change_and_rewritten_periodically() {
        use firmware_proto::mem::HeapWindow;
        let w = HeapWindow::new();
        let mut u = AnalogUnit::new();
        u.set_pins([1.0; ANALOG_INPUTS]);
        u.tick(1, &[], &[], 0);
        u.publish(&w, 1);
        let b = layout::ANALOG_STATUS.read(&w);
        assert_eq!(b.input[7], adc_sample(1.0));
        // A stray write: the card does not see it until the block changes or is due.
        let mut stray = b;
        stray.input[7] = 9.0;
        layout::ANALOG_STATUS.write(&w, &stray);
        let mut repaired = None;
        for t in 2..=70 {
            u.tick(t, &[], &[], 0);
            u.publish(&w, t);
            if repaired.is_none() && layout::ANALOG_STATUS.read(&w) == b {
                repaired = Some(t);
            }
        }
        let due = (2..=70).find(|t| (t + REWRITE_TICKS / 4).is_multiple_of(REWRITE_TICKS));
        assert_eq!(repaired, due);
        // A change is written in its tick.
        u.set_pins([2.0; ANALOG_INPUTS]);
        u.tick(71, &[], &[], 0);
        u.publish(&w, 71);
        assert_eq!(layout::ANALOG_STATUS.read(&w).input[0], adc_sample(2.0));
    }

    #[test]
    fn pso_value_is_clamped_between_min_and_max() {
        let p = Pso {
            output: PsoOutput::Pwm { output: 3, hz: 1e3 },
            gate: 2,
            min: 0.2,
            max: 0.9,
            v_ref: 1000.0,
            filter_hz: 0.0,
        };
        assert_eq!(pso_value(&p, 0.0), 0.2);
        assert_eq!(pso_value(&p, 500.0), 0.2 + 0.7 * 0.5);
        assert_eq!(pso_value(&p, 2000.0), 0.9);
        let d = Pso {
            output: PsoOutput::Dac(0),
            ..p
        };
        assert_eq!(pso_value(&d, 500.0), Dac::output(0.55).0);
    }
}
