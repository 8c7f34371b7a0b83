//! Verifies that the per-tick functions do not touch the heap: a counting global allocator
//! (only in this test binary) records allocations made on this thread while armed.

use card_emu::motion::nurbs::{clamped_uniform_knots, Nurbs, Point};
use card_emu::motion::nurbs_interp::{InterpConfig, Interpolator};
use card_emu::motion::path_speed::PathSpeedPlanner;
use card_emu::motion::saturation::{AxisSample, SaturationAwareFeed};
use card_emu::presets::die_bonder_preset;
use card_emu::servo::pdplus::{DriveModelExt, PdPlus};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    static ARMED: Cell<bool> = const { Cell::new(false) };
    static COUNT: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if ARMED.with(|a| a.get()) {
            COUNT.with(|c| c.set(c.get() + 1));
        }
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if ARMED.with(|a| a.get()) {
            COUNT.with(|c| c.set(c.get() + 1));
        }
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn counted<R>(f: impl FnOnce() -> R) -> (R, usize) {
    COUNT.with(|c| c.set(0));
    ARMED.with(|a| a.set(true));
    let r = f();
    ARMED.with(|a| a.set(false));
    (r, COUNT.with(|c| c.get()))
}

#[test]
fn per_tick_functions_do_not_allocate() {
    let n = 200;
    let ctrl: Vec<f64> = (0..n)
        .flat_map(|i| {
            let t = i as f64 / 8.0;
            [30_000.0 * t.cos(), 20_000.0 * (1.3 * t).sin()]
        })
        .collect();
    let knots = clamped_uniform_knots(n, 4).unwrap();
    let w: Vec<f64> = (0..n).map(|i| 1.0 + 0.5 * ((i % 3) as f64)).collect();
    let curve = Nurbs::new(4, 2, &ctrl, &w, &knots).unwrap();
    let preset = die_bonder_preset();
    let sat = SaturationAwareFeed::new(&preset.axes, preset.ts).unwrap();
    let cfg = InterpConfig {
        feed: 300_000.0,
        ..InterpConfig::default()
    };
    let mut a = Interpolator::new(curve.clone(), cfg).unwrap();
    let mut b = Interpolator::with_actuator_limits(curve.clone(), cfg, &sat, 0.8).unwrap();
    let mut c = Interpolator::new(curve.clone(), cfg).unwrap();
    let mut pd = PdPlus::new(preset.axes[0].gains, preset.ts).unwrap();
    let mut planner = PathSpeedPlanner::new(1e-3, 1e7, 1e10).unwrap();
    let (ticks, allocs) = counted(|| {
        let mut n = 0usize;
        let mut theta = Point::zeros();
        let mut w_a = Point::zeros();
        while !(a.is_done() && b.is_done() && c.is_done()) && n < 200_000 {
            let _ = curve.eval(0.37);
            let _ = a.tick();
            let _ = c.advance(250_000.0);
            if let Ok((t, _)) = b.tick_guarded(&sat, &theta, &w_a) {
                // crude "plant": follow the reference with one tick of lag
                w_a = (t.pos - theta) / 1e-3;
                theta = t.pos;
                let _ = pd.update(t.pos[0], t.vel[0], t.acc[0], theta[0]);
                let _ = preset.axes[0].plant.step(1e-3, theta[0], w_a[0], 0.1);
            }
            let st = [AxisSample::default(); 2];
            let _ = sat.limit_feed(1e5, 2e5, &Point::x(), &st);
            let _ = planner.next(1e5, 1e6);
            n += 1;
        }
        n
    });
    println!("{ticks} ticks, {allocs} heap allocations");
    assert!(a.is_done() && b.is_done() && c.is_done());
    assert_eq!(allocs, 0);

    // A path of two curves run through their joint: the continuation, the planning over both
    // and the take-over of the step that crosses the joint.
    let pieces = card_emu::motion::nurbs::split_curve(4, 2, &ctrl, &w, &knots, 120).unwrap();
    assert_eq!(pieces.len(), 2);
    let mut first = Interpolator::new(pieces[0].clone(), cfg).unwrap();
    let mut second = Interpolator::new(pieces[1].clone(), cfg).unwrap();
    let (handed, allocs) = counted(|| {
        let mut n = 0;
        loop {
            let next = first.continuation(&second);
            assert!(next.is_some());
            let t = first.tick_into(next).unwrap();
            n += 1;
            if t.done {
                let t = second.take_over(&first).unwrap();
                assert!(t.feed > 0.0);
                break;
            }
            assert!(n < 200_000);
        }
        while !second.is_done() {
            let _ = second.tick();
        }
        true
    });
    assert!(handed);
    assert_eq!(allocs, 0, "allocations across a joint");
}
