//! Motion generation through four and five poses (issue 35, item 3):
//! Burmester's circle-point and centre-point curves, and Burmester's points.
//!
//! **Poses and dyads** as in [`super::motion`]: pose j is (x_j, y_j, θ_j); a
//! circle point a = (u, v) of the coupler frame is at q_j = P_j + R(θ_j)·a; a
//! dyad is a circle point with a centre point C (a ground pivot) such that
//! |q_j − C| is the same for every pose.
//!
//! **Four poses: the curves.** In Erdman & Sandor's standard form (*Mechanism
//! Design*, vol. 1, §8) a dyad is the link W (C → the circle point in pose 1)
//! turning by β_j and the coupler vector Z (circle point → pose point) turning
//! by the pose's rotation α_j = θ_j − θ_1:
//!
//! ```text
//! W (e^{iβ_j} − 1) + Z (e^{iα_j} − 1) = δ_j = P_j − P_1,   j = 2, 3, 4,
//! ```
//!
//! three complex equations in the two unknowns W, Z. They have a solution iff
//! the 3 × 3 determinant of [e^{iβ_j} − 1, e^{iα_j} − 1, δ_j] vanishes: with
//! Δ_j the cofactors of the first column (known from the poses),
//!
//! ```text
//! Δ_2 e^{iβ_2} + Δ_3 e^{iβ_3} + Δ_4 e^{iβ_4} = Δ_2 + Δ_3 + Δ_4,
//! ```
//!
//! a closed loop of four vectors of fixed lengths (the *compatibility
//! linkage*). One rotation β_p is the curves' parameter (p is the pose whose
//! |Δ_p| is smallest, so that the other two are well defined; normally p = 2);
//! for each β_p the other two follow in closed form from the intersection of two
//! circles — two solutions, the branch σ = ±1 — and W, Z from the two
//! best-conditioned of the three linear equations. Sweeping β_p over a turn
//! traces every real point of both curves: the circle point a = R(−θ_1)(−Z)
//! and the centre point C = P_1 − Z − W. The curves are cubics: the circle
//! point's condition, subtracting pose 1 from the others, is
//!
//! ```text
//! 2 (q_j − q_1)·C = |q_j|² − |q_1|²,   j = 2, 3, 4,
//! ```
//!
//! linear in C with every entry linear in a (|a|² cancels), consistent iff a
//! 3 × 3 determinant — a cubic in a — vanishes ([`circle_point_det`]). Two
//! points of every curve are at infinity (β_j = α_j for all j: the circle
//! point at infinity, a slider on the coupler; β_j → 0: the centre at
//! infinity, a slider on the ground): the polyline breaks there.
//!
//! **Five poses: Burmester's points.** A circle point of five poses lies on the
//! circle-point curve of poses {1, 2, 3, 4} and on that of {1, 2, 3, 5}. Two
//! cubics meet in nine points; the three poles P12, P13, P23 and the two
//! circular points at infinity lie on both, which leaves at most four:
//! Burmester's points, real in pairs (0, 2 or 4 of them). They are found by
//! tracing the first curve (dense in β_p, both branches, across the joins of
//! the branches at the compatibility linkage's folds) and bracketing every sign
//! change of the second curve's determinant, refined by bisection, then
//! polished by Newton's method on the five equations |q_j − C|² = ρ (unknowns
//! a, C, ρ); the same is done with the roles of poses 4 and 5 swapped, and the
//! two lists merged. No root search from guesses: every real intersection with
//! a sign change is bracketed.
//!
//! **Near-degenerate cases (the rule).** A root is kept only if Newton's
//! method converges and every pose's distance from the centre equals the
//! radius to 1e-9 of (radius + the poses' spread); roots at the poles (two of
//! the circle point's positions closer than 1e-7 of the spread), at infinity
//! (radius or circle point beyond 1e6 spreads) and where the sign change was
//! the curve passing through infinity fail that test and are dropped. Roots
//! closer than 1e-5 of (the spread + their distance from pose 1's point) are
//! one point (a double root, or one root found twice where it is
//! ill-conditioned, as when two poses nearly coincide), counted once. A
//! double root without a sign change (the two cubics tangent) is not
//! bracketed: it is the boundary between two and zero real pairs, where a
//! perturbation of the poses below their printed precision decides. If the
//! merged count is odd (a root lost to that), the trace is repeated 16 times
//! denser; an odd count after that is returned as found, flagged.

use std::f64::consts::PI;

use nalgebra::{Complex, Matrix5, Vector5};

use super::motion::{check_poses, pose_point, MotionError, Pose};

type C64 = Complex<f64>;

/// Points farther than this many spreads of the poses are dropped from the
/// curves' polylines (they are on the way to a point at infinity).
pub const CURVE_FAR: f64 = 1e4;

/// Default samples of the curves' parameter per branch.
pub const CURVE_SAMPLES: usize = 2048;

/// One point of the four-pose curves: the dyad with crank rotation `beta`
/// [rad] (from pose 1 to pose `parameter_pose`) on branch `sigma` (±1), its
/// circle point (coupler frame, [m]) and centre point (fixed frame, [m]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvePoint {
    pub beta: f64,
    pub sigma: f64,
    pub circle: [f64; 2],
    pub centre: [f64; 2],
}

/// Burmester's curves of four poses, as polyline branches.
#[derive(Debug, Clone, PartialEq)]
pub struct BurmesterCurves {
    /// The pose (index from 1: 2, 3 or 4) whose crank rotation parametrises them.
    pub parameter_pose: usize,
    /// Polylines, each a run of one branch σ in increasing β (a run through
    /// β = ±π continues across it).
    pub branches: Vec<Vec<CurvePoint>>,
}

/// A Burmester point of five poses: a dyad through all five.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BurmesterPoint {
    /// Circle point (coupler frame) [m].
    pub circle: [f64; 2],
    /// Centre point [m].
    pub centre: [f64; 2],
    /// The radius |A − A0| [m].
    pub radius: f64,
    /// The largest | |q_j − C| − radius | over the five poses [m].
    pub residual: f64,
}

/// Burmester's points and whether their count is even, as it must be.
#[derive(Debug, Clone, PartialEq)]
pub struct BurmesterPoints {
    pub points: Vec<BurmesterPoint>,
    pub parity_ok: bool,
}

/// Poses normalised: relative to pose 1's point, divided by the spread `scale`.
struct Normal {
    p1: [f64; 2],
    scale: f64,
    /// (P_j − P_1)/scale and θ_j, j = 1..n.
    pts: Vec<[f64; 2]>,
    th: Vec<f64>,
}

impl Normal {
    fn new(poses: &[Pose]) -> Self {
        let p1 = [poses[0][0], poses[0][1]];
        let spread = poses
            .iter()
            .map(|p| (p[0] - p1[0]).hypot(p[1] - p1[1]))
            .fold(0.0f64, f64::max);
        let scale = if spread > 0.0 { spread } else { 1.0 };
        Normal {
            p1,
            scale,
            pts: poses
                .iter()
                .map(|p| [(p[0] - p1[0]) / scale, (p[1] - p1[1]) / scale])
                .collect(),
            th: poses.iter().map(|p| p[2]).collect(),
        }
    }

    /// Circle point (normalised coupler frame) in pose j (normalised world).
    fn q(&self, j: usize, a: [f64; 2]) -> [f64; 2] {
        pose_point([self.pts[j][0], self.pts[j][1], self.th[j]], a)
    }

    fn to_world(&self, c: [f64; 2]) -> [f64; 2] {
        [
            self.p1[0] + self.scale * c[0],
            self.p1[1] + self.scale * c[1],
        ]
    }
}

fn check_distinct(poses: &[Pose]) -> Result<(), MotionError> {
    let size = check_poses(poses)?;
    let n = poses.len();
    for i in 0..n {
        for j in i + 1..n {
            let (a, b) = (poses[i], poses[j]);
            let place = (a[0] - b[0]).hypot(a[1] - b[1]) <= 1e-12 * (1.0 + size);
            let turn = (a[2] - b[2] + PI).rem_euclid(2.0 * PI) - PI;
            if place && turn.abs() <= 1e-11 {
                return Err(MotionError::Coincident { i, j, n });
            }
        }
    }
    Ok(())
}

/// The circle-point condition of four poses at circle point `uv` (coupler
/// frame, [m]): the 3 × 3 determinant of the rows [2(q_j − q_1), |q_j|² − |q_1|²],
/// j = 2, 3, 4, in the poses' normalised frame (module docs). Zero on the
/// circle-point curve; a cubic in (u, v).
pub fn circle_point_det(poses: &[Pose; 4], uv: [f64; 2]) -> Result<f64, MotionError> {
    check_poses(poses)?;
    let nm = Normal::new(poses);
    Ok(det_norm(
        &nm,
        [0, 1, 2, 3],
        [uv[0] / nm.scale, uv[1] / nm.scale],
    ))
}

fn det_norm(nm: &Normal, idx: [usize; 4], a: [f64; 2]) -> f64 {
    let q1 = nm.q(idx[0], a);
    let n1 = q1[0] * q1[0] + q1[1] * q1[1];
    let rows: Vec<[f64; 3]> = idx[1..]
        .iter()
        .map(|&j| {
            let q = nm.q(j, a);
            [
                2.0 * (q[0] - q1[0]),
                2.0 * (q[1] - q1[1]),
                q[0] * q[0] + q[1] * q[1] - n1,
            ]
        })
        .collect();
    let (r0, r1, r2) = (rows[0], rows[1], rows[2]);
    r0[0] * (r1[1] * r2[2] - r1[2] * r2[1]) - r0[1] * (r1[0] * r2[2] - r1[2] * r2[0])
        + r0[2] * (r1[0] * r2[1] - r1[1] * r2[0])
}

/// The compatibility linkage of four poses (module docs), normalised.
struct Compat {
    /// e^{iα_j} − 1 and δ_j, j = 2, 3, 4 (indices 0..3).
    ea: [C64; 3],
    delta: [C64; 3],
    /// Cofactors Δ_2, Δ_3, Δ_4.
    cof: [C64; 3],
    /// The parameter's index (0..3 for poses 2..4) and the other two.
    p: usize,
    others: [usize; 2],
    th1: f64,
}

impl Compat {
    fn new(nm: &Normal, idx: [usize; 4]) -> Option<Self> {
        let i1 = idx[0];
        let ea: [C64; 3] =
            [1, 2, 3].map(|k| C64::from_polar(1.0, nm.th[idx[k]] - nm.th[i1]) - C64::new(1.0, 0.0));
        let delta: [C64; 3] = [1, 2, 3].map(|k| {
            let (a, b) = (nm.pts[idx[k]], nm.pts[i1]);
            C64::new(a[0] - b[0], a[1] - b[1])
        });
        let m = |r: usize, s: usize| ea[r] * delta[s] - ea[s] * delta[r];
        let cof = [m(1, 2), -m(0, 2), m(0, 1)];
        let mags = cof.map(|c| c.norm());
        let big = mags.iter().fold(0.0f64, |a, &b| a.max(b));
        if big.is_nan() || big <= 1e-300 {
            return None;
        }
        let p = (0..3)
            .min_by(|&x, &y| mags[x].total_cmp(&mags[y]))
            .unwrap_or(0);
        let others = match p {
            0 => [1, 2],
            1 => [0, 2],
            _ => [0, 1],
        };
        if mags[others[0]] <= 1e-12 * big || mags[others[1]] <= 1e-12 * big {
            return None;
        }
        Some(Compat {
            ea,
            delta,
            cof,
            p,
            others,
            th1: nm.th[i1],
        })
    }

    /// The crank rotations (β_2, β_3, β_4) at parameter `beta` on branch
    /// `sigma`, or None where the compatibility linkage does not assemble.
    fn betas(&self, beta: f64, sigma: f64) -> Option<[f64; 3]> {
        let [q, r] = self.others;
        let total = self.cof[0] + self.cof[1] + self.cof[2];
        let k = total - self.cof[self.p] * C64::from_polar(1.0, beta);
        let (rq, rr, kk) = (self.cof[q].norm(), self.cof[r].norm(), k.norm());
        if kk <= 1e-300 {
            return None;
        }
        let mut c = (rq * rq + kk * kk - rr * rr) / (2.0 * rq * kk);
        if c.abs() > 1.0 {
            if c.abs() <= 1.0 + 1e-12 {
                c = c.signum();
            } else {
                return None;
            }
        }
        let phi_q = k.arg() + sigma * c.acos();
        let vq = C64::from_polar(rq, phi_q);
        let vr = k - vq;
        let mut b = [0.0; 3];
        b[self.p] = beta;
        b[q] = phi_q - self.cof[q].arg();
        b[r] = vr.arg() - self.cof[r].arg();
        Some(b)
    }

    /// W, Z (normalised) for crank rotations `b`, from the two best-conditioned
    /// of the three equations.
    fn wz(&self, b: [f64; 3]) -> Option<(C64, C64)> {
        let eb = b.map(|x| C64::from_polar(1.0, x) - C64::new(1.0, 0.0));
        let mut best: Option<(f64, usize, usize)> = None;
        for (r, s) in [(0, 1), (0, 2), (1, 2)] {
            let d = (eb[r] * self.ea[s] - eb[s] * self.ea[r]).norm();
            if best.is_none_or(|(m, _, _)| d > m) {
                best = Some((d, r, s));
            }
        }
        let (_, r, s) = best?;
        let det = eb[r] * self.ea[s] - eb[s] * self.ea[r];
        if det.norm() <= 1e-300 {
            return None;
        }
        let w = (self.delta[r] * self.ea[s] - self.delta[s] * self.ea[r]) / det;
        let z = (eb[r] * self.delta[s] - eb[s] * self.delta[r]) / det;
        (w.re.is_finite() && w.im.is_finite() && z.re.is_finite() && z.im.is_finite())
            .then_some((w, z))
    }

    /// The dyad (circle point in the normalised coupler frame, centre point
    /// normalised) at parameter `beta`, branch `sigma`.
    fn dyad(&self, beta: f64, sigma: f64) -> Option<([f64; 2], [f64; 2])> {
        let b = self.betas(beta, sigma)?;
        let (w, z) = self.wz(b)?;
        // Pose 1's point is the origin of the normalised frame (idx[0] = 0 is
        // required of callers that want world points; see `curve_norm`).
        let m1 = -z;
        let c = m1 - w;
        let a = m1 * C64::from_polar(1.0, -self.th1);
        Some(([a.re, a.im], [c.re, c.im]))
    }
}

/// A dyad as (circle point (coupler frame), centre point) [m].
pub type DyadPoints = ([f64; 2], [f64; 2]);

/// One sample of a branch: (β, circle point, centre point), normalised.
type Sample = (f64, [f64; 2], [f64; 2]);

/// Refinement of the traced curves: neighbours closer than this (normalised:
/// spreads of the poses, circle point plus centre point; relative beyond one
/// spread from pose 1) ...
const REFINE_STEP: f64 = 5e-3;
/// ... within this many spreads, at most 2^REFINE_DEPTH points per interval.
const REFINE_WITHIN: f64 = 100.0;
const REFINE_DEPTH: u32 = 24;

impl Compat {
    fn sample(&self, beta: f64, sigma: f64) -> Option<Sample> {
        self.dyad(beta, sigma).map(|(a, c)| (beta, a, c))
    }

    /// Branch σ traced: for each of `n` uniform values β_k over a turn, the
    /// sample there (None where the compatibility linkage does not assemble)
    /// and, if the next is a sample too, the points bisected in between until
    /// neighbours are closer than [`REFINE_STEP`] (the curve races through a
    /// small range of β where a crank barely turns).
    fn trace(&self, sigma: f64, n: usize) -> Vec<(Option<Sample>, Vec<Sample>)> {
        let h = 2.0 * PI / n as f64;
        (0..n)
            .map(|k| {
                let b0 = -PI + h * k as f64;
                let s0 = self.sample(b0, sigma);
                let mut mid = Vec::new();
                if let (Some(s0), Some(s1)) = (s0, self.sample(b0 + h, sigma)) {
                    self.refine(sigma, s0, s1, REFINE_DEPTH, &mut mid);
                }
                (s0, mid)
            })
            .collect()
    }

    fn refine(&self, sigma: f64, s0: Sample, s1: Sample, depth: u32, out: &mut Vec<Sample>) {
        let mut pts = Vec::new();
        refine_by(
            &|b| self.sample(b, sigma),
            (s0.0, s0),
            (s1.0, s1),
            depth,
            &mut pts,
        );
        out.extend(pts.into_iter().map(|(_, x)| x));
    }

    /// The fold of the compatibility linkage between `b_ok` (the branches
    /// assemble) and `b_bad` (they do not), by bisection.
    fn fold(&self, b_ok: f64, b_bad: f64) -> f64 {
        let (mut lo, mut hi) = (b_ok, b_bad);
        for _ in 0..80 {
            let mid = 0.5 * (lo + hi);
            if self.sample(mid, 1.0).is_some() {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    }

    /// The curve through a fold at `fold`, from branch σ = −1 at `b_ok` to
    /// σ = +1 at `b_ok`: s ∈ [−1, 1], σ = sign(s), β = fold + (b_ok − fold)s²
    /// (the curve is smooth in s, not in β: near a fold it moves as √|β − fold|).
    fn at_fold(&self, fold: f64, b_ok: f64, s: f64) -> Option<Sample> {
        let sigma = if s < 0.0 { -1.0 } else { 1.0 };
        self.sample(fold + (b_ok - fold) * s * s, sigma)
    }

    /// Samples (s, sample) through the fold between `b_ok` and `b_bad`,
    /// refined like [`Compat::trace`]; also the fold.
    fn fold_fill(&self, b_ok: f64, b_bad: f64) -> (f64, Vec<(f64, Sample)>) {
        let fold = self.fold(b_ok, b_bad);
        let f = |s: f64| self.at_fold(fold, b_ok, s);
        let m = 16;
        let grid: Vec<(f64, Sample)> = (0..=2 * m)
            .filter_map(|i| {
                let s = -1.0 + i as f64 / m as f64;
                f(s).map(|x| (s, x))
            })
            .collect();
        let mut out = Vec::with_capacity(grid.len());
        for w in grid.windows(2) {
            out.push(w[0]);
            refine_by(&f, w[0], w[1], REFINE_DEPTH, &mut out);
        }
        out.extend(grid.last().copied());
        (fold, out)
    }
}

/// Points bisected in the parameter between `p0` and `p1` (parameter, sample)
/// until neighbours are closer than [`REFINE_STEP`] (relative beyond one
/// spread), within [`REFINE_WITHIN`] spreads.
fn refine_by<F: Fn(f64) -> Option<Sample>>(
    f: &F,
    p0: (f64, Sample),
    p1: (f64, Sample),
    depth: u32,
    out: &mut Vec<(f64, Sample)>,
) {
    let (s0, s1) = (p0.1, p1.1);
    let norm = |s: &Sample| s.1[0].hypot(s.1[1]).max(s.2[0].hypot(s.2[1]));
    let gap =
        (s0.1[0] - s1.1[0]).hypot(s0.1[1] - s1.1[1]) + (s0.2[0] - s1.2[0]).hypot(s0.2[1] - s1.2[1]);
    let near = norm(&s0).min(norm(&s1));
    if depth == 0 || gap <= REFINE_STEP * near.max(1.0) || near > REFINE_WITHIN {
        return;
    }
    let t = 0.5 * (p0.0 + p1.0);
    let Some(m) = f(t) else {
        return;
    };
    refine_by(f, p0, (t, m), depth - 1, out);
    out.push((t, m));
    refine_by(f, (t, m), p1, depth - 1, out);
}

fn compat_for(nm: &Normal, poses: &[Pose]) -> Result<Compat, MotionError> {
    Compat::new(nm, [0, 1, 2, 3]).ok_or(MotionError::PoseCount {
        what: "Burmester's curves (the poses are degenerate: every dyad of three of them passes the fourth)",
        want: "four non-degenerate",
        got: poses.len(),
    })
}

/// Burmester's circle-point and centre-point curves of four poses, sampled at
/// `samples` values of the parameter per branch (module docs), as polylines.
pub fn burmester_curves(poses: &[Pose], samples: usize) -> Result<BurmesterCurves, MotionError> {
    if poses.len() != 4 {
        return Err(MotionError::PoseCount {
            what: "Burmester's curves",
            want: "exactly 4",
            got: poses.len(),
        });
    }
    check_distinct(poses)?;
    let nm = Normal::new(poses);
    let cp = compat_for(&nm, poses)?;
    let n = samples.clamp(16, 1 << 20);
    let mut branches = Vec::new();
    let far = |(_, a, c): &Sample| a[0].hypot(a[1]) > CURVE_FAR || c[0].hypot(c[1]) > CURVE_FAR;
    let point = |(beta, a, c): Sample, sigma: f64| CurvePoint {
        beta,
        sigma,
        circle: [a[0] * nm.scale, a[1] * nm.scale],
        centre: nm.to_world(c),
    };
    let h = 2.0 * PI / n as f64;
    let mut folds: Vec<Vec<CurvePoint>> = Vec::new();
    for sigma in [1.0, -1.0] {
        let mut runs: Vec<Vec<CurvePoint>> = Vec::new();
        let mut cur: Vec<CurvePoint> = Vec::new();
        let mut starts_at_first = false;
        for (k, (s0, mid)) in cp.trace(sigma, n).into_iter().enumerate() {
            for s in s0.into_iter().chain(mid) {
                if far(&s) {
                    if !cur.is_empty() {
                        runs.push(std::mem::take(&mut cur));
                    }
                } else {
                    if cur.is_empty() && runs.is_empty() && k == 0 {
                        starts_at_first = true;
                    }
                    cur.push(point(s, sigma));
                }
            }
            if s0.is_none() && !cur.is_empty() {
                runs.push(std::mem::take(&mut cur));
            }
            // Through each fold once (it joins the two branches).
            let b0 = -PI + h * k as f64;
            let next_ok = cp.sample(b0 + h, sigma).is_some();
            let fold = match (s0.is_some(), next_ok) {
                (true, false) => Some((b0, b0 + h)),
                (false, true) => Some((b0 + h, b0)),
                _ => None,
            };
            if let (Some((b_ok, b_bad)), true) = (fold, sigma > 0.0) {
                let mut run = Vec::new();
                for (s, x) in cp.fold_fill(b_ok, b_bad).1 {
                    let sg = if s < 0.0 { -1.0 } else { 1.0 };
                    if far(&x) {
                        if !run.is_empty() {
                            folds.push(std::mem::take(&mut run));
                        }
                    } else {
                        run.push(point(x, sg));
                    }
                }
                if !run.is_empty() {
                    folds.push(run);
                }
            }
        }
        if !cur.is_empty() {
            // A run reaching β = π continues the one that starts at β = −π.
            if starts_at_first && !runs.is_empty() {
                let first = runs.remove(0);
                cur.extend(first);
            }
            runs.push(cur);
        }
        branches.extend(runs);
    }
    branches.extend(folds);
    Ok(BurmesterCurves {
        parameter_pose: cp.p + 2,
        branches,
    })
}

/// The dyad of four poses at crank rotation `beta` [rad] (from pose 1 to pose
/// `parameter_pose` of [`burmester_curves`]) on branch `sigma` (±1): its circle
/// point (coupler frame) and centre point [m], or None where there is none.
pub fn burmester_dyad(
    poses: &[Pose],
    beta: f64,
    sigma: f64,
) -> Result<Option<DyadPoints>, MotionError> {
    if poses.len() != 4 {
        return Err(MotionError::PoseCount {
            what: "a dyad of Burmester's curves",
            want: "exactly 4",
            got: poses.len(),
        });
    }
    check_distinct(poses)?;
    let nm = Normal::new(poses);
    let cp = compat_for(&nm, poses)?;
    Ok(cp
        .dyad(beta, if sigma < 0.0 { -1.0 } else { 1.0 })
        .map(|(a, c)| ([a[0] * nm.scale, a[1] * nm.scale], nm.to_world(c))))
}

/// Newton's method on |q_j − C|² − ρ = 0 for all poses (normalised), from
/// (a, C); the polished (a, C, ρ) or None if it does not converge.
fn polish(nm: &Normal, a: [f64; 2], c: [f64; 2]) -> Option<([f64; 2], [f64; 2], f64)> {
    let n = nm.pts.len();
    debug_assert_eq!(n, 5);
    let q0 = nm.q(0, a);
    let mut x = Vector5::new(
        a[0],
        a[1],
        c[0],
        c[1],
        (q0[0] - c[0]).powi(2) + (q0[1] - c[1]).powi(2),
    );
    for _ in 0..40 {
        let (a, c, rho) = ([x[0], x[1]], [x[2], x[3]], x[4]);
        let mut f = Vector5::zeros();
        let mut jac = Matrix5::zeros();
        for j in 0..5 {
            let q = nm.q(j, a);
            let (dx, dy) = (q[0] - c[0], q[1] - c[1]);
            f[j] = dx * dx + dy * dy - rho;
            let (s, co) = nm.th[j].sin_cos();
            // d q / d u = (cos, sin), d q / d v = (−sin, cos).
            jac[(j, 0)] = 2.0 * (dx * co + dy * s);
            jac[(j, 1)] = 2.0 * (-dx * s + dy * co);
            jac[(j, 2)] = -2.0 * dx;
            jac[(j, 3)] = -2.0 * dy;
            jac[(j, 4)] = -1.0;
        }
        let step = jac.lu().solve(&f)?;
        x -= step;
        if !x.iter().all(|v| v.is_finite()) {
            return None;
        }
        if step.norm() <= 1e-15 * (1.0 + x.norm()) {
            break;
        }
    }
    Some(([x[0], x[1]], [x[2], x[3]], x[4]))
}

/// Burmester's points of five poses (module docs).
pub fn burmester_points(poses: &[Pose]) -> Result<BurmesterPoints, MotionError> {
    if poses.len() != 5 {
        return Err(MotionError::PoseCount {
            what: "Burmester's points",
            want: "exactly 5",
            got: poses.len(),
        });
    }
    check_distinct(poses)?;
    let mut found = Vec::new();
    let mut parity_ok = false;
    for density in [1024usize, 16384] {
        found.clear();
        // Curve of {1, 2, 3, 4} against the condition of {1, 2, 3, 5}, and back.
        for (curve, cond) in [([0, 1, 2, 3], [0, 1, 2, 4]), ([0, 1, 2, 4], [0, 1, 2, 3])] {
            trace_roots(poses, curve, cond, density, &mut found);
        }
        parity_ok = found.len().is_multiple_of(2);
        if parity_ok {
            break;
        }
    }
    found.sort_by(|a: &BurmesterPoint, b| {
        a.circle[0]
            .total_cmp(&b.circle[0])
            .then(a.circle[1].total_cmp(&b.circle[1]))
    });
    Ok(BurmesterPoints {
        points: found,
        parity_ok,
    })
}

fn trace_roots(
    poses: &[Pose],
    curve: [usize; 4],
    cond: [usize; 4],
    n: usize,
    found: &mut Vec<BurmesterPoint>,
) {
    let sub: Vec<Pose> = curve.iter().map(|&i| poses[i]).collect();
    let nm4 = Normal::new(&sub);
    let nm5 = Normal::new(poses);
    let Some(cp) = Compat::new(&nm4, [0, 1, 2, 3]) else {
        return;
    };
    // The condition in the five poses' normalisation: both normalisations share
    // pose 1's point; the scales differ.
    let ratio = nm4.scale / nm5.scale;
    let eval = |beta: f64, sigma: f64| -> Option<(f64, [f64; 2], [f64; 2])> {
        let (a, c) = cp.dyad(beta, sigma)?;
        let a5 = [a[0] * ratio, a[1] * ratio];
        let c5 = [c[0] * ratio, c[1] * ratio];
        Some((det_norm(&nm5, cond, a5), a5, c5))
    };
    let h = 2.0 * PI / n as f64;
    let cond_of = |(b, a, c): Sample| -> (f64, f64, [f64; 2], [f64; 2]) {
        let a5 = [a[0] * ratio, a[1] * ratio];
        let c5 = [c[0] * ratio, c[1] * ratio];
        (b, det_norm(&nm5, cond, a5), a5, c5)
    };
    let mut cands: Vec<([f64; 2], [f64; 2])> = Vec::new();
    for sigma in [1.0, -1.0] {
        let traced = cp.trace(sigma, n);
        for k in 0..n {
            let (s0, mid) = &traced[k];
            let next_ok = traced[(k + 1) % n].0.is_some();
            let Some(s0) = *s0 else {
                if next_ok && sigma > 0.0 {
                    let b1 = -PI + h * (k + 1) as f64;
                    fold_roots(&cp, &cond_of, b1, b1 - h, &mut cands);
                }
                continue;
            };
            if !next_ok {
                if sigma > 0.0 {
                    fold_roots(&cp, &cond_of, s0.0, s0.0 + h, &mut cands);
                }
                continue;
            }
            // The samples of the interval, its end included.
            let end = cp.sample(s0.0 + h, sigma);
            let pts: Vec<_> = std::iter::once(s0)
                .chain(mid.iter().copied())
                .chain(end)
                .map(cond_of)
                .collect();
            for w in pts.windows(2) {
                let ((b0, f0, a0, c0), (b1, f1, _, _)) = (w[0], w[1]);
                if f0 == 0.0 {
                    cands.push((a0, c0));
                } else if f0 * f1 < 0.0 {
                    if let Some(r) = bisect(|b| eval(b, sigma).map(|v| v.0), b0, b1, f0) {
                        if let Some((_, a, c)) = eval(r, sigma) {
                            cands.push((a, c));
                        }
                    }
                }
            }
        }
    }
    let spread = nm5.scale;
    for (a, c) in cands {
        let Some((a, c, rho)) = polish(&nm5, a, c) else {
            continue;
        };
        if let Some(p) = verify(&nm5, poses, a, c, rho) {
            let dup = found.iter().any(|f| {
                let (da, dc) = (
                    (f.circle[0] - p.circle[0]).hypot(f.circle[1] - p.circle[1]),
                    (f.centre[0] - p.centre[0]).hypot(f.centre[1] - p.centre[1]),
                );
                let size = spread
                    + f.centre[0]
                        .hypot(f.centre[1])
                        .max(f.circle[0].hypot(f.circle[1]));
                da <= 1e-5 * size && dc <= 1e-5 * size
            });
            if !dup {
                found.push(p);
            }
        }
    }
}

/// Roots on the arc through the fold of the compatibility linkage between
/// `b_ok` (both branches assemble) and `b_bad` (neither): `cond` maps a sample
/// to (β, condition, circle point, centre) in the five poses' normalisation.
fn fold_roots<G>(
    cp: &Compat,
    cond: &G,
    b_ok: f64,
    b_bad: f64,
    cands: &mut Vec<([f64; 2], [f64; 2])>,
) where
    G: Fn(Sample) -> (f64, f64, [f64; 2], [f64; 2]),
{
    let (fold, fill) = cp.fold_fill(b_ok, b_bad);
    let vals: Vec<(f64, f64, [f64; 2], [f64; 2])> = fill
        .iter()
        .map(|&(s, x)| {
            let (_, f, a, c) = cond(x);
            (s, f, a, c)
        })
        .collect();
    for w in vals.windows(2) {
        let ((s0, f0, a0, c0), (s1, f1, _, _)) = (w[0], w[1]);
        if f0 == 0.0 {
            cands.push((a0, c0));
        } else if f0 * f1 < 0.0 {
            let g = |s: f64| cp.at_fold(fold, b_ok, s).map(|x| cond(x).1);
            if let Some(r) = bisect(g, s0, s1, f0) {
                if let Some(x) = cp.at_fold(fold, b_ok, r) {
                    let (_, _, a, c) = cond(x);
                    cands.push((a, c));
                }
            }
        }
    }
}

/// Bisection for a sign change of f on [x0, x1], f(x0) = f0 ≠ 0.
fn bisect<F: Fn(f64) -> Option<f64>>(f: F, x0: f64, x1: f64, f0: f64) -> Option<f64> {
    let (mut lo, mut hi, mut flo) = (x0, x1, f0);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if mid == lo || mid == hi {
            break;
        }
        let fm = f(mid)?;
        if fm == 0.0 {
            return Some(mid);
        }
        if (fm < 0.0) == (flo < 0.0) {
            lo = mid;
            flo = fm;
        } else {
            hi = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

/// The near-degenerate rule of the module docs, in world units.
fn verify(
    nm: &Normal,
    poses: &[Pose],
    a: [f64; 2],
    c: [f64; 2],
    rho: f64,
) -> Option<BurmesterPoint> {
    if rho.is_nan() || rho <= 0.0 || rho.sqrt() > 1e6 || a[0].hypot(a[1]) > 1e6 {
        return None;
    }
    let uv = [a[0] * nm.scale, a[1] * nm.scale];
    let centre = nm.to_world(c);
    let q: Vec<[f64; 2]> = poses.iter().map(|&p| pose_point(p, uv)).collect();
    for i in 0..q.len() {
        for j in i + 1..q.len() {
            if (q[i][0] - q[j][0]).hypot(q[i][1] - q[j][1]) <= 1e-7 * nm.scale {
                return None; // a pole
            }
        }
    }
    let r: Vec<f64> = q
        .iter()
        .map(|p| (p[0] - centre[0]).hypot(p[1] - centre[1]))
        .collect();
    let radius = r.iter().sum::<f64>() / r.len() as f64;
    let residual = r.iter().fold(0.0f64, |m, x| m.max((x - radius).abs()));
    (residual <= 1e-9 * (radius + nm.scale)).then_some(BurmesterPoint {
        circle: uv,
        centre,
        radius,
        residual,
    })
}

#[cfg(test)]
#[path = "burmester_tests.rs"]
mod tests;
