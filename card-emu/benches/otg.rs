//! Cost of one time-optimal plan from any state (`motion::otg::Trajectory::to_position`)
//! against rsruckig's calculation for the same single-DOF inputs: 1,000 random states from the
//! tests' generator (`testkit::otg`, all eight kinds in turn), planned one after the other.
//!
//! `cargo bench -p card-emu --bench otg`
//!
//! Criterion's figures are per 1,000 plans; the line printed first gives ns per plan of each
//! and their ratio, from plain timed loops over the same set (the rounds of the two alternated,
//! best of each, so that both see the same load on a shared machine). `to_position` is the plan
//! as the card runs it, its own check (`Trajectory::verify`) included; the cost of that check
//! alone, timed on the same plans, is printed too, and the ratio without it.
use card_emu::motion::otg::{OtgLimits, Trajectory};
use card_emu::testkit::otg::{case, Case};
use card_emu::testkit::rng::Rng;
use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use rsruckig::prelude as rk;
use std::time::Instant;

const N: usize = 1000;

fn states() -> Vec<Case> {
    let mut rng = Rng::new(11);
    (0..N).map(|i| case(&mut rng, i % 8)).collect()
}

fn inputs(cases: &[Case]) -> Vec<rk::InputParameter<1>> {
    cases
        .iter()
        .map(|c| {
            let mut inp = rk::InputParameter::<1>::new(None);
            inp.current_position[0] = c.p0;
            inp.current_velocity[0] = c.v0;
            inp.current_acceleration[0] = c.a0;
            inp.target_position[0] = c.p1;
            inp.target_velocity[0] = c.v1;
            inp.max_velocity[0] = c.lim.vmax;
            inp.max_acceleration[0] = c.lim.amax;
            inp.max_jerk[0] = c.lim.jmax;
            inp.min_velocity = Some(rk::DataArrayOrVec::Stack([c.lim.vmin]));
            inp.min_acceleration = Some(rk::DataArrayOrVec::Stack([c.lim.amin]));
            inp
        })
        .collect()
}

fn ours(cases: &[Case]) -> f64 {
    let mut sum = 0.0;
    for c in cases {
        // (by reference: moving the 552-byte trajectory out of the result would time a copy)
        if let Ok(t) = &Trajectory::to_position(c.p0, c.v0, c.a0, c.p1, c.v1, &c.lim) {
            sum += t.duration();
        }
    }
    sum
}

fn ruckig(
    otg: &mut rk::Ruckig<1, rk::IgnoreErrorHandler>,
    traj: &mut rk::Trajectory<1>,
    inputs: &[rk::InputParameter<1>],
) -> f64 {
    let mut sum = 0.0;
    for inp in inputs {
        if let Ok(rk::RuckigResult::Working) = otg.calculate(inp, traj) {
            sum += traj.get_duration();
        }
    }
    sum
}

/// `Trajectory::verify` of each plan against its limits: the number that pass.
fn verify(plans: &[(Trajectory, OtgLimits)]) -> f64 {
    plans.iter().filter(|(t, l)| t.verify(l).is_ok()).count() as f64
}

/// ns per plan of each plain loop over the set, best of `reps` rounds; the rounds of the loops
/// alternate.
fn per_plan<const K: usize>(reps: usize, mut fs: [&mut dyn FnMut() -> f64; K]) -> [f64; K] {
    let mut best = [f64::INFINITY; K];
    for _ in 0..reps {
        for (f, b) in fs.iter_mut().zip(best.iter_mut()) {
            let t = Instant::now();
            black_box(f());
            *b = b.min(t.elapsed().as_secs_f64());
        }
    }
    best.map(|b| b / N as f64 * 1e9)
}

fn bench(c: &mut Criterion) {
    let cases = states();
    let inputs = inputs(&cases);
    let mut otg = rk::Ruckig::<1, rk::IgnoreErrorHandler>::new(None, 0.001);
    let mut traj = rk::Trajectory::<1>::new(None);
    let plans: Vec<(Trajectory, OtgLimits)> = cases
        .iter()
        .filter_map(|c| {
            let t = Trajectory::to_position(c.p0, c.v0, c.a0, c.p1, c.v1, &c.lim).ok()?;
            Some((t, c.lim))
        })
        .collect();
    let [a, b, v] = per_plan(
        300,
        [
            &mut || ours(black_box(&cases)),
            &mut || ruckig(&mut otg, &mut traj, black_box(&inputs)),
            &mut || verify(black_box(&plans)),
        ],
    );
    println!(
        "otg::to_position {a:.0} ns/plan (of which verify {v:.0}), rsruckig calculate {b:.0} \
         ns/plan, ratio {:.2} ({:.2} without verify)",
        a / b,
        (a - v) / b
    );
    let mut g = c.benchmark_group("otg 1000 random states");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("Trajectory::to_position", |bch| {
        bch.iter(|| ours(black_box(&cases)))
    });
    g.bench_function("rsruckig Ruckig::calculate", |bch| {
        bch.iter(|| ruckig(&mut otg, &mut traj, black_box(&inputs)))
    });
    g.bench_function("Trajectory::verify", |bch| {
        bch.iter(|| verify(black_box(&plans)))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
