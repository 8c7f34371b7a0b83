//! Cost of one time-optimal plan from any state (`motion::otg::Trajectory::to_position`)
//! against rsruckig's calculation for the same single-DOF inputs: 1,000 random states from the
//! tests' generator (`testkit::otg`, all eight kinds in turn), planned one after the other.
//!
//! `cargo bench -p card-emu --bench otg`
//!
//! Criterion's figures are per 1,000 plans; the line printed first gives ns per plan of each
//! and their ratio, from a plain timed loop over the same set.
use card_emu::motion::otg::Trajectory;
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
        if let Ok(t) = Trajectory::to_position(c.p0, c.v0, c.a0, c.p1, c.v1, &c.lim) {
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

/// ns per plan of a plain loop over the set, best of `reps` rounds.
fn per_plan(reps: usize, mut f: impl FnMut() -> f64) -> f64 {
    let mut best = f64::INFINITY;
    for _ in 0..reps {
        let t = Instant::now();
        black_box(f());
        best = best.min(t.elapsed().as_secs_f64());
    }
    best / N as f64 * 1e9
}

fn bench(c: &mut Criterion) {
    let cases = states();
    let inputs = inputs(&cases);
    let mut otg = rk::Ruckig::<1, rk::IgnoreErrorHandler>::new(None, 0.001);
    let mut traj = rk::Trajectory::<1>::new(None);
    let a = per_plan(200, || ours(black_box(&cases)));
    let b = per_plan(200, || ruckig(&mut otg, &mut traj, black_box(&inputs)));
    println!(
        "otg::to_position {a:.0} ns/plan, rsruckig calculate {b:.0} ns/plan, ratio {:.2}",
        a / b
    );
    let mut g = c.benchmark_group("otg 1000 random states");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("Trajectory::to_position", |bch| {
        bch.iter(|| ours(black_box(&cases)))
    });
    g.bench_function("rsruckig Ruckig::calculate", |bch| {
        bch.iter(|| ruckig(&mut otg, &mut traj, black_box(&inputs)))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
