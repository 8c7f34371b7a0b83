//! Cost of the acc/dec filters and interpolators per axis per servo tick (no servo, no plant).
//!
//! `cargo bench -p card-emu --bench interp`
use card_emu::firmware::axis::Axis;
use card_emu::firmware::group::{filter_bank, FilterConfig, Group, GroupConfig, GroupMove, Outbox};
use card_emu::motion::filters::{AccDecFilter, FilterKind};
use criterion::{black_box, criterion_group, criterion_main, Criterion};
use firmware_proto::cmd::GroupCmd;
use firmware_proto::{move_flags, raw, Command, Opcode, MAX_AXES};

fn filters(c: &mut Criterion) {
    for kind in [
        FilterKind::Linear,
        FilterKind::Exponential,
        FilterKind::Bell,
    ] {
        let mut f = AccDecFilter::from_time_constant(kind, 0.03, 1e-4).unwrap();
        let mut x = 0.0f64;
        c.bench_function(&format!("filter step, {kind:?} 30 ms at 10 kHz"), |b| {
            b.iter(|| {
                x += 1.0;
                black_box(f.step(black_box((x * 0.001).sin() * 10.0)))
            })
        });
    }
}

/// A group over `n` axes, enabled, with `kind` filters on every feed type.
fn group(
    n: usize,
    pre: bool,
    post: bool,
    rw: bool,
    kind: FilterKind,
) -> (
    Group,
    [Axis; MAX_AXES],
    card_emu::firmware::group::FilterBank,
    Outbox,
) {
    let mut axes = core::array::from_fn(|_| Axis::new());
    for a in axes.iter_mut() {
        a.power(true).unwrap();
    }
    let mut bank = filter_bank();
    for f in bank.iter_mut() {
        f.config = FilterConfig {
            kind: [kind; 3],
            tau: [0.03; 3],
        };
    }
    let mut ax = [0usize; MAX_AXES];
    for (i, a) in ax.iter_mut().enumerate() {
        *a = i;
    }
    let mut g = Group::new(0);
    g.configure(GroupConfig {
        naxes: n,
        axes: ax,
        pre,
        post,
        reference_word: rw,
        tolerance: 2.0,
        home: Default::default(),
    })
    .unwrap();
    let mut out = Outbox::default();
    g.enable(&mut axes, 0, &mut out).unwrap();
    (g, axes, bank, out)
}

/// Queue a move as the command manager does: the entry decoded, then queued.
fn queue(g: &mut Group, op: Opcode, args: &[f64], flags: u32, out: &mut Outbox) {
    let mut c = Command::new(op, 0).with_args(args);
    c.flags = flags | move_flags::BUFFERED;
    let decoded = GroupCmd::decode(op, c.flags, &c.args);
    let mv = match &decoded {
        Ok(GroupCmd::MoveLinear(m)) => GroupMove::Linear(m),
        Ok(GroupCmd::MoveCircular(m)) => GroupMove::Circular(m),
        Ok(GroupCmd::MovePtp(m)) => GroupMove::Ptp(m),
        other => panic!("not a move: {other:?}"),
    };
    let _ = g.queue_move(0, mv, 1e-4, 0, out);
}

fn interpolators(c: &mut Criterion) {
    let ts = 1e-4;
    let cases: [(&str, usize, bool, bool, bool, FilterKind); 4] = [
        (
            "8-axis linear, S-curve feed + linear filters",
            8,
            true,
            true,
            false,
            FilterKind::Linear,
        ),
        (
            "3-axis helix (exact arc), S-curve feed + bell filters",
            3,
            true,
            true,
            false,
            FilterKind::Bell,
        ),
        (
            "2-axis circle, reference-word, exponential filters",
            2,
            false,
            true,
            true,
            FilterKind::Exponential,
        ),
        (
            "2-axis circle, exact, S-curve feed, no filters",
            2,
            true,
            false,
            false,
            FilterKind::None,
        ),
    ];
    for (name, n, pre, post, rw, kind) in cases {
        let (mut g, mut axes, mut bank, mut out) = group(n, pre, post, rw, kind);
        let circ = raw::MC_CIRC_BY_CENTRE << move_flags::CIRC_MODE_SHIFT | move_flags::CIRC_CCW;
        let refill = |g: &mut Group, out: &mut Outbox| {
            if n == 8 {
                queue(
                    g,
                    Opcode::GroupMoveLinear,
                    &[2e4, 1e6, 1e6, 1e8, 1e9, -1e9, 5e8, 1e8, 2e8, -3e8, 4e8, 7e8],
                    move_flags::RELATIVE,
                    out,
                );
            } else if n == 3 {
                queue(
                    g,
                    Opcode::GroupMoveCircular,
                    &[2e4, 1e6, 1e6, 1e8, 0.0, 0.0, 1e5, 0.0, 1e4],
                    circ | move_flags::RELATIVE,
                    out,
                );
            } else {
                queue(
                    g,
                    Opcode::GroupMoveCircular,
                    &[2e4, 1e6, 1e6, 1e8, 0.0, 0.0, 1e5, 0.0],
                    circ | move_flags::RELATIVE,
                    out,
                );
            }
        };
        refill(&mut g, &mut out);
        let mut tick = 0u64;
        c.bench_function(&format!("group tick / {n} axes: {name}"), |b| {
            b.iter(|| {
                tick += 1;
                g.tick(&mut axes, &mut bank, ts, tick, &mut out);
                out.clear();
                if g.status(tick).queued == 0 {
                    refill(&mut g, &mut out);
                }
            })
        });
    }
}

/// One NURBS interpolation step (Yeh eq 3.1 + Newton corrections, knot-span search, point and
/// derivatives), plain and saturation-aware, on a long cubic with 1000 control points.
fn nurbs_step(c: &mut Criterion) {
    use card_emu::motion::nurbs::{clamped_uniform_knots, Nurbs, Point};
    use card_emu::motion::nurbs_interp::{InterpConfig, Interpolator};
    use card_emu::motion::saturation::SaturationAwareFeed;
    use card_emu::presets::die_bonder_volts;
    let n = 1000;
    let mut ctrl = Vec::with_capacity(2 * n);
    for i in 0..n {
        ctrl.push(i as f64 * 20_000.0);
        ctrl.push(if i % 2 == 0 { 0.0 } else { 15_000.0 });
    }
    let curve = Nurbs::new(
        3,
        2,
        &ctrl,
        &vec![1.0; n],
        &clamped_uniform_knots(n, 3).unwrap(),
    )
    .unwrap();
    let cfg = InterpConfig {
        ts: 1e-3,
        feed: 50_000.0,
        accel: 1e7,
        jerk: 1e10,
        chord_tol: 1.0,
        max_corrections: 3,
    };
    // Time steps in blocks, rebuilding the interpolator (untimed) whenever it reaches the end,
    // so every timed step is a real step along the curve.
    let die = card_emu::presets::die_bonder_path();
    let run = |b: &mut criterion::Bencher, curve: &Nurbs, cfg: InterpConfig, guarded: bool| {
        let preset = die_bonder_volts();
        let sat = SaturationAwareFeed::new(&preset.axes, 1e-3).unwrap();
        let build = || {
            if guarded {
                Interpolator::with_actuator_limits(curve.clone(), cfg, &sat, 0.8).unwrap()
            } else {
                Interpolator::new(curve.clone(), cfg).unwrap()
            }
        };
        let mut it = build();
        // The axes track their command: θ_a = θ_d, w_a = w_d of the previous step.
        let (mut theta, mut w) = (Point::zeros(), Point::zeros());
        b.iter_custom(|iters| {
            let mut total = std::time::Duration::ZERO;
            let mut left = iters;
            while left > 0 {
                let block = left.min(1000);
                let t0 = std::time::Instant::now();
                let mut done = false;
                let mut n = 0;
                // (a block ends with the curve: the steps after it would only hold the end)
                while n < block && !done {
                    let t = if guarded {
                        it.tick_guarded(&sat, &theta, &w).map(|(t, _)| t)
                    } else {
                        it.tick()
                    }
                    .unwrap();
                    theta = t.pos;
                    w = t.vel;
                    done = t.done;
                    n += 1;
                }
                total += t0.elapsed();
                left -= n;
                if done {
                    it.reset();
                    (theta, w) = (Point::zeros(), Point::zeros());
                }
            }
            total
        })
    };
    let die_cfg = InterpConfig {
        ts: 1e-3,
        feed: 400_000.0,
        accel: 4e7,
        jerk: 4e10,
        chord_tol: 1.0,
        max_corrections: 3,
    };
    c.bench_function("NURBS step: speed-controlled, die-bonder path", |b| {
        run(b, &die, die_cfg, false)
    });
    c.bench_function(
        "NURBS step: saturation-aware (Yeh 3.4), die-bonder path",
        |b| run(b, &die, die_cfg, true),
    );
    c.bench_function(
        "NURBS step: speed-controlled, 1000-point zigzag cubic",
        |b| run(b, &curve, cfg, false),
    );
    c.bench_function(
        "NURBS step: saturation-aware (Yeh 3.4), 1000-point zigzag cubic",
        |b| run(b, &curve, cfg, true),
    );
}

criterion_group!(benches, filters, interpolators, nurbs_step);
criterion_main!(benches);
