//! Rational B-spline (NURBS) curves of degree 1..=5 in 2..=8 dimensions.
//!
//! Storage is allocated at construction (at most `MAX_CTRL` control points), or once with room
//! for the largest curve ([`Nurbs::with_capacity`]) and refilled in place ([`Nurbs::set`]);
//! evaluation ([`Nurbs::eval`]) allocates nothing and never panics. Algorithms follow Piegl & Tiller, *The NURBS Book* (2nd ed.):
//! A2.1 `FindSpan`, A2.3 `DersBasisFuns`, and the rational-derivative quotient rule of
//! eq. 4.8 / A4.2 applied to the homogeneous curve `Cw(u) = Σ N_i,p(u) · (w_i P_i, w_i)`.
//!
//! Units are whatever the caller uses (in the firmware: encoder counts for points, and
//! the curve parameter `u` is dimensionless).

use core::fmt;
use nalgebra::SVector;

use crate::ram::FixedVec;
#[cfg(feature = "host")]
use alloc::{vec, vec::Vec};

/// Highest supported degree p.
pub const MAX_DEGREE: usize = 5;
/// Highest supported spatial dimension (number of axes).
pub const MAX_DIM: usize = 8;
/// Highest number of control points per curve.
pub const MAX_CTRL: usize = 1024;
/// Highest knot-vector length: `MAX_CTRL + MAX_DEGREE + 1`.
pub const MAX_KNOTS: usize = MAX_CTRL + MAX_DEGREE + 1;
/// Largest ratio between two weights of a curve. Beyond about 10⁶ the curve's parametric
/// speed has spikes the adaptive arc-length quadrature cannot resolve: planning the move
/// takes seconds and its length comes out wrong (a degree-1 curve with weights 0.08 and
/// 2.6·10⁹ measured half its true length after 8 s). CAD weights stay within 10³.
pub const MAX_WEIGHT_RATIO: f64 = 1e4;

/// Width of a homogeneous control point: `MAX_DIM` weighted coordinates, then the weight.
const HW: usize = MAX_DIM + 1;
/// Index of the weight inside a homogeneous point.
const W: usize = MAX_DIM;
/// Basis-function table width.
const PB: usize = MAX_DEGREE + 1;

/// A point (or derivative vector) of a curve; entries `dim..MAX_DIM` are zero.
pub type Point = SVector<f64, MAX_DIM>;

/// Everything that can be wrong with a NURBS definition or an evaluation request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NurbsError {
    /// Degree outside `1..=MAX_DEGREE`.
    BadDegree { degree: usize },
    /// Dimension outside `2..=MAX_DIM`.
    BadDimension { dim: usize },
    /// The flat control-point slice is empty or not a multiple of `dim`.
    ControlDataLength { len: usize, dim: usize },
    /// Fewer than `p + 1` control points.
    TooFewControlPoints { n_ctrl: usize, min: usize },
    /// More than `MAX_CTRL` control points.
    TooManyControlPoints { n_ctrl: usize, max: usize },
    /// `weights.len() != n_ctrl`.
    WeightCountMismatch { weights: usize, n_ctrl: usize },
    /// `knots.len() != n_ctrl + p + 1` (= n + p + 2 with n = n_ctrl − 1).
    KnotCountMismatch { knots: usize, expected: usize },
    /// A knot is NaN or infinite.
    NonFiniteKnot { index: usize },
    /// `knots[index] < knots[index - 1]`.
    KnotsDecreasing { index: usize },
    /// A run of equal knots starting at `index` is too long: more than `p` inside, or more
    /// than `p + 1` at an end.
    KnotMultiplicity { index: usize, multiplicity: usize },
    /// The first or last knot is not repeated `p + 1` times (only clamped curves are accepted).
    NotClamped,
    /// First knot equals last knot: the parameter domain is empty.
    EmptyDomain,
    /// Weight not finite or not > 0, or more than `MAX_WEIGHT_RATIO` times (or less than
    /// 1/`MAX_WEIGHT_RATIO` of) another weight.
    BadWeight { index: usize },
    /// A control point has a NaN or infinite coordinate.
    NonFiniteControlPoint { index: usize },
    /// `eval` called with NaN or ±∞.
    NonFiniteParameter,
    /// `eval` called outside `[u_first, u_last]`.
    ParameterOutOfRange,
    /// `Nurbs::circle` called with a non-finite centre or a radius that is not finite and > 0.
    BadCircle,
}

impl fmt::Display for NurbsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::BadDegree { degree } => write!(f, "degree {degree} not in 1..={MAX_DEGREE}"),
            Self::BadDimension { dim } => write!(f, "dimension {dim} not in 2..={MAX_DIM}"),
            Self::ControlDataLength { len, dim } => {
                write!(
                    f,
                    "control data length {len} is not a non-zero multiple of {dim}"
                )
            }
            Self::TooFewControlPoints { n_ctrl, min } => {
                write!(f, "{n_ctrl} control points, need at least {min}")
            }
            Self::TooManyControlPoints { n_ctrl, max } => {
                write!(f, "{n_ctrl} control points, at most {max}")
            }
            Self::WeightCountMismatch { weights, n_ctrl } => {
                write!(f, "{weights} weights for {n_ctrl} control points")
            }
            Self::KnotCountMismatch { knots, expected } => {
                write!(f, "{knots} knots, expected n + p + 2 = {expected}")
            }
            Self::NonFiniteKnot { index } => write!(f, "knot {index} is not finite"),
            Self::KnotsDecreasing { index } => {
                write!(f, "knot {index} is below knot {}", index - 1)
            }
            Self::KnotMultiplicity {
                index,
                multiplicity,
            } => write!(f, "knot run at {index} has multiplicity {multiplicity}"),
            Self::NotClamped => write!(f, "knot vector is not clamped (end knots need p+1 copies)"),
            Self::EmptyDomain => write!(f, "first and last knot are equal"),
            Self::BadWeight { index } => write!(
                f,
                "weight {index} is not finite and positive, or over {MAX_WEIGHT_RATIO:e} times \
                 another weight (or under its 1/{MAX_WEIGHT_RATIO:e})"
            ),
            Self::NonFiniteControlPoint { index } => {
                write!(f, "control point {index} is not finite")
            }
            Self::NonFiniteParameter => write!(f, "parameter is not finite"),
            Self::ParameterOutOfRange => write!(f, "parameter outside the knot domain"),
            Self::BadCircle => write!(f, "circle needs a finite centre and a finite radius > 0"),
        }
    }
}

impl core::error::Error for NurbsError {}

/// A clamped NURBS curve. Its storage holds exactly its control points and knots, or, for a
/// curve made by [`with_capacity`](Self::with_capacity), room for the largest curve, which
/// [`set`](Self::set) then fills in place without allocating.
#[derive(Clone, Debug)]
pub struct Nurbs {
    degree: usize,
    dim: usize,
    n_ctrl: usize,
    /// Homogeneous control points `(w·P, w)`, `n_ctrl` rows.
    pw: FixedVec<[f64; HW], MAX_CTRL>,
    /// Knot vector, `n_ctrl + degree + 1` entries.
    knots: FixedVec<f64, MAX_KNOTS>,
}

/// Two curves are equal when they have the same degree, dimension, homogeneous control points
/// and knots (storage capacity aside).
impl PartialEq for Nurbs {
    fn eq(&self, o: &Self) -> bool {
        self.degree == o.degree
            && self.dim == o.dim
            && self.n_ctrl == o.n_ctrl
            && self.pw == o.pw
            && self.knots == o.knots
    }
}

/// Basis functions and their first two derivatives at one parameter (NURBS Book A2.3 output).
type BasisDers = [[f64; PB]; 3];

impl Nurbs {
    /// Builds a curve of `degree` in `dim` dimensions.
    ///
    /// `ctrl` is flat, `dim` coordinates per control point (`n_ctrl = ctrl.len() / dim`);
    /// `weights` has `n_ctrl` entries; `knots` has `n_ctrl + degree + 1` entries, is clamped
    /// (first and last knot each exactly `degree + 1` times), non-decreasing, with interior
    /// multiplicities ≤ `degree`.
    pub fn new(
        degree: usize,
        dim: usize,
        ctrl: &[f64],
        weights: &[f64],
        knots: &[f64],
    ) -> Result<Self, NurbsError> {
        let n_ctrl = check_curve(degree, dim, ctrl, weights, knots, MAX_CTRL)?;
        let mut c = Self {
            degree: 0,
            dim: 0,
            n_ctrl: 0,
            pw: FixedVec::with_capacity(n_ctrl),
            knots: FixedVec::with_capacity(knots.len()),
        };
        c.fill(degree, dim, n_ctrl, ctrl, weights, knots);
        Ok(c)
    }

    /// A curve with room for [`MAX_CTRL`] control points and [`MAX_KNOTS`] knots, allocated
    /// once (and not touched: the pages stay unused until a curve fills them). Until
    /// [`set`](Self::set) it is the straight line from (0, 0) to (1, 0).
    pub fn with_capacity() -> Self {
        let mut c = Self {
            degree: 0,
            dim: 0,
            n_ctrl: 0,
            pw: FixedVec::with_capacity(MAX_CTRL),
            knots: FixedVec::with_capacity(MAX_KNOTS),
        };
        c.fill(
            1,
            2,
            2,
            &[0.0, 0.0, 1.0, 0.0],
            &[1.0, 1.0],
            &[0.0, 0.0, 1.0, 1.0],
        );
        c
    }

    /// Replace the curve by the one [`new`](Self::new) would build from the same arguments,
    /// in this curve's storage: no allocation when it has the room (see
    /// [`with_capacity`](Self::with_capacity)). A refused curve leaves this one unchanged.
    pub fn set(
        &mut self,
        degree: usize,
        dim: usize,
        ctrl: &[f64],
        weights: &[f64],
        knots: &[f64],
    ) -> Result<(), NurbsError> {
        let n_ctrl = check_curve(degree, dim, ctrl, weights, knots, MAX_CTRL)?;
        self.fill(degree, dim, n_ctrl, ctrl, weights, knots);
        Ok(())
    }

    /// Store a checked curve.
    fn fill(
        &mut self,
        degree: usize,
        dim: usize,
        n_ctrl: usize,
        ctrl: &[f64],
        weights: &[f64],
        knots: &[f64],
    ) {
        // checked: at most MAX_CTRL points, MAX_KNOTS knots
        self.pw.clear();
        for (p, &w) in ctrl.chunks_exact(dim).zip(weights) {
            let mut row = [0.0; HW];
            for (dst, &c) in row.iter_mut().zip(p.iter()) {
                *dst = c * w;
            }
            row[W] = w;
            let _ = self.pw.push(row);
        }
        self.knots.clear();
        let _ = self.knots.extend_from_slice(knots);
        self.degree = degree;
        self.dim = dim;
        self.n_ctrl = n_ctrl;
    }

    /// Exact full circle of `radius` around `center` (2-D) from four rational quadratic
    /// arcs: 9 control points on the circumscribed square, weights 1, √2/2 alternating,
    /// knots `[0,0,0,¼,¼,½,½,¾,¾,1,1,1]` (NURBS Book §7.5). Starts at angle 0,
    /// counter-clockwise.
    pub fn circle(center: [f64; 2], radius: f64) -> Result<Self, NurbsError> {
        if !(radius.is_finite() && radius > 0.0) || center.iter().any(|c| !c.is_finite()) {
            return Err(NurbsError::BadCircle);
        }
        let s = core::f64::consts::FRAC_1_SQRT_2;
        let unit: [[f64; 2]; 9] = [
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [-1.0, 1.0],
            [-1.0, 0.0],
            [-1.0, -1.0],
            [0.0, -1.0],
            [1.0, -1.0],
            [1.0, 0.0],
        ];
        let mut ctrl = [0.0; 18];
        for (dst, p) in ctrl.chunks_exact_mut(2).zip(unit.iter()) {
            dst[0] = center[0] + radius * p[0];
            dst[1] = center[1] + radius * p[1];
        }
        let weights = [1.0, s, 1.0, s, 1.0, s, 1.0, s, 1.0];
        let knots = [
            0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
        ];
        Self::new(2, 2, &ctrl, &weights, &knots).map_err(|_| NurbsError::BadCircle)
    }

    /// Degree p.
    pub fn degree(&self) -> usize {
        self.degree
    }
    /// Number of axes.
    pub fn dim(&self) -> usize {
        self.dim
    }
    /// Number of control points (n + 1).
    pub fn n_ctrl(&self) -> usize {
        self.n_ctrl
    }
    /// The knot vector (length `n_ctrl + degree + 1`).
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }
    /// Parameter domain `[u_first, u_last]`.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.n_ctrl])
    }
    /// Weight of control point `i` (None if out of range).
    pub fn weight(&self, i: usize) -> Option<f64> {
        (i < self.n_ctrl).then(|| self.pw[i][W])
    }
    /// Cartesian control point `i` (None if out of range).
    pub fn control_point(&self, i: usize) -> Option<Point> {
        if i >= self.n_ctrl {
            return None;
        }
        let row = &self.pw[i];
        let mut p = Point::zeros();
        for k in 0..self.dim {
            p[k] = row[k] / row[W];
        }
        Some(p)
    }

    /// NURBS Book A2.1 `FindSpan`: the index `i` with `U[i] <= u < U[i+1]`, the last non-empty
    /// span for `u >= U[n+1]`, the first one for `u <= U[p]`. `u` must be finite.
    pub fn find_span(&self, u: f64) -> usize {
        let p = self.degree;
        let n = self.n_ctrl - 1;
        let k = &self.knots;
        if u >= k[n + 1] {
            return n; // clamped with end multiplicity exactly p+1 => U[n] < U[n+1]
        }
        if u <= k[p] {
            return p;
        }
        let (mut low, mut high) = (p, n + 1);
        let mut mid = (low + high) / 2;
        // Invariant U[low] <= u < U[high]; at most log2(MAX_KNOTS)+1 halvings.
        for _ in 0..64 {
            if u < k[mid] {
                high = mid;
            } else if u >= k[mid + 1] {
                low = mid;
            } else {
                break;
            }
            mid = (low + high) / 2;
        }
        mid
    }

    /// NURBS Book A2.3 `DersBasisFuns` for derivatives up to order min(2, p); higher-order
    /// rows are zero. `ders[k][j]` = k-th derivative of `N_{span-p+j, p}` at `u`.
    fn ders_basis_funs(&self, span: usize, u: f64) -> BasisDers {
        let p = self.degree;
        let k = &self.knots;
        let mut ders: BasisDers = [[0.0; PB]; 3];
        let mut ndu = [[0.0; PB]; PB];
        let mut left = [0.0; PB];
        let mut right = [0.0; PB];
        ndu[0][0] = 1.0;
        for j in 1..=p {
            left[j] = u - k[span + 1 - j];
            right[j] = k[span + j] - u;
            let mut saved = 0.0;
            for r in 0..j {
                // lower triangle: knot differences
                ndu[j][r] = right[r + 1] + left[j - r];
                let temp = ndu[r][j - 1] / ndu[j][r];
                // upper triangle: basis functions
                ndu[r][j] = saved + right[r + 1] * temp;
                saved = left[j - r] * temp;
            }
            ndu[j][j] = saved;
        }
        for j in 0..=p {
            ders[0][j] = ndu[j][p];
        }
        let nd = p.min(2);
        let mut a = [[0.0; PB]; 2];
        for r in 0..=p {
            let (mut s1, mut s2) = (0usize, 1usize);
            a[0][0] = 1.0;
            for kk in 1..=nd {
                let mut d = 0.0;
                let pk = p - kk;
                // rk = r - kk may be negative: work with offsets
                if r >= kk {
                    let rk = r - kk;
                    a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
                    d = a[s2][0] * ndu[rk][pk];
                }
                // j1 = 1 if rk >= -1 else -rk
                let j1 = if r + 1 >= kk { 1 } else { kk - r };
                // j2 = kk-1 if r-1 <= pk else p-r
                let j2 = if r <= pk + 1 { kk - 1 } else { p - r };
                for j in j1..=j2 {
                    // rk + j = r + j - kk >= 0 because j >= j1
                    let rkj = r + j - kk;
                    a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rkj];
                    d += a[s2][j] * ndu[rkj][pk];
                }
                if r <= pk {
                    a[s2][kk] = -a[s1][kk - 1] / ndu[pk + 1][r];
                    d += a[s2][kk] * ndu[r][pk];
                }
                ders[kk][r] = d;
                core::mem::swap(&mut s1, &mut s2);
            }
        }
        let mut fac = p as f64;
        for (kk, row) in ders.iter_mut().enumerate().take(nd + 1).skip(1) {
            for v in row.iter_mut().take(p + 1) {
                *v *= fac;
            }
            fac *= (p - kk) as f64;
        }
        ders
    }

    /// Point, first and second derivative with respect to `u` (NURBS Book eq 4.8, A4.2),
    /// evaluated in the span that contains `u` (right-continuous at interior knots).
    ///
    /// Errors: `NonFiniteParameter`, `ParameterOutOfRange`. Allocation-free.
    pub fn eval(&self, u: f64) -> Result<(Point, Point, Point), NurbsError> {
        if !u.is_finite() {
            return Err(NurbsError::NonFiniteParameter);
        }
        let (a, b) = self.domain();
        if u < a || u > b {
            return Err(NurbsError::ParameterOutOfRange);
        }
        Ok(self.eval_in_domain(u))
    }

    /// Like [`eval`](Self::eval) but clamps `u` into the domain (NaN maps to the start).
    pub fn eval_clamped(&self, u: f64) -> (Point, Point, Point) {
        let (a, b) = self.domain();
        let uc = if u.is_nan() { a } else { u.clamp(a, b) };
        self.eval_in_domain(uc)
    }

    /// Point only.
    pub fn point(&self, u: f64) -> Result<Point, NurbsError> {
        self.eval(u).map(|(c, _, _)| c)
    }

    /// Like [`eval_clamped`](Self::eval_clamped), with the knot span of the previous call as
    /// a hint (`hint` is updated): a caller that moves along the curve skips the span search.
    pub fn eval_hinted(&self, u: f64, hint: &mut usize) -> (Point, Point, Point) {
        let (a, b) = self.domain();
        let u = if u.is_nan() { a } else { u.clamp(a, b) };
        let k = &self.knots;
        let h = *hint;
        let span = if h >= self.degree && h < self.n_ctrl && k[h] <= u && u < k[h + 1] {
            h
        } else if h + 1 >= self.degree && h + 1 < self.n_ctrl && k[h + 1] <= u && u < k[h + 2] {
            h + 1
        } else {
            self.find_span(u)
        };
        *hint = span;
        self.eval_span(span, u)
    }

    /// Point, first and second derivative at `u` (clamped into the span) in knot span `span`
    /// (`knots[span] < knots[span + 1]`, `degree <= span < n_ctrl`; else the span of `u`): at
    /// the span's right end, the left limits (the span's own polynomial).
    pub fn eval_in_span(&self, span: usize, u: f64) -> (Point, Point, Point) {
        let k = &self.knots;
        if span < self.degree || span >= self.n_ctrl || k[span] >= k[span + 1] || u.is_nan() {
            return self.eval_clamped(u);
        }
        self.eval_span(span, u.clamp(k[span], k[span + 1]))
    }

    fn eval_in_domain(&self, u: f64) -> (Point, Point, Point) {
        self.eval_span(self.find_span(u), u)
    }

    fn eval_span(&self, span: usize, u: f64) -> (Point, Point, Point) {
        let p = self.degree;
        let nders = self.ders_basis_funs(span, u);
        // Homogeneous derivatives Aw^(k)(u) = Σ_j N^(k)_{span-p+j}(u) · Pw_{span-p+j}
        let mut aw = [[0.0; HW]; 3];
        for (j, row) in self.pw.iter().skip(span - p).take(p + 1).enumerate() {
            for (k, awk) in aw.iter_mut().enumerate() {
                let n = nders[k][j];
                for c in 0..self.dim {
                    awk[c] += n * row[c];
                }
                awk[W] += n * row[W];
            }
        }
        let (w0, w1, w2) = (aw[0][W], aw[1][W], aw[2][W]);
        // w0 > 0: positive weights, non-negative basis summing to 1.
        let mut c = Point::zeros();
        let mut d1 = Point::zeros();
        let mut d2 = Point::zeros();
        for i in 0..self.dim {
            // NURBS Book eq 4.8: C = A/w, C' = (A' - w'C)/w, C'' = (A'' - 2w'C' - w''C)/w
            c[i] = aw[0][i] / w0;
            d1[i] = (aw[1][i] - w1 * c[i]) / w0;
            d2[i] = (aw[2][i] - 2.0 * w1 * d1[i] - w2 * c[i]) / w0;
        }
        (c, d1, d2)
    }
}

fn validate_knots(p: usize, n_ctrl: usize, knots: &[f64]) -> Result<(), NurbsError> {
    let expected = n_ctrl + p + 1;
    if knots.len() != expected {
        return Err(NurbsError::KnotCountMismatch {
            knots: knots.len(),
            expected,
        });
    }
    if let Some(index) = knots.iter().position(|k| !k.is_finite()) {
        return Err(NurbsError::NonFiniteKnot { index });
    }
    if let Some(i) = knots.windows(2).position(|w| w[1] < w[0]) {
        return Err(NurbsError::KnotsDecreasing { index: i + 1 });
    }
    let m = knots.len();
    if knots[0] == knots[m - 1] {
        return Err(NurbsError::EmptyDomain);
    }
    // Runs of equal knots.
    let mut start = 0;
    while start < m {
        let mut end = start + 1;
        while end < m && knots[end] == knots[start] {
            end += 1;
        }
        let mult = end - start;
        let at_start = start == 0;
        let at_end = end == m;
        if at_start || at_end {
            if mult < p + 1 {
                return Err(NurbsError::NotClamped);
            }
            if mult > p + 1 {
                return Err(NurbsError::KnotMultiplicity {
                    index: start,
                    multiplicity: mult,
                });
            }
        } else if mult > p {
            return Err(NurbsError::KnotMultiplicity {
                index: start,
                multiplicity: mult,
            });
        }
        start = end;
    }
    Ok(())
}

/// Clamped uniform knot vector on [0, 1] for `n_ctrl` control points of `degree`:
/// `p+1` zeros, `n_ctrl-p-1` equally spaced interior knots, `p+1` ones. Host-side helper.
#[cfg(feature = "host")]
pub fn clamped_uniform_knots(n_ctrl: usize, degree: usize) -> Result<Vec<f64>, NurbsError> {
    if degree == 0 || degree > MAX_DEGREE {
        return Err(NurbsError::BadDegree { degree });
    }
    if n_ctrl < degree + 1 {
        return Err(NurbsError::TooFewControlPoints {
            n_ctrl,
            min: degree + 1,
        });
    }
    if n_ctrl > MAX_CTRL {
        return Err(NurbsError::TooManyControlPoints {
            n_ctrl,
            max: MAX_CTRL,
        });
    }
    let segs = n_ctrl - degree; // number of non-empty spans
    let mut k = Vec::with_capacity(n_ctrl + degree + 1);
    k.extend(core::iter::repeat_n(0.0, degree + 1));
    for i in 1..segs {
        k.push(i as f64 / segs as f64);
    }
    k.extend(core::iter::repeat_n(1.0, degree + 1));
    Ok(k)
}

/// What [`Nurbs::new`] and [`split_curve`] check of their arguments, in this order: degree,
/// dimension, control data length, at least `degree + 1` and at most `max_ctrl` control
/// points, one weight per point, the knot vector, the weights (finite, positive, within
/// [`MAX_WEIGHT_RATIO`] of each other), the control points (finite, also once weighted).
/// Returns the number of control points.
fn check_curve(
    degree: usize,
    dim: usize,
    ctrl: &[f64],
    weights: &[f64],
    knots: &[f64],
    max_ctrl: usize,
) -> Result<usize, NurbsError> {
    if degree == 0 || degree > MAX_DEGREE {
        return Err(NurbsError::BadDegree { degree });
    }
    if !(2..=MAX_DIM).contains(&dim) {
        return Err(NurbsError::BadDimension { dim });
    }
    if ctrl.is_empty() || !ctrl.len().is_multiple_of(dim) {
        return Err(NurbsError::ControlDataLength {
            len: ctrl.len(),
            dim,
        });
    }
    let n_ctrl = ctrl.len() / dim;
    if n_ctrl < degree + 1 {
        return Err(NurbsError::TooFewControlPoints {
            n_ctrl,
            min: degree + 1,
        });
    }
    if n_ctrl > max_ctrl {
        return Err(NurbsError::TooManyControlPoints {
            n_ctrl,
            max: max_ctrl,
        });
    }
    if weights.len() != n_ctrl {
        return Err(NurbsError::WeightCountMismatch {
            weights: weights.len(),
            n_ctrl,
        });
    }
    validate_knots(degree, n_ctrl, knots)?;
    if let Some(index) = weights.iter().position(|w| !(w.is_finite() && *w > 0.0)) {
        return Err(NurbsError::BadWeight { index });
    }
    let lightest = weights.iter().copied().fold(f64::INFINITY, f64::min);
    if let Some(index) = weights
        .iter()
        .position(|&w| w > MAX_WEIGHT_RATIO * lightest)
    {
        return Err(NurbsError::BadWeight { index });
    }
    // Finite, and w·P does not overflow.
    if let Some(index) = ctrl
        .chunks_exact(dim)
        .zip(weights)
        .position(|(p, w)| p.iter().any(|c| !c.is_finite() || !(c * w).is_finite()))
    {
        return Err(NurbsError::NonFiniteControlPoint { index });
    }
    Ok(n_ctrl)
}

/// Splits a clamped NURBS curve of any number of control points into consecutive curves of
/// at most `max_ctrl` control points each (host-side helper; allocates). The curve is cut at
/// interior knots: each cut knot is inserted until its multiplicity is the degree (Boehm's
/// knot insertion, NURBS Book A5.1, on the homogeneous points), where the curve passes through
/// a control point; the pieces are the two halves of that control polygon, with the knots on
/// either side clamped there. Knot insertion does not change the curve, so the pieces are the
/// curve exactly (up to rounding), keep its parametrisation, and share their end points
/// bit for bit. Arguments as for [`Nurbs::new`] except the control point count; `max_ctrl` is
/// at most [`MAX_CTRL`] and at least `degree + 1`.
#[cfg(feature = "host")]
pub fn split_curve(
    degree: usize,
    dim: usize,
    ctrl: &[f64],
    weights: &[f64],
    knots: &[f64],
    max_ctrl: usize,
) -> Result<Vec<Nurbs>, NurbsError> {
    let p = degree;
    let n_ctrl = check_curve(degree, dim, ctrl, weights, knots, usize::MAX)?;
    let max_ctrl = max_ctrl.clamp(p + 1, MAX_CTRL);
    let mut pw: Vec<[f64; HW]> = Vec::with_capacity(n_ctrl + 2 * p);
    for (pt, &w) in ctrl.chunks_exact(dim).zip(weights) {
        let mut row = [0.0; HW];
        for (dst, &c) in row.iter_mut().zip(pt) {
            *dst = c * w;
        }
        row[W] = w;
        pw.push(row);
    }
    let mut kv = knots.to_vec();
    let build = |pw: &[[f64; HW]], kv: &[f64]| {
        let mut c = Vec::with_capacity(pw.len() * dim);
        let mut w = Vec::with_capacity(pw.len());
        for row in pw {
            c.extend(row[..dim].iter().map(|x| x / row[W]));
            w.push(row[W]);
        }
        Nurbs::new(p, dim, &c, &w, kv)
    };
    let mut out = Vec::new();
    while pw.len() > max_ctrl {
        // The largest cut that leaves at most max_ctrl points on the left: a distinct interior
        // knot whose first copy is at index i (the left piece then has i control points).
        let last = kv[kv.len() - 1];
        let Some(i) = (p + 1..=max_ctrl.min(kv.len() - 1))
            .rev()
            .find(|&i| kv[i] > kv[i - 1] && kv[i] < last)
        else {
            break; // cannot happen for a valid curve with max_ctrl ≥ p + 1
        };
        let u = kv[i];
        let s = kv[i..].iter().take_while(|&&k| k == u).count();
        if s < p {
            (pw, kv) = insert_knot(p, &pw, &kv, u, i + s - 1, s, p - s);
        }
        // u now has multiplicity p at i..i+p; C(u) is control point i-1
        let mut left_k = kv[..i + p].to_vec();
        left_k.push(u);
        out.push(build(&pw[..i], &left_k)?);
        let mut right_k = vec![u];
        right_k.extend_from_slice(&kv[i..]);
        pw.drain(..i - 1);
        kv = right_k;
    }
    out.push(build(&pw, &kv)?);
    Ok(out)
}

/// NURBS Book A5.1 `CurveKnotIns`: inserts `u` (in span `k`, `U[k] ≤ u < U[k+1]`, already of
/// multiplicity `s`) `r` times into the homogeneous control polygon `pw` with knots `up`.
#[cfg(feature = "host")]
fn insert_knot(
    p: usize,
    pw: &[[f64; HW]],
    up: &[f64],
    u: f64,
    k: usize,
    s: usize,
    r: usize,
) -> (Vec<[f64; HW]>, Vec<f64>) {
    let np = pw.len() - 1;
    let mp = np + p + 1;
    let mut uq = Vec::with_capacity(mp + r + 1);
    uq.extend_from_slice(&up[..=k]);
    uq.extend(core::iter::repeat_n(u, r));
    uq.extend_from_slice(&up[k + 1..=mp]);
    let mut qw = vec![[0.0; HW]; np + r + 1];
    qw[..=k - p].copy_from_slice(&pw[..=k - p]);
    qw[k - s + r..=np + r].copy_from_slice(&pw[k - s..=np]);
    let mut rw: Vec<[f64; HW]> = pw[k - p..=k - s].to_vec();
    let mut l = k - p;
    for j in 1..=r {
        l = k - p + j;
        for i in 0..=p - j - s {
            let alpha = (u - up[l + i]) / (up[i + k + 1] - up[l + i]);
            let (a, b) = (rw[i + 1], rw[i]);
            for c in 0..HW {
                rw[i][c] = alpha * a[c] + (1.0 - alpha) * b[c];
            }
        }
        qw[l] = rw[0];
        qw[k + r - j - s] = rw[p - j - s];
    }
    if l + 1 < k - s {
        qw[l + 1..k - s].copy_from_slice(&rw[1..k - s - l]);
    }
    (qw, uq)
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::testkit::rng::Rng;

    struct Def {
        p: usize,
        dim: usize,
        ctrl: Vec<f64>,
        w: Vec<f64>,
        knots: Vec<f64>,
    }

    fn random_def(r: &mut Rng) -> Def {
        let p = r.int(1, 5);
        let dim = r.int(2, 8);
        let n_ctrl = if r.unit() < 0.15 {
            r.int(p + 1, 200)
        } else {
            r.int(p + 1, p + 14)
        };
        let ctrl: Vec<f64> = (0..n_ctrl * dim)
            .map(|_| r.uniform(-100.0, 100.0))
            .collect();
        let w: Vec<f64> = (0..n_ctrl).map(|_| r.uniform(0.2, 5.0)).collect();
        let n_int = n_ctrl - p - 1;
        let mut interior = Vec::new();
        while interior.len() < n_int {
            let v = r.uniform(0.02, 0.98);
            let room = (n_int - interior.len()).min(p);
            let mult = if r.unit() < 0.3 { r.int(1, room) } else { 1 };
            for _ in 0..mult {
                interior.push(v);
            }
        }
        interior.sort_by(f64::total_cmp);
        let a = r.uniform(-5.0, 5.0);
        let len = r.uniform(0.5, 10.0);
        let mut knots = vec![a; p + 1];
        knots.extend(interior.iter().map(|t| a + len * t));
        knots.extend(core::iter::repeat_n(a + len, p + 1));
        Def {
            p,
            dim,
            ctrl,
            w,
            knots,
        }
    }

    /// Independent reference: de Boor's algorithm on homogeneous points (NURBS Book A3.1-style
    /// triangle), span found by linear search with the same right-continuous convention.
    fn de_boor(p: usize, knots: &[f64], pw: &[Vec<f64>], u: f64) -> Vec<f64> {
        let n = pw.len() - 1;
        let mut k = p;
        if u >= knots[n + 1] {
            k = n;
        } else {
            for i in p..=n {
                if knots[i] <= u && u < knots[i + 1] {
                    k = i;
                }
            }
        }
        let mut d: Vec<Vec<f64>> = (0..=p).map(|j| pw[j + k - p].clone()).collect();
        for r in 1..=p {
            for j in (r..=p).rev() {
                let i = j + k - p;
                let den = knots[i + p + 1 - r] - knots[i];
                let alpha = (u - knots[i]) / den;
                let prev = d[j - 1].clone();
                for (x, y) in d[j].iter_mut().zip(prev) {
                    *x = (1.0 - alpha) * y + alpha * *x;
                }
            }
        }
        d[p].clone()
    }

    /// Control points and knots of the derivative B-spline (NURBS Book eq 3.7-3.8):
    /// Q_i = p (P_{i+1} - P_i) / (u_{i+p+1} - u_{i+1}), knots U[1..m-1], degree p-1.
    fn derivative_spline(p: usize, knots: &[f64], pw: &[Vec<f64>]) -> (Vec<f64>, Vec<Vec<f64>>) {
        let q: Vec<Vec<f64>> = (0..pw.len() - 1)
            .map(|i| {
                let den = knots[i + p + 1] - knots[i + 1];
                pw[i + 1]
                    .iter()
                    .zip(&pw[i])
                    .map(|(a, b)| p as f64 * (a - b) / den)
                    .collect()
            })
            .collect();
        (knots[1..knots.len() - 1].to_vec(), q)
    }

    fn homogeneous(d: &Def) -> Vec<Vec<f64>> {
        d.ctrl
            .chunks(d.dim)
            .zip(&d.w)
            .map(|(c, &w)| {
                let mut v: Vec<f64> = c.iter().map(|x| x * w).collect();
                v.push(w);
                v
            })
            .collect()
    }

    /// Reference (C, C', C'') from de Boor on Cw, Cw' and Cw'' and the quotient rule.
    fn reference(d: &Def, u: f64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let pw0 = homogeneous(d);
        let a0 = de_boor(d.p, &d.knots, &pw0, u);
        let (k1, pw1) = derivative_spline(d.p, &d.knots, &pw0);
        let a1 = if d.p >= 1 {
            de_boor(d.p - 1, &k1, &pw1, u)
        } else {
            vec![0.0; d.dim + 1]
        };
        let a2 = if d.p >= 2 {
            let (k2, pw2) = derivative_spline(d.p - 1, &k1, &pw1);
            de_boor(d.p - 2, &k2, &pw2, u)
        } else {
            vec![0.0; d.dim + 1]
        };
        let (w0, w1, w2) = (a0[d.dim], a1[d.dim], a2[d.dim]);
        let c: Vec<f64> = (0..d.dim).map(|i| a0[i] / w0).collect();
        let c1: Vec<f64> = (0..d.dim).map(|i| (a1[i] - w1 * c[i]) / w0).collect();
        let c2: Vec<f64> = (0..d.dim)
            .map(|i| (a2[i] - 2.0 * w1 * c1[i] - w2 * c[i]) / w0)
            .collect();
        (c, c1, c2)
    }

    fn max_rel(a: &Point, b: &[f64], scale: f64) -> f64 {
        b.iter()
            .enumerate()
            .map(|(i, &x)| (a[i] - x).abs() / scale)
            .fold(0.0, f64::max)
    }

    #[test]
    fn random_curves_match_de_boor_and_finite_differences() {
        let mut r = Rng::new(0x5EED_2008);
        let mut worst = [0.0f64; 3];
        let mut worst_fd = [0.0f64; 2];
        let mut n_fd = 0;
        for _ in 0..400 {
            let d = random_def(&mut r);
            let c = Nurbs::new(d.p, d.dim, &d.ctrl, &d.w, &d.knots).expect("valid random curve");
            let (ua, ub) = c.domain();
            assert_eq!((ua, ub), (d.knots[0], d.knots[d.knots.len() - 1]));
            // random parameters, every knot, and the ends
            let mut us: Vec<f64> = (0..40).map(|_| r.uniform(ua, ub)).collect();
            us.extend(d.knots.iter().copied());
            for &u in &us {
                let (p0, p1, p2) = c.eval(u).unwrap();
                let (r0, r1, r2) = reference(&d, u);
                let s0 = 100.0;
                let s1 = r1.iter().fold(1.0f64, |m, x| m.max(x.abs()));
                let s2 = r2.iter().fold(1.0f64, |m, x| m.max(x.abs()));
                worst[0] = worst[0].max(max_rel(&p0, &r0, s0));
                worst[1] = worst[1].max(max_rel(&p1, &r1, s1));
                worst[2] = worst[2].max(max_rel(&p2, &r2, s2));
                for i in d.dim..MAX_DIM {
                    assert_eq!((p0[i], p1[i], p2[i]), (0.0, 0.0, 0.0));
                }
                // Fourth-order central differences inside the span: h = 1/64 of the distance
                // to the nearest knot (at most 1e-3 of the domain), so [u-2h, u+2h] holds no knot.
                let dk = d
                    .knots
                    .iter()
                    .fold(f64::INFINITY, |m, k| m.min((k - u).abs()));
                let h = (1e-3 * (ub - ua)).min(dk / 64.0);
                if dk > 1e-4 * (ub - ua) {
                    n_fd += 1;
                    let e = |x: f64| c.eval(x).unwrap();
                    let (p2p, d2p, _) = e(u + 2.0 * h);
                    let (p1p, d1p, _) = e(u + h);
                    let (p1m, d1m, _) = e(u - h);
                    let (p2m, d2m, _) = e(u - 2.0 * h);
                    let fd1 = (-p2p + p1p * 8.0 - p1m * 8.0 + p2m) / (12.0 * h);
                    let fd2 = (-d2p + d1p * 8.0 - d1m * 8.0 + d2m) / (12.0 * h);
                    worst_fd[0] = worst_fd[0].max((fd1 - p1).amax() / s1);
                    worst_fd[1] = worst_fd[1].max((fd2 - p2).amax() / s2);
                }
            }
        }
        println!(
            "de Boor: worst rel err C {:.2e}, C' {:.2e}, C'' {:.2e}",
            worst[0], worst[1], worst[2]
        );
        println!(
            "finite differences ({n_fd} pts): worst rel err C' {:.2e}, C'' {:.2e}",
            worst_fd[0], worst_fd[1]
        );
        // Tolerances: same-maths references in f64 -> 1e-9 relative to the magnitude.
        assert!(worst[0] < 1e-11, "point {}", worst[0]);
        assert!(worst[1] < 1e-9, "first derivative {}", worst[1]);
        assert!(worst[2] < 1e-8, "second derivative {}", worst[2]);
        // O(h^4) truncation (h ≤ span/128, but rational factors with weight ratios up to 25
        // amplify the fifth derivative) plus rounding ~ eps·|C|/h: an independent sanity
        // check of the derivative formulas, the de Boor comparison above is the tight one.
        assert!(worst_fd[0] < 1e-5, "fd first {}", worst_fd[0]);
        assert!(worst_fd[1] < 1e-4, "fd second {}", worst_fd[1]);
        assert!(n_fd > 10_000, "{n_fd}");
    }

    /// Splitting at knots (knot insertion) is exact: every piece evaluates like the original
    /// (checked against de Boor on the original, which has too many points for a `Nurbs`),
    /// the pieces cover the domain in order, respect the size limit, and share their ends.
    #[test]
    fn split_curve_is_exact() {
        let mut r = Rng::new(0x5B17_0001);
        for case in 0..40 {
            let p = 1 + case % 5;
            let dim = r.int(2, 4);
            let n_ctrl = if case % 4 == 0 {
                r.int(2000, 3000)
            } else {
                r.int(p + 1, 400)
            };
            let max_ctrl = if case % 4 == 0 {
                [100, MAX_CTRL][case % 8 / 4]
            } else {
                [p + 1, p + 2, 17, 100, MAX_CTRL][case % 5]
            };
            let ctrl: Vec<f64> = (0..n_ctrl * dim).map(|_| r.uniform(-1e4, 1e4)).collect();
            let w: Vec<f64> = (0..n_ctrl).map(|_| r.uniform(0.3, 3.0)).collect();
            let n_int = n_ctrl - p - 1;
            let mut interior: Vec<f64> = Vec::new();
            while interior.len() < n_int {
                let v = r.uniform(0.01, 0.99);
                let mult = if r.unit() < 0.2 {
                    r.int(1, (n_int - interior.len()).min(p))
                } else {
                    1
                };
                interior.extend(core::iter::repeat_n(v, mult));
            }
            interior.sort_by(f64::total_cmp);
            let mut knots = vec![0.0; p + 1];
            knots.extend(interior);
            knots.extend([1.0].repeat(p + 1));
            let pieces = split_curve(p, dim, &ctrl, &w, &knots, max_ctrl).unwrap();
            let d = Def {
                p,
                dim,
                ctrl: ctrl.clone(),
                w: w.clone(),
                knots: knots.clone(),
            };
            let mut at = 0.0;
            for (k, c) in pieces.iter().enumerate() {
                assert!(
                    c.n_ctrl() <= max_ctrl.max(p + 1),
                    "piece {k}: {}",
                    c.n_ctrl()
                );
                let (a, b) = c.domain();
                assert_eq!(a, at, "pieces in order");
                at = b;
                if k + 1 < pieces.len() {
                    let next = &pieces[k + 1];
                    assert_eq!(
                        c.control_point(c.n_ctrl() - 1),
                        next.control_point(0),
                        "joint {k}: not the same control point"
                    );
                    assert_eq!(c.weight(c.n_ctrl() - 1), next.weight(0));
                    let gap = (c.point(b).unwrap() - next.point(b).unwrap()).amax();
                    assert!(gap <= 1e-9, "joint {k}: {gap}");
                }
                for i in 0..=6 {
                    let u = if i == 6 {
                        b
                    } else {
                        a + (b - a) * i as f64 / 6.0
                    };
                    let (c0, c1, _) = c.eval(u).unwrap();
                    let (r0, r1, _) = reference(&d, u);
                    let s1 = r1.iter().fold(1.0f64, |m, x| m.max(x.abs()));
                    assert!(
                        max_rel(&c0, &r0, 1e4) < 1e-11,
                        "case {case} piece {k} u {u}"
                    );
                    // derivatives agree inside the piece (at its ends they are one-sided)
                    if i > 0 && i < 6 {
                        assert!(max_rel(&c1, &r1, s1) < 1e-8, "case {case} piece {k} u {u}");
                    }
                }
            }
            assert_eq!(at, 1.0);
            if n_ctrl <= max_ctrl {
                assert_eq!(pieces.len(), 1);
            }
        }
        // the same checks as Nurbs::new, except the point count
        assert_eq!(
            split_curve(
                3,
                2,
                &[0.0; 8],
                &[1.0; 4],
                &[0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 2.0],
                10
            )
            .unwrap_err(),
            NurbsError::NotClamped
        );
        assert_eq!(
            split_curve(
                1,
                2,
                &[0.0, 0.0, 1.0, f64::NAN],
                &[1.0; 2],
                &[0.0, 0.0, 1.0, 1.0],
                10
            )
            .unwrap_err(),
            NurbsError::NonFiniteControlPoint { index: 1 }
        );
    }

    #[test]
    fn full_circle_is_exact() {
        for &(cx, cy, rad) in &[
            (0.0, 0.0, 1.0),
            (0.3, -0.7, 1.0),
            (1234.5, -987.0, 10_000.0),
        ] {
            let c = Nurbs::circle([cx, cy], rad).unwrap();
            let centre = Point::from_fn(|i, _| [cx, cy, 0., 0., 0., 0., 0., 0.][i]);
            let mut worst = 0.0f64;
            let mut worst_tan = 0.0f64;
            for i in 0..=10_000 {
                let u = i as f64 / 10_000.0;
                let (p, d1, _) = c.eval(u).unwrap();
                let rel = p - centre;
                worst = worst.max((rel.norm() - rad).abs() / rad);
                worst_tan = worst_tan.max(rel.dot(&d1).abs() / (rad * d1.norm()));
            }
            println!(
                "circle r={rad}: worst relative radius error {worst:.2e}, tangent {worst_tan:.2e}"
            );
            assert!(worst <= 1e-12, "radius error {worst}");
            assert!(worst_tan <= 1e-12);
            let (p0, _, _) = c.eval(0.0).unwrap();
            assert!((p0[0] - (cx + rad)).abs() < 1e-9 && (p0[1] - cy).abs() < 1e-9);
        }
    }

    #[test]
    fn clamped_uniform_knots_shape() {
        let k = clamped_uniform_knots(7, 3).unwrap();
        assert_eq!(
            k,
            vec![0.0, 0.0, 0.0, 0.0, 0.25, 0.5, 0.75, 1.0, 1.0, 1.0, 1.0]
        );
        let k = clamped_uniform_knots(2, 1).unwrap();
        assert_eq!(k, vec![0.0, 0.0, 1.0, 1.0]);
        assert_eq!(
            clamped_uniform_knots(3, 3),
            Err(NurbsError::TooFewControlPoints { n_ctrl: 3, min: 4 })
        );
        assert_eq!(
            clamped_uniform_knots(5, 0),
            Err(NurbsError::BadDegree { degree: 0 })
        );
        assert!(matches!(
            clamped_uniform_knots(MAX_CTRL + 1, 2),
            Err(NurbsError::TooManyControlPoints { .. })
        ));
        // a curve built on it validates
        let ctrl: Vec<f64> = (0..14).map(|i| i as f64).collect();
        let k = clamped_uniform_knots(7, 3).unwrap();
        assert!(Nurbs::new(3, 2, &ctrl, &[1.0; 7], &k).is_ok());
    }

    #[test]
    fn every_validation_error() {
        use NurbsError::*;
        let ctrl4 = [0.0, 0.0, 1.0, 1.0, 2.0, 0.0, 3.0, 1.0];
        let w4 = [1.0; 4];
        let k4 = [0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0]; // p = 2, 4 points
        assert!(Nurbs::new(2, 2, &ctrl4, &w4, &k4).is_ok());
        assert_eq!(
            Nurbs::new(0, 2, &ctrl4, &w4, &k4).unwrap_err(),
            BadDegree { degree: 0 }
        );
        assert_eq!(
            Nurbs::new(6, 2, &ctrl4, &w4, &k4).unwrap_err(),
            BadDegree { degree: 6 }
        );
        assert_eq!(
            Nurbs::new(2, 1, &ctrl4, &w4, &k4).unwrap_err(),
            BadDimension { dim: 1 }
        );
        assert_eq!(
            Nurbs::new(2, 9, &ctrl4, &w4, &k4).unwrap_err(),
            BadDimension { dim: 9 }
        );
        assert_eq!(
            Nurbs::new(2, 3, &ctrl4, &w4, &k4).unwrap_err(),
            ControlDataLength { len: 8, dim: 3 }
        );
        assert_eq!(
            Nurbs::new(2, 2, &[], &[], &k4).unwrap_err(),
            ControlDataLength { len: 0, dim: 2 }
        );
        assert_eq!(
            Nurbs::new(3, 2, &ctrl4[..6], &w4[..3], &k4).unwrap_err(),
            TooFewControlPoints { n_ctrl: 3, min: 4 }
        );
        let big = vec![0.0; 2 * (MAX_CTRL + 1)];
        assert_eq!(
            Nurbs::new(1, 2, &big, &[1.0; MAX_CTRL + 1], &[]).unwrap_err(),
            TooManyControlPoints {
                n_ctrl: MAX_CTRL + 1,
                max: MAX_CTRL
            }
        );
        assert_eq!(
            Nurbs::new(2, 2, &ctrl4, &w4[..3], &k4).unwrap_err(),
            WeightCountMismatch {
                weights: 3,
                n_ctrl: 4
            }
        );
        assert_eq!(
            Nurbs::new(2, 2, &ctrl4, &w4, &k4[..6]).unwrap_err(),
            KnotCountMismatch {
                knots: 6,
                expected: 7
            }
        );
        let mut k = k4;
        k[3] = f64::NAN;
        assert_eq!(
            Nurbs::new(2, 2, &ctrl4, &w4, &k).unwrap_err(),
            NonFiniteKnot { index: 3 }
        );
        k[3] = f64::INFINITY;
        assert_eq!(
            Nurbs::new(2, 2, &ctrl4, &w4, &k).unwrap_err(),
            NonFiniteKnot { index: 3 }
        );
        let k = [0.0, 0.0, 0.0, 1.5, 1.0, 1.0, 1.0];
        assert_eq!(
            Nurbs::new(2, 2, &ctrl4, &w4, &k).unwrap_err(),
            KnotsDecreasing { index: 4 }
        );
        // interior multiplicity p+1 = 3 (p = 2, 6 points -> 9 knots)
        let ctrl6 = [0.0; 12];
        let k = [0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0];
        assert_eq!(
            Nurbs::new(2, 2, &ctrl6, &[1.0; 6], &k).unwrap_err(),
            KnotMultiplicity {
                index: 3,
                multiplicity: 3
            }
        );
        // interior multiplicity p = 2 is fine
        let k = [0.0, 0.0, 0.0, 0.3, 0.5, 0.5, 1.0, 1.0, 1.0];
        assert!(Nurbs::new(2, 2, &ctrl6, &[1.0; 6], &k).is_ok());
        // end run longer than p+1
        let k = [0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0];
        assert_eq!(
            Nurbs::new(2, 2, &ctrl6, &[1.0; 6], &k).unwrap_err(),
            KnotMultiplicity {
                index: 0,
                multiplicity: 4
            }
        );
        // not clamped (uniform)
        let k = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        assert_eq!(Nurbs::new(2, 2, &ctrl4, &w4, &k).unwrap_err(), NotClamped);
        let k = [0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 2.0];
        assert_eq!(Nurbs::new(2, 2, &ctrl4, &w4, &k).unwrap_err(), NotClamped);
        assert_eq!(
            Nurbs::new(2, 2, &ctrl4, &w4, &[1.0; 7]).unwrap_err(),
            EmptyDomain
        );
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let w = [1.0, 1.0, bad, 1.0];
            assert_eq!(
                Nurbs::new(2, 2, &ctrl4, &w, &k4).unwrap_err(),
                BadWeight { index: 2 }
            );
        }
        // weights spread wider than MAX_WEIGHT_RATIO: the heavier one is named
        let w = [0.5, 1.0, 0.5 * MAX_WEIGHT_RATIO, 1.0];
        assert!(Nurbs::new(2, 2, &ctrl4, &w, &k4).is_ok());
        let w = [0.5, 1.0, 0.5 * MAX_WEIGHT_RATIO * 1.001, 1.0];
        assert_eq!(
            Nurbs::new(2, 2, &ctrl4, &w, &k4).unwrap_err(),
            BadWeight { index: 2 }
        );
        let w = [1.0, 1.0, 1.0, 1e-5];
        assert_eq!(
            Nurbs::new(2, 2, &ctrl4, &w, &k4).unwrap_err(),
            BadWeight { index: 0 }
        );
        let mut c = ctrl4;
        c[3] = f64::NAN;
        assert_eq!(
            Nurbs::new(2, 2, &c, &w4, &k4).unwrap_err(),
            NonFiniteControlPoint { index: 1 }
        );
        // finite point whose weighted value overflows
        let mut c = ctrl4;
        c[4] = f64::MAX;
        let w = [1.0, 1.0, 4.0, 1.0];
        assert_eq!(
            Nurbs::new(2, 2, &c, &w, &k4).unwrap_err(),
            NonFiniteControlPoint { index: 2 }
        );
        let curve = Nurbs::new(2, 2, &ctrl4, &w4, &k4).unwrap();
        assert_eq!(curve.eval(f64::NAN).unwrap_err(), NonFiniteParameter);
        assert_eq!(
            curve.eval(f64::NEG_INFINITY).unwrap_err(),
            NonFiniteParameter
        );
        assert_eq!(curve.eval(1.0 + 1e-12).unwrap_err(), ParameterOutOfRange);
        assert_eq!(curve.eval(-1e-12).unwrap_err(), ParameterOutOfRange);
        let (a, _, _) = curve.eval_clamped(f64::NAN);
        assert_eq!(a[0], 0.0);
        for bad in [0.0, -1.0, f64::NAN] {
            assert_eq!(Nurbs::circle([0.0, 0.0], bad).unwrap_err(), BadCircle);
        }
        assert_eq!(Nurbs::circle([f64::NAN, 0.0], 1.0).unwrap_err(), BadCircle);
        // accessors
        assert_eq!(curve.weight(4), None);
        assert_eq!(curve.control_point(9), None);
        assert_eq!(curve.control_point(1).unwrap()[1], 1.0);
        // every error has a message
        for e in [BadDegree { degree: 0 }, NotClamped, EmptyDomain, BadCircle] {
            assert!(!e.to_string().is_empty());
        }
    }

    #[test]
    fn degree_one_rational_and_span_convention() {
        let ctrl = [0.0, 0.0, 1.0, 0.0, 1.0, 1.0];
        let c = Nurbs::new(1, 2, &ctrl, &[1.0, 2.0, 1.0], &[0.0, 0.0, 0.5, 1.0, 1.0]).unwrap();
        let (p, d1, d2) = c.eval(1.0).unwrap();
        assert!((p[0] - 1.0).abs() < 1e-15 && (p[1] - 1.0).abs() < 1e-15);
        assert!(d1[1] > 0.0);
        assert!(d2[0].is_finite());
        assert_eq!(c.find_span(1.0), 2);
        assert_eq!(c.find_span(0.5), 2);
        assert_eq!(c.find_span(0.0), 1);
    }
}
