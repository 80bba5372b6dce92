//! Class III Assur group (triad): a ternary link J0-J1-J2 held by three binary
//! links K_i–J_i to known joints K_i (seed 001: the knife drives of BR-125 and of
//! the Burg trimmer).
//!
//! Six closure equations in the six coordinates of J0, J1, J2:
//!
//! ```text
//! F_i   = (|J_i − K_i|² − arm_i²) / 2        i = 0, 1, 2   (binary links)
//! F_3+k = (|J_a − J_b|² − side_k²) / 2        (a, b) = (0,1), (1,2), (2,0)
//! ```
//!
//! No closed form exists. Along a crank-angle grid the solver takes Newton steps
//! on F with the analytic Jacobian, started from a second-order predictor (the
//! previous pose plus its velocity and acceleration analogs). When Newton fails,
//! or lands on another assembly (the ternary link mirrored, or far from the
//! predictor), it falls back to the seed's method: open the group at J1, leaving a
//! four-bar K0-J0-J2-K2; move the angle ψ of K0→J0 over its full turn; bracket the
//! sign changes of `f(ψ) = |J1(ψ) − K1| − arm1` and bisect (Bolzano); take the root
//! nearest the predictor and polish it with Newton.
//!
//! The analogs solve `J·v = r`, `J·a = r2` with the same Jacobian (nalgebra LU):
//! `r_i = (J_i − K_i)·K_i'`, `r2_i = (J_i − K_i)·K_i'' − |J_i' − K_i'|²`, and for a
//! side `r2 = −|J_a' − J_b'|²`.

use nalgebra::{SMatrix, SVector};

use crate::geom::{cross, dist, dot, sub, V2};

type M3 = SMatrix<f64, 3, 3>;
type V3 = SVector<f64, 3>;
#[cfg(test)]
type M6 = SMatrix<f64, 6, 6>;
type V6 = SVector<f64, 6>;

const SIDES: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];

/// The triad's dimensions and the orientation of its ternary link.
#[derive(Debug, Clone, PartialEq)]
pub struct Triad {
    /// |K_i J_i| of the three binary links.
    pub arms: [f64; 3],
    /// |J0 J1|, |J1 J2|, |J2 J0| of the ternary link.
    pub sides: [f64; 3],
    /// Sign of (J1 − J0) × (J2 − J0): a rigid body keeps its orientation.
    pub orientation: f64,
}

/// The Jacobian of a pose in the reduced form of [`Triad::reduce`].
struct Reduced {
    d: [V2; 3],
    n: [V2; 3],
    s: [V2; 3],
    inv: Option<M3>,
    /// det M, which is ± det F' (the change to the (α, t) coordinates has
    /// determinant Π|d_i|² and scales the first three rows by the same).
    det: f64,
}

impl Reduced {
    /// x with `F' x = r` (r in the row order of the closure equations), by the
    /// structure: three projections and the 3×3 inverse.
    fn solve(&self, r: [f64; 6]) -> Option<[V2; 3]> {
        let inv = self.inv.as_ref()?;
        let alpha: [f64; 3] = [0, 1, 2].map(|i| r[i] / dot(self.d[i], self.d[i]));
        let mut b = V3::zeros();
        for (row, &(a, c)) in SIDES.iter().enumerate() {
            b[row] = r[3 + row] - alpha[a] * dot(self.s[row], self.d[a])
                + alpha[c] * dot(self.s[row], self.d[c]);
        }
        let t = inv * b;
        let x = [0, 1, 2].map(|i| {
            [
                alpha[i] * self.d[i][0] + t[i] * self.n[i][0],
                alpha[i] * self.d[i][1] + t[i] * self.n[i][1],
            ]
        });
        x.iter().flatten().all(|v| v.is_finite()).then_some(x)
    }
}

/// The largest distance between corresponding joints of two poses.
fn away(j: &[V2; 3], other: &[V2; 3]) -> f64 {
    (0..3)
        .map(|i| dot(sub(j[i], other[i]), sub(j[i], other[i])).sqrt())
        .fold(0.0, f64::max)
}

/// Intersection of circle(c1, r1) and circle(c2, r2) on side `sign` of c1→c2.
fn circles(c1: V2, r1: f64, c2: V2, r2: f64, sign: f64) -> Option<V2> {
    let d = sub(c2, c1);
    let dd = dot(d, d);
    let l = dd.sqrt();
    if l == 0.0 {
        return None;
    }
    let x = (r1 * r1 - r2 * r2 + dd) / (2.0 * l);
    let h2 = r1 * r1 - x * x;
    if h2 < 0.0 {
        return None;
    }
    let h = h2.sqrt();
    let (ex, ey) = (d[0] / l, d[1] / l);
    Some([
        c1[0] + x * ex - sign * h * ey,
        c1[1] + x * ey + sign * h * ex,
    ])
}

impl Triad {
    /// Dimensions and orientation from an assembled (drawn) pose.
    pub fn from_pose(k: [V2; 3], j: [V2; 3]) -> Triad {
        Triad {
            arms: [dist(j[0], k[0]), dist(j[1], k[1]), dist(j[2], k[2])],
            sides: SIDES.map(|(a, b)| dist(j[a], j[b])),
            orientation: cross(sub(j[1], j[0]), sub(j[2], j[0])).signum(),
        }
    }

    /// A length scale for tolerances.
    pub fn size(&self) -> f64 {
        self.arms
            .iter()
            .chain(&self.sides)
            .fold(0.0f64, |a, &b| a.max(b))
    }

    fn residual(&self, k: &[V2; 3], j: &[V2; 3]) -> V6 {
        let mut f = V6::zeros();
        for i in 0..3 {
            let d = sub(j[i], k[i]);
            f[i] = 0.5 * (dot(d, d) - self.arms[i] * self.arms[i]);
        }
        for (s, &(a, b)) in SIDES.iter().enumerate() {
            let d = sub(j[a], j[b]);
            f[3 + s] = 0.5 * (dot(d, d) - self.sides[s] * self.sides[s]);
        }
        f
    }

    /// The full 6×6 Jacobian: the tests' reference for the structured solve.
    #[cfg(test)]
    fn jacobian(&self, k: &[V2; 3], j: &[V2; 3]) -> M6 {
        let mut m = M6::zeros();
        for i in 0..3 {
            let d = sub(j[i], k[i]);
            m[(i, 2 * i)] = d[0];
            m[(i, 2 * i + 1)] = d[1];
        }
        for (s, &(a, b)) in SIDES.iter().enumerate() {
            let d = sub(j[a], j[b]);
            m[(3 + s, 2 * a)] = d[0];
            m[(3 + s, 2 * a + 1)] = d[1];
            m[(3 + s, 2 * b)] = -d[0];
            m[(3 + s, 2 * b + 1)] = -d[1];
        }
        m
    }

    /// The Jacobian `F'(J)` reduced by its structure, for solving `F'(J) x = r`.
    ///
    /// Rows 0–2 (the binary links) say `d_i · x_i = r_i` with `d_i = J_i − K_i`,
    /// so `x_i = (r_i / |d_i|²) d_i + t_i n_i` with `n_i ⟂ d_i`; rows 3–5 (the sides
    /// `s = J_a − J_b`) then give three equations in `t`:
    /// `t_a (s·n_a) − t_b (s·n_b) = r − α_a (s·d_a) + α_b (s·d_b)`. The 3×3 matrix
    /// `M` of that system carries the singularity: `det F' = ± det M` with a sign
    /// fixed by the layout, so `det M`'s sign tells the assembly branch.
    fn reduce(&self, k: &[V2; 3], j: &[V2; 3]) -> Reduced {
        let d: [V2; 3] = [0, 1, 2].map(|i| sub(j[i], k[i]));
        let n: [V2; 3] = d.map(|v| [-v[1], v[0]]);
        let s: [V2; 3] = SIDES.map(|(a, b)| sub(j[a], j[b]));
        let mut m = M3::zeros();
        for (row, &(a, b)) in SIDES.iter().enumerate() {
            m[(row, a)] = dot(s[row], n[a]);
            m[(row, b)] = -dot(s[row], n[b]);
        }
        // nalgebra's 3×3 determinant and inverse are closed-form (cofactors).
        let det = m.determinant();
        Reduced {
            d,
            n,
            s,
            inv: m.try_inverse(),
            det,
        }
    }

    /// Largest closure error as a length: max |(|P − Q| − length)|.
    pub fn closure_error(&self, k: &[V2; 3], j: &[V2; 3]) -> f64 {
        let arms = (0..3).map(|i| (dist(j[i], k[i]) - self.arms[i]).abs());
        let sides = SIDES
            .iter()
            .enumerate()
            .map(|(s, &(a, b))| (dist(j[a], j[b]) - self.sides[s]).abs());
        arms.chain(sides).fold(0.0, f64::max)
    }

    fn oriented(&self, j: &[V2; 3]) -> bool {
        cross(sub(j[1], j[0]), sub(j[2], j[0])) * self.orientation > 0.0
    }

    /// Newton from `guess`; `None` if it does not converge to 1e-13 of the size,
    /// or lands on the mirrored ternary link.
    pub fn newton(&self, k: &[V2; 3], guess: [V2; 3]) -> Option<[V2; 3]> {
        let size = self.size();
        let mut j = guess;
        for _ in 0..30 {
            if self.closure_error(k, &j) <= 1e-13 * size {
                return self.oriented(&j).then_some(j);
            }
            let f = self.residual(k, &j);
            let step = self.reduce(k, &j).solve(f.into())?;
            for i in 0..3 {
                j[i][0] -= step[i][0];
                j[i][1] -= step[i][1];
            }
        }
        (self.closure_error(k, &j) <= 1e-12 * size && self.oriented(&j)).then_some(j)
    }

    /// J0 and J2 for the opened four-bar at ψ, then J1 on the rigid link.
    fn open(&self, k: &[V2; 3], psi: f64, sign: f64) -> Option<[V2; 3]> {
        let j0 = [
            k[0][0] + self.arms[0] * psi.cos(),
            k[0][1] + self.arms[0] * psi.sin(),
        ];
        let j2 = circles(j0, self.sides[2], k[2], self.arms[2], sign)?;
        // J1 at |J0J1| from J0 and |J1J2| from J2, on the side of J0→J2 that
        // keeps the ternary link's orientation: (J1−J0)×(J2−J0) has its sign, so
        // J1 is on side −orientation of the line J0→J2.
        let j1 = circles(j0, self.sides[0], j2, self.sides[1], -self.orientation)?;
        Some([j0, j1, j2])
    }

    /// The seed's bracketing: every root of f(ψ) over a full turn of ψ, for both
    /// assemblies of the opened four-bar, each bisected and polished by Newton.
    pub fn bracket_all(&self, k: &[V2; 3]) -> Vec<[V2; 3]> {
        const SAMPLES: usize = 1440;
        let mut roots = Vec::new();
        let f = |psi: f64, sign: f64| -> Option<f64> {
            let j = self.open(k, psi, sign)?;
            Some(dot(sub(j[1], k[1]), sub(j[1], k[1])).sqrt() - self.arms[1])
        };
        for sign in [1.0, -1.0] {
            let step = std::f64::consts::TAU / SAMPLES as f64;
            let mut prev: Option<(f64, f64)> = None;
            let mut before: Option<(f64, f64)> = None;
            for s in 0..=SAMPLES {
                let psi = s as f64 * step;
                let cur = f(psi, sign).map(|v| (psi, v));
                // Two roots closer than a step leave no sign change between samples:
                // a sample where |f| dips without changing sign is a start for Newton.
                if let (Some((_, f0)), Some((mid, f1)), Some((_, f2))) = (before, prev, cur) {
                    if f0 * f1 > 0.0
                        && f1 * f2 > 0.0
                        && f1.abs() < f0.abs()
                        && f1.abs() < f2.abs()
                        && f1.abs() < 0.05 * self.size()
                    {
                        if let Some(j) = self.open(k, mid, sign).and_then(|j| self.newton(k, j)) {
                            roots.push(j);
                        }
                    }
                }
                // At an edge of the opened four-bar's range (its own dead centre) a
                // root can sit where f stops existing, with no sign change: try
                // Newton from the last sample that still assembles.
                if let (Some((edge, fe)), None) | (None, Some((edge, fe))) = (prev, cur) {
                    if fe.abs() < 0.1 * self.size() {
                        if let Some(j) = self.open(k, edge, sign).and_then(|j| self.newton(k, j)) {
                            roots.push(j);
                        }
                    }
                    // f changes like a square root there, so the last sample may be
                    // far from a root at the edge itself: bisect for the edge and
                    // start Newton there (it keeps only a closed, oriented pose).
                    {
                        let mut inside = edge;
                        let mut outside = if edge == psi { psi - step } else { psi };
                        for _ in 0..60 {
                            let mid = 0.5 * (inside + outside);
                            if self.open(k, mid, sign).is_some() {
                                inside = mid;
                            } else {
                                outside = mid;
                            }
                        }
                        if let Some(j) = self.open(k, inside, sign).and_then(|j| self.newton(k, j))
                        {
                            roots.push(j);
                        }
                    }
                }
                if let (Some((a, fa)), Some((b, fb))) = (prev, cur) {
                    if fa == 0.0 || fa * fb < 0.0 {
                        let (mut lo, mut hi, mut flo) = (a, b, fa);
                        for _ in 0..60 {
                            let mid = 0.5 * (lo + hi);
                            match f(mid, sign) {
                                Some(fm) if fm * flo <= 0.0 => hi = mid,
                                Some(fm) => {
                                    lo = mid;
                                    flo = fm;
                                }
                                None => break,
                            }
                        }
                        if let Some(j) = self.open(k, 0.5 * (lo + hi), sign) {
                            if let Some(polished) = self.newton(k, j) {
                                roots.push(polished);
                            }
                        }
                    }
                }
                before = prev;
                prev = cur;
            }
        }
        roots
    }

    /// The assembly continuous with `predicted`: Newton from it, and if that fails
    /// or jumps more than `max_jump`, the bracketed root nearest to it.
    pub fn solve(&self, k: &[V2; 3], predicted: [V2; 3], max_jump: f64) -> Option<[V2; 3]> {
        if let Some(j) = self.newton(k, predicted) {
            if away(&j, &predicted) <= max_jump {
                return Some(j);
            }
        }
        self.bracket_all(k)
            .into_iter()
            .filter(|j| away(j, &predicted) <= max_jump)
            .min_by(|a, b| away(a, &predicted).total_cmp(&away(b, &predicted)))
    }

    /// Newton from the predictor only, for a continuation step: `None` unless it
    /// converges to a pose within `tol` of `predicted` (a root further away is on
    /// another assembly, or the followed one has ended at a fold).
    pub fn follow(&self, k: &[V2; 3], predicted: [V2; 3], tol: f64) -> Option<[V2; 3]> {
        self.newton(k, predicted)
            .filter(|j| away(j, &predicted) <= tol)
    }

    /// Re-acquire the group where its followed assembly has ended: every root of
    /// the seed's bracketing, those whose Jacobian determinant has the sign `sign`
    /// (the drawn assembly mode) first, and among them the one nearest `near`.
    pub fn acquire(&self, k: &[V2; 3], near: &[V2; 3], sign: f64) -> Option<[V2; 3]> {
        let key = |j: &[V2; 3]| {
            let other = (self.reduce(k, j).det.signum() != sign) as u8;
            (other, away(j, near))
        };
        self.bracket_all(k).into_iter().min_by(|a, b| {
            let (ka, kb) = (key(a), key(b));
            ka.0.cmp(&kb.0).then(ka.1.total_cmp(&kb.1))
        })
    }

    /// The sign of the Jacobian's determinant at pose `j` (the assembly mode; it
    /// changes only through a singular position).
    pub fn det_sign(&self, k: &[V2; 3], j: &[V2; 3]) -> f64 {
        self.reduce(k, j).det.signum()
    }

    /// Velocity and acceleration analogs of J from those of K, and the sign of the
    /// Jacobian's determinant (which assembly branch the pose is on: it changes
    /// only through a singular position). The analogs are `None` at a singular
    /// position (the Jacobian is not invertible).
    #[allow(clippy::type_complexity)]
    pub fn analogs(
        &self,
        k: &[V2; 3],
        kv: &[V2; 3],
        ka: &[V2; 3],
        j: &[V2; 3],
    ) -> (f64, Option<([V2; 3], [V2; 3])>) {
        let red = self.reduce(k, j);
        // |det| relative to the scale of the entries (size⁶): a dead centre.
        if red.det.abs() <= 1e-8 * self.size().powi(6) {
            return (red.det.signum(), None);
        }
        let mut r = [0.0; 6];
        for i in 0..3 {
            r[i] = dot(red.d[i], kv[i]);
        }
        let Some(v) = red.solve(r) else {
            return (red.det.signum(), None);
        };
        let mut r2 = [0.0; 6];
        for i in 0..3 {
            let rel = sub(v[i], kv[i]);
            r2[i] = dot(red.d[i], ka[i]) - dot(rel, rel);
        }
        for (s, &(a, b)) in SIDES.iter().enumerate() {
            let rel = sub(v[a], v[b]);
            r2[3 + s] = -dot(rel, rel);
        }
        (red.det.signum(), red.solve(r2).map(|a| (v, a)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A random assembled triad: anchors and joints drawn at random.
    fn triad_pose() -> impl Strategy<Value = ([V2; 3], [V2; 3])> {
        let pt = || (-3.0f64..3.0, -3.0f64..3.0).prop_map(|(x, y)| [x, y]);
        ([pt(), pt(), pt()], [pt(), pt(), pt()]).prop_filter("non-degenerate", |(k, j)| {
            let t = Triad::from_pose(*k, *j);
            t.arms.iter().chain(&t.sides).all(|&l| l > 0.3)
                && cross(sub(j[1], j[0]), sub(j[2], j[0])).abs() > 0.3
        })
    }

    #[test]
    fn bracketing_finds_a_root_at_the_edge_of_the_range() {
        // Found by the property test below on a fresh machine: the drawn pose lies
        // at the edge of the opened four-bar's range, between the last sample that
        // assembles and the first that does not.
        let k = [
            [-0.39917138870379304, -2.8981437220848973],
            [2.169463478376187, 0.0],
            [-1.5575628277323534, -0.4807192288132295],
        ];
        let j = [
            [-1.2714355822739363, -0.21211261572923573],
            [1.3589427596481871, -2.8589867979771073],
            [1.9784667200530694, 2.6553920968799956],
        ];
        let t = Triad::from_pose(k, j);
        let roots = t.bracket_all(&k);
        let near = roots
            .iter()
            .any(|r| (0..3).all(|i| dot(sub(r[i], j[i]), sub(r[i], j[i])).sqrt() < 1e-8));
        assert!(near, "{} roots, none at the drawn pose", roots.len());
    }

    proptest! {
        #[test]
        fn newton_and_bracketing_find_the_drawn_pose((k, j) in triad_pose(), nudge in -0.05f64..0.05) {
            let t = Triad::from_pose(k, j);
            // A pose drawn at a singular position (a double root of the closure)
            // has no sign change to bracket: not a fair case for either method.
            let sigma = t.jacobian(&k, &j).singular_values().min();
            prop_assume!(sigma > 0.05 * t.size());
            // Newton from a nudged guess returns to the pose (closure to 1e-12).
            let guess = j.map(|p| [p[0] + nudge, p[1] - nudge]);
            if let Some(n) = t.newton(&k, guess) {
                prop_assert!(t.closure_error(&k, &n) <= 1e-12 * t.size());
            }
            // The seed's bracketing, independently, finds the drawn pose among its roots.
            let roots = t.bracket_all(&k);
            let near = roots.iter().any(|r| (0..3).all(|i| dot(sub(r[i], j[i]), sub(r[i], j[i])).sqrt() < 1e-8));
            prop_assert!(near, "{} roots, none at the drawn pose", roots.len());
            for r in &roots {
                prop_assert!(t.closure_error(&k, r) <= 1e-12 * t.size());
                prop_assert!(t.oriented(r));
            }
        }

        #[test]
        fn structured_solve_matches_a_dense_lu((k, j) in triad_pose(), r in prop::array::uniform6(-1.0f64..1.0)) {
            let t = Triad::from_pose(k, j);
            let dense = t.jacobian(&k, &j);
            prop_assume!(dense.singular_values().min() > 1e-3 * t.size() * t.size());
            let want = dense.lu().solve(&V6::from_row_slice(&r)).unwrap();
            let red = t.reduce(&k, &j);
            let got = red.solve(r).unwrap();
            for i in 0..3 {
                for c in 0..2 {
                    prop_assert!((got[i][c] - want[2 * i + c]).abs() <= 1e-9 * (1.0 + want.amax()));
                }
            }
            // |det M| is |det F'|.
            let det = dense.determinant();
            prop_assert!((red.det.abs() - det.abs()).abs() <= 1e-9 * det.abs().max(1.0));
        }

        #[test]
        fn analogs_match_finite_differences((k, j) in triad_pose(), vx in -1.0f64..1.0, vy in -1.0f64..1.0) {
            // Move anchor K0 along a circle-free straight line with velocity (vx, vy).
            let t = Triad::from_pose(k, j);
            let kv = [[vx, vy], [0.0, 0.0], [0.0, 0.0]];
            let ka = [[0.0; 2]; 3];
            let (_, found) = t.analogs(&k, &kv, &ka, &j);
            prop_assume!(found.is_some());
            let (v, a) = found.unwrap();
            // Finite differences are only a fair reference away from singular poses.
            prop_assume!(v.iter().chain(&a).all(|p| p[0].abs() < 20.0 && p[1].abs() < 20.0));
            // Newton stops at 1e-13 of the size: h = 1e-4 keeps that round-off
            // (1e-13 / h²) well below the second difference's own accuracy.
            let h = 1e-4;
            let at = |s: f64| {
                let ks = [[k[0][0] + s * vx, k[0][1] + s * vy], k[1], k[2]];
                t.newton(&ks, j)
            };
            if let (Some(lo), Some(hi)) = (at(-h), at(h)) {
                for i in 0..3 {
                    for c in 0..2 {
                        let fd1 = (hi[i][c] - lo[i][c]) / (2.0 * h);
                        let fd2 = (hi[i][c] - 2.0 * j[i][c] + lo[i][c]) / (h * h);
                        prop_assert!((v[i][c] - fd1).abs() <= 1e-5 * (1.0 + fd1.abs()), "v {} vs {}", v[i][c], fd1);
                        prop_assert!((a[i][c] - fd2).abs() <= 1e-3 * (1.0 + fd2.abs()), "a {} vs {}", a[i][c], fd2);
                    }
                }
            }
        }
    }
}
