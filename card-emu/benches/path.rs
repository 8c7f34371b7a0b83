//! Cost of the continuous-path engine (`motion::path`) on a dense free-form curve: 10,000
//! chords of ~0.1 mm (1 count = 1 µm) along y = 3000·sin(x/5000) + 1000·sin(x/2000) (radius
//! of curvature ≥ 2.7 mm, so the chord error of a 0.1 mm chord is < 1 µm), blended within
//! 1 µm, at 10 kHz.
//!
//! `cargo bench -p card-emu --bench path`
//!
//! `push`: one segment (validation, the blend with the previous one, its arc-length table and
//! speed cap), per segment, averaged over the 10,000. `tick`: one servo tick (look-ahead scan,
//! planner, executor), averaged over the whole run of the curve.
use card_emu::motion::path::{
    BlendSpeed, Geom, Path, PathLimits, Segment, Transition, DEFAULT_LOOKAHEAD, MAX_AXES,
};
use criterion::{black_box, criterion_group, criterion_main, Criterion};
use std::time::{Duration, Instant};

const N: usize = 10_000;

fn curve() -> Vec<[f64; MAX_AXES]> {
    let mut v = Vec::with_capacity(N + 1);
    let mut x = 0.0f64;
    for _ in 0..=N {
        let y = 3000.0 * (x / 5000.0).sin() + 1000.0 * (x / 2000.0).sin();
        let dy = 0.6 * (x / 5000.0).cos() + 0.5 * (x / 2000.0).cos();
        let mut p = [0.0; MAX_AXES];
        p[0] = x;
        p[1] = y;
        v.push(p);
        x += 100.0 / (1.0 + dy * dy).sqrt();
    }
    v
}

fn limits() -> PathLimits {
    let mut l = PathLimits {
        naxes: 2,
        ts: 1e-4,
        vmax: [2e5; MAX_AXES],
        amax: [2e7; MAX_AXES],
        jmax: [2e9; MAX_AXES],
        accel: 0.0,
        jerk: 0.0,
    };
    l.vmax[1] = 1e5;
    l.amax[1] = 1e7;
    l.jmax[1] = 1e9;
    l
}

fn load(p: &mut Path, pts: &[[f64; MAX_AXES]]) {
    p.reset(pts[0], limits(), DEFAULT_LOOKAHEAD).unwrap();
    for (i, q) in pts[1..].iter().enumerate() {
        p.push(Segment {
            id: i as u32,
            geom: Geom::Line { end: *q },
            feed: 2e5,
            transition: Transition::MaxDeviation(1.0),
            blend: BlendSpeed::Low,
            last: i + 2 == pts.len(),
        })
        .unwrap();
    }
}

fn bench(c: &mut Criterion) {
    let pts = curve();
    let mut p = Path::with_capacity(N);
    // one plain run first: ticks and path time
    load(&mut p, &pts);
    let t0 = Instant::now();
    let mut ticks = 0u64;
    while p.queued() > 0 || p.is_moving() {
        black_box(p.tick(1.0, &mut |_| {}));
        ticks += 1;
    }
    let el = t0.elapsed();
    let t1 = Instant::now();
    load(&mut p, &pts);
    let el_push = t1.elapsed();
    println!(
        "path: {N} segments, {ticks} ticks at 10 kHz = {:.3} s of motion; push {:.0} ns/segment, tick {:.0} ns",
        ticks as f64 * 1e-4,
        el_push.as_nanos() as f64 / N as f64,
        el.as_nanos() as f64 / ticks as f64
    );
    let mut g = c.benchmark_group("path 10k dense chords");
    g.sample_size(10);
    g.bench_function("push (per 10,000 segments)", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                let t = Instant::now();
                load(&mut p, &pts);
                total += t.elapsed();
            }
            total
        })
    });
    g.bench_function("tick (per 1,000 ticks)", |b| {
        let mut left = 0u64;
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                if left < 1000 {
                    load(&mut p, &pts);
                    left = ticks;
                }
                let t = Instant::now();
                for _ in 0..1000 {
                    black_box(p.tick(1.0, &mut |_| {}));
                }
                total += t.elapsed();
                left -= 1000;
            }
            total
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
