//! The dense micro-segment benchmark of issue 14, shared by the `path` bench (the engine alone)
//! and `path_run -- dense` (the whole stepped card): a free-form curve (a hypotrochoid, radius
//! of curvature down to 1.25 mm) cut into 10,000 chords of ~0.083 mm (chord error ≤ 1 µm),
//! one count = 1 µm, axis limits 100 mm/s, 1 m/s², 100 m/s³ on both axes, 10 kHz; its
//! offline time bound, and the figures a run is judged by (peaks over the limits, distance
//! from the chords).

/// Servo period, s; axis velocity, acceleration and jerk limits, counts/s, /s², /s³.
pub const TS: f64 = 1e-4;
pub const V: f64 = 1e5;
pub const A: f64 = 1e6;
pub const J: f64 = 1e8;
/// Chords of the benchmark; the corner tolerance, counts.
pub const CHORDS: usize = 10_000;
pub const TOL: f64 = 1.0;

/// The hypotrochoid z(t) = a·e^{it} + b·e^{ikt} (counts), its minimum radius of curvature
/// (b·k − a)² / (b·k² − a) = 1250 counts = 1.25 mm.
const CA: f64 = 86_000.0;
const CK: f64 = 7.0;
const CB: f64 = 116_100.0 / 7.0;

fn curve(t: f64) -> [f64; 2] {
    [
        CA * t.cos() + CB * (CK * t).cos(),
        CA * t.sin() + CB * (CK * t).sin(),
    ]
}

/// Distance from `p` to the segment [a, b].
pub fn dist_seg(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let l2 = d[0] * d[0] + d[1] * d[1];
    let t = if l2 > 0.0 {
        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - a[0] - t * d[0]).hypot(p[1] - a[1] - t * d[1])
}

/// `n` chords of equal parameter-arc length along one turn, starting at the origin (the
/// group's position: the curve is shifted), and the largest chord error.
pub fn dense_points(n: usize) -> (Vec<[f64; 2]>, f64) {
    // Arc length table on a fine parameter grid, then equal-length stations.
    let m = 2_000_000;
    let mut s = vec![0.0; m + 1];
    let dt = std::f64::consts::TAU / m as f64;
    let mut prev = curve(0.0);
    for i in 1..=m {
        let p = curve(i as f64 * dt);
        s[i] = s[i - 1] + (p[0] - prev[0]).hypot(p[1] - prev[1]);
        prev = p;
    }
    let total = s[m];
    let o = curve(0.0);
    let mut pts = Vec::with_capacity(n + 1);
    let mut j = 0;
    for k in 0..=n {
        let target = total * k as f64 / n as f64;
        while j < m && s[j + 1] < target {
            j += 1;
        }
        let f = if j < m {
            (target - s[j]) / (s[j + 1] - s[j])
        } else {
            0.0
        };
        let p = curve((j as f64 + f) * dt);
        pts.push([p[0] - o[0], p[1] - o[1]]);
    }
    // The largest chord error (sampled between the stations).
    let mut chord_err: f64 = 0.0;
    for k in 0..n {
        let t0 = total * k as f64 / n as f64;
        let mid = t0 + 0.5 * total / n as f64;
        let jm = s.partition_point(|x| *x < mid).min(m);
        let p = curve(jm as f64 * dt);
        chord_err = chord_err.max(dist_seg([p[0] - o[0], p[1] - o[1]], pts[k], pts[k + 1]));
    }
    (pts, chord_err)
}

/// The offline bound: the time along the exact curve at the largest speed its curvature and
/// each axis's velocity, acceleration and jerk allow (normal terms at constant speed), with a
/// tangential acceleration within the smallest axis acceleration (forward and backward
/// passes), from rest to rest. A lower bound on any jerk-limited run.
pub fn bound_time(feed: f64) -> f64 {
    let m = 400_000;
    let dt = std::f64::consts::TAU / m as f64;
    // unit tangent T, curvature vector κN = (z'' − (z''·T)T)/|z'|² and |z'| at parameter t
    let frame = |t: f64| {
        let d1 = [
            -CA * t.sin() - CB * CK * (CK * t).sin(),
            CA * t.cos() + CB * CK * (CK * t).cos(),
        ];
        let d2 = [
            -CA * t.cos() - CB * CK * CK * (CK * t).cos(),
            -CA * t.sin() - CB * CK * CK * (CK * t).sin(),
        ];
        let sp = d1[0].hypot(d1[1]);
        let tan = [d1[0] / sp, d1[1] / sp];
        let dt2 = d2[0] * tan[0] + d2[1] * tan[1];
        let kn = [
            (d2[0] - dt2 * tan[0]) / (sp * sp),
            (d2[1] - dt2 * tan[1]) / (sp * sp),
        ];
        (tan, kn, sp)
    };
    let mut ds = vec![0.0; m];
    let mut cap = vec![0.0; m + 1];
    for i in 0..=m {
        let t = i as f64 * dt;
        let (tan, kn, sp) = frame(t);
        let mut c = feed;
        for a in 0..2 {
            if tan[a].abs() > 0.0 {
                c = c.min(V / tan[a].abs());
            }
            if kn[a].abs() > 0.0 {
                c = c.min((A / kn[a].abs()).sqrt());
            }
        }
        if i < m {
            // jerk at constant speed: v³·|d(κN)/ds|, by differences of κN along s
            let (_, k1, _) = frame(t + dt);
            for a in 0..2 {
                let dk = ((k1[a] - kn[a]) / (sp * dt)).abs();
                if dk > 0.0 {
                    c = c.min((J / dk).cbrt());
                }
            }
            ds[i] = sp * dt;
        }
        cap[i] = c;
    }
    cap[0] = 0.0;
    cap[m] = 0.0;
    for i in 0..m {
        cap[i + 1] = cap[i + 1].min((cap[i] * cap[i] + 2.0 * A * ds[i]).sqrt());
    }
    for i in (0..m).rev() {
        cap[i] = cap[i].min((cap[i + 1] * cap[i + 1] + 2.0 * A * ds[i]).sqrt());
    }
    (0..m)
        .map(|i| 2.0 * ds[i] / (cap[i] + cap[i + 1]).max(1e-9))
        .sum()
}

/// What a run's commanded positions (one per tick, from rest to rest) show: path time, peak
/// axis velocity, acceleration and jerk over the limits (finite differences per tick), and
/// the worst distance from the chords.
#[derive(Debug, Clone, Copy)]
pub struct Quality {
    pub time: f64,
    pub peaks: [f64; 3],
    pub deviation: f64,
}

pub fn quality(pos: &[[f64; 2]], pts: &[[f64; 2]], lim: [[f64; 3]; 2]) -> Quality {
    let first = pos.iter().position(|p| *p != pos[0]).unwrap_or(0);
    let last = pos
        .iter()
        .rposition(|p| *p != pos[pos.len() - 1])
        .unwrap_or(0);
    let mut peaks = [0.0f64; 3];
    for (a, l) in lim.iter().enumerate() {
        for w in pos.windows(4) {
            let v = (w[3][a] - w[2][a]) / TS;
            let acc = (w[3][a] - 2.0 * w[2][a] + w[1][a]) / (TS * TS);
            let j = (w[3][a] - 3.0 * w[2][a] + 3.0 * w[1][a] - w[0][a]) / (TS * TS * TS);
            peaks[0] = peaks[0].max(v.abs() / l[0]);
            peaks[1] = peaks[1].max(acc.abs() / l[1]);
            peaks[2] = peaks[2].max(j.abs() / l[2]);
        }
    }
    // Distance to the chords, walking a window forward with the motion.
    let mut k = 0usize;
    let mut deviation: f64 = 0.0;
    for p in pos {
        let lo = k.saturating_sub(4);
        let hi = (k + 64).min(pts.len() - 1);
        let (mut best, mut bi) = (f64::INFINITY, k);
        for i in lo..hi {
            let d = dist_seg(*p, pts[i], pts[i + 1]);
            if d < best {
                best = d;
                bi = i;
            }
        }
        k = bi;
        deviation = deviation.max(best);
    }
    Quality {
        time: (last + 1 - first) as f64 * TS,
        peaks,
        deviation,
    }
}
