//! Cost of the acc/dec filters and interpolators per axis per servo tick (no servo, no plant).
//!
//! `cargo bench -p card-emu --bench interp`
use card_emu::axis::Axis;
use card_emu::filters::{AccDecFilter, FilterKind};
use card_emu::group::{filter_bank, FilterConfig, Group, GroupConfig, Outbox};
use criterion::{black_box, criterion_group, criterion_main, Criterion};
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
    Box<[card_emu::group::AxisFilter]>,
    Outbox,
) {
    let mut axes = [Axis::new(); MAX_AXES];
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
    })
    .unwrap();
    let mut out = Outbox::default();
    g.enable(&mut axes, 0, &mut out).unwrap();
    (g, axes, bank, out)
}

fn queue(g: &mut Group, op: Opcode, args: &[f64], flags: u32, out: &mut Outbox) {
    let mut c = Command::new(op, 0).with_args(args);
    c.flags = flags | move_flags::BUFFERED;
    let _ = g.queue_move(&c, op, 1e-4, 0, out);
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

criterion_group!(benches, filters, interpolators);
criterion_main!(benches);
