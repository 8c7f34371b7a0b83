//! G38.2–G38.5 on the card: a straight move toward the programmed end with the card's touch
//! probes armed on the moving axes, each with `halt` ([`ProbeTrigger::halt`]), so that the
//! card itself halts the group along its path in the tick it sees the probe's edge (no host
//! latency in the overshoot). Once the motion has ended, the captures give where the probe
//! tripped (#5061–#5070) and the group's position where it came to rest; the program reads on
//! from there ([`super::Program::probe_result`]).
//!
//! The probe is a digital input of the card ([`super::run::RunSettings::probe_input`]):
//! G38.2/G38.3 move until it becomes active (a rising edge), G38.4/G38.5 until it becomes
//! inactive. A probe already in the state the move looks for is an error, as in LinuxCNC. The
//! move uses touch-probe channels 0, 1 and 2 (X, Y, Z), which are disarmed after it.

use super::{GcodeError, Pos};
use crate::{Error, Group, IoState, PathBuffer, ProbeTrigger, Result, Segment, Transition};

/// A probing move running.
#[derive(Debug, Clone)]
pub(super) struct ProbeRun {
    line: usize,
    end: Pos,
    /// (program axis, card axis, probe channel) of each axis captured.
    captured: Vec<(usize, usize, usize)>,
}

/// What a probing move found.
pub(super) struct ProbeResult {
    pub at: Pos,
    pub stopped: Pos,
    pub tripped: bool,
}

fn gerr(line: usize, m: String) -> Error {
    Error::Gcode(GcodeError::new(line, m))
}

impl ProbeRun {
    /// Arms the probes and queues the move from `start` to `end` (machine coordinates) at
    /// `feed` mm/s. `axis_of` gives each program axis's group axis; `axes` the program's
    /// letters in group order. The group must be at rest with its path empty.
    #[allow(clippy::too_many_arguments)]
    pub fn start(
        group: &Group,
        axis_of: &[Option<usize>; 6],
        target: Vec<f64>,
        (line, start, end): (usize, Pos, Pos),
        feed: f64,
        toward: bool,
        input: Option<u32>,
    ) -> Result<Self> {
        let name = if toward { "G38.2/G38.3" } else { "G38.4/G38.5" };
        let input = input.ok_or_else(|| {
            gerr(
                line,
                format!("{name}: no probe input is set for the run (RunSettings::probe_input)"),
            )
        })?;
        let card = group.card_pub();
        let bit = 1u32
            .checked_shl(input)
            .filter(|&b| b <= 1 << 15)
            .ok_or_else(|| gerr(line, format!("{name}: the card has no input {input}")))?;
        let active = card.inputs_raw()? & bit != 0;
        if active == toward {
            return Err(gerr(
                line,
                format!(
                    "{name}: the probe is already {} at the start of the move",
                    if toward { "tripped" } else { "open" }
                ),
            ));
        }
        let (_, ids) = group.axes_pub()?;
        let mut captured = Vec::new();
        for (i, g) in axis_of.iter().enumerate().take(3) {
            if let Some(g) = *g {
                if end[i] != start[i] {
                    captured.push((i, ids[g], captured.len()));
                }
            }
        }
        let trigger = ProbeTrigger {
            rising: toward,
            falling: !toward,
            halt: true,
            ..ProbeTrigger::rising(input)
        };
        for &(_, axis, channel) in &captured {
            card.axis(axis)?.touch_probe(channel).arm(&trigger)?;
        }
        let id = u32::try_from(line).unwrap_or(u32::MAX);
        let seg = Segment::line(id, &target, feed, 0.0)
            .buffer(PathBuffer::Buffered)
            .transition(Transition::None)
            .last();
        if let Err(e) = group.stream_path(vec![crate::PathItem::from(seg)], |_| {}) {
            let run = Self {
                line,
                end,
                captured,
            };
            run.disarm(group)?;
            return Err(e.error);
        }
        Ok(Self {
            line,
            end,
            captured,
        })
    }

    /// The move's result once its motion has ended with the group at `stopped` (program
    /// axes): where the probe tripped (the captures of the moving axes, the others where they
    /// were) and where the group came to rest. The probes are disarmed.
    pub fn finish(self, group: &Group, stopped: Pos) -> Result<ProbeResult> {
        let card = group.card_pub();
        let mut at = stopped;
        let mut tripped = false;
        for &(i, axis, channel) in &self.captured {
            let st = card.axis(axis)?.touch_probe(channel).status()?;
            if st.state == IoState::Done {
                if let Some(&p) = st.positions.last() {
                    at[i] = p;
                    tripped = true;
                }
            }
        }
        self.disarm(group)?;
        if !tripped {
            // Ran to its end: #5061… report the end, as LinuxCNC does.
            at = stopped;
            for (a, e) in at.iter_mut().zip(self.end).take(3) {
                if (*a - e).abs() > 1e-6 {
                    return Err(gerr(
                        self.line,
                        "the probe move ended away from its end without the probe tripping \
                         (a halt, a stop or a fault)"
                            .into(),
                    ));
                }
            }
        }
        Ok(ProbeResult {
            at,
            stopped,
            tripped,
        })
    }

    fn disarm(&self, group: &Group) -> Result<()> {
        let card = group.card_pub();
        for &(_, axis, channel) in &self.captured {
            card.axis(axis)?.touch_probe(channel).abort()?;
        }
        Ok(())
    }
}
