//! Fixtures for the tests of the tick's steps: a group over powered axes of a card without a
//! plant (the encoders follow the references exactly when asked), and moves queued the way the
//! command manager queues them.

use super::*;
use crate::math;
use firmware_proto::cmd::{Args, CircularMove, LinearMove, NurbsBegin, NurbsData};
use firmware_proto::{move_flags, Command};

/// The fixtures' servo period, s (10 kHz).
pub(super) const TS: f64 = 1e-4;

/// Group 0 with its axes, filters and outbox.
pub(super) struct Bench {
    pub(super) g: Group,
    pub(super) axes: [Axis; MAX_AXES],
    pub(super) filters: FilterBank,
    pub(super) out: Outbox,
    pub(super) tick: u64,
}

impl Bench {
    /// Group 0 over axes `0..n`, powered and enabled at 0, with S-curve feeds (`pre`) and/or
    /// post-interpolation filters (`post`), exact arcs, a 1-count tolerance.
    pub(super) fn new(n: usize, pre: bool, post: bool) -> Self {
        Self::with(n, pre, post, false)
    }

    /// As [`new`](Self::new), with Kim's reference-word arcs when `reference_word`.
    pub(super) fn with(n: usize, pre: bool, post: bool, reference_word: bool) -> Self {
        let mut axes = core::array::from_fn(|_| Axis::new());
        for a in axes.iter_mut().take(n) {
            a.power(true).unwrap();
        }
        let mut members = [0; MAX_AXES];
        for (i, m) in members.iter_mut().enumerate().take(n) {
            *m = i;
        }
        let mut g = Group::new(0);
        g.configure(GroupConfig {
            naxes: n,
            axes: members,
            pre,
            post,
            reference_word,
            tolerance: 1.0,
            home: Default::default(),
        })
        .unwrap();
        let mut out = Outbox::default();
        g.enable(&mut axes, 0, &mut out).unwrap();
        out.clear();
        Self {
            g,
            axes,
            filters: filter_bank(),
            out,
            tick: 0,
        }
    }

    pub(super) fn cfg(&self) -> GroupConfig {
        self.g.config.unwrap()
    }

    /// Queue a line to `target` (absolute), buffered, with `flags` (feed type), at
    /// v 1e5, a and d 1e6, j 1e8.
    pub(super) fn line(&mut self, seq: u32, target: &[f64], flags: u32) {
        let mut args = vec![1e5, 1e6, 1e6, 1e8];
        args.extend_from_slice(target);
        let mut c = Command::new(Opcode::GroupMoveLinear, 0).with_args(&args);
        c.seq = seq;
        c.flags = flags | move_flags::BUFFERED;
        let m = LinearMove::decode(c.flags, &c.args).unwrap();
        self.g
            .queue_move(seq, GroupMove::Linear(&m), TS, self.tick, &mut self.out)
            .unwrap();
    }

    /// Queue a counter-clockwise arc in the XY plane to `end` around `centre` (absolute), then
    /// the other axes' ends (`helix`), buffered, at v 1e5, a and d 1e6, j 1e8.
    pub(super) fn arc(&mut self, seq: u32, end: [f64; 2], centre: [f64; 2], helix: &[f64]) {
        let mut args = vec![1e5, 1e6, 1e6, 1e8, end[0], end[1], centre[0], centre[1]];
        args.extend_from_slice(helix);
        let mut c = Command::new(Opcode::GroupMoveCircular, 0).with_args(&args);
        c.seq = seq;
        c.flags = move_flags::BUFFERED
            | move_flags::CIRC_CCW
            | (raw::MC_CIRC_BY_CENTRE << move_flags::CIRC_MODE_SHIFT)
            | (raw::MC_PLANE_XY << move_flags::PLANE_SHIFT);
        let m = CircularMove::decode(c.flags, &c.args).unwrap();
        self.g
            .queue_move(seq, GroupMove::Circular(&m), TS, self.tick, &mut self.out)
            .unwrap();
    }

    /// Send `curve` as a NURBS transfer (buffered) at feed `feed`, accel 1e6, jerk 1e8, chord
    /// tolerance 1 count.
    pub(super) fn nurbs(&mut self, seq: u32, curve: &crate::motion::nurbs::Nurbs, feed: f64) {
        let n_ctrl = curve.n_ctrl();
        let mut stream = Vec::new();
        for i in 0..n_ctrl {
            let p = curve.control_point(i).unwrap();
            stream.extend_from_slice(&p.as_slice()[..curve.dim()]);
        }
        stream.extend((0..n_ctrl).map(|i| curve.weight(i).unwrap()));
        stream.extend_from_slice(curve.knots());
        let header = [
            curve.degree() as f64,
            n_ctrl as f64,
            curve.knots().len() as f64,
            feed,
            1e6,
            1e8,
            1.0,
            1.0,
        ];
        let mut c = Command::new(Opcode::NurbsBegin, 0).with_args(&header);
        c.flags = move_flags::BUFFERED;
        let b = NurbsBegin::decode(c.flags, &c.args).unwrap();
        self.g.nurbs_begin(&b, &self.axes, TS).unwrap();
        for (k, chunk) in stream.chunks(firmware_proto::NURBS_DATA_MAX).enumerate() {
            let mut args = vec![
                (k * firmware_proto::NURBS_DATA_MAX) as f64,
                chunk.len() as f64,
            ];
            args.extend_from_slice(chunk);
            let c = Command::new(Opcode::NurbsData, 0).with_args(&args);
            self.g
                .nurbs_data(&NurbsData::decode(c.flags, &c.args).unwrap())
                .unwrap();
        }
        self.g
            .nurbs_end(seq, &self.axes, TS, self.tick, &mut self.out)
            .unwrap();
    }

    /// The events pushed since the last call.
    pub(super) fn events(&mut self) -> Vec<Event> {
        let v = (0..self.out.len())
            .filter_map(|i| self.out.get(i))
            .collect();
        self.out.clear();
        v
    }

    /// Has an event of `kind` for `seq` been pushed (since the last `events`)?
    pub(super) fn pushed(&self, kind: EventKind, seq: u32) -> bool {
        self.out
            .iter()
            .any(|e| e.kind == kind as u16 && e.seq == seq)
    }

    /// The encoders read the references exactly (a perfect plant).
    pub(super) fn follow(&mut self) {
        for a in self.axes.iter_mut() {
            a.sense(math::round(a.reference().pos) as i64, TS);
        }
    }

    /// A whole group tick after the encoders followed.
    pub(super) fn tick(&mut self) {
        self.follow();
        self.tick += 1;
        self.g.tick(
            &mut self.axes,
            &mut self.filters,
            TS,
            self.tick,
            &mut self.out,
        );
    }

    /// Tick until `done` (at most `max` ticks): whether it came.
    pub(super) fn run_until(&mut self, max: usize, done: impl Fn(&Self) -> bool) -> bool {
        for _ in 0..max {
            if done(self) {
                return true;
            }
            self.tick();
        }
        done(self)
    }

    pub(super) fn pos(&self, a: usize) -> f64 {
        self.axes[a].reference().pos
    }
}
