//! Change points of class II groups, and the smooth motion through them.
//!
//! A change point (an uncertainty position) is a crank angle where a group's joint
//! reaches the line through its anchors — two circles' centres a and b for
//! [`Step::Circles`], its guide for [`Step::Slide`] — while the crank turns on: the
//! distance between the anchors (or from the anchor to the guide) passes an
//! extremum exactly at the sum or difference of the radii, and the group's two
//! assemblies meet. A parallelogram four-bar has two per turn (where all its links
//! line up), a Grashof linkage with s + l = p + q one. Unlike a fold (a dead
//! centre, where the group stops assembling and the crank cannot go on), the
//! analogs stay bounded and the motion can go on in either assembly.
//!
//! The closed form holds the drawn assembly (the side of the line, `sign`), so on
//! its own it would leave the smooth motion at every change point, with a jump in
//! velocity: a parallelogram would turn into the crossed antiparallelogram for half
//! the turn. The rule here:
//!
//! * **Found exactly.** A grid of [`SCAN`] crank angles over one turn from the
//!   drawn angle brackets every extremum of the anchors' distance (a sign change of
//!   its derivative, from the analogs); Brent's method puts it to round-off, and it
//!   is a change point where the group's h² there is within the fold's round-off
//!   floor ([`super::solve::FOLD_H2_REL`] of its radius², |h| ≤ 1e-6 of it) — the
//!   tolerance under which a group is already at its fold. A near change point
//!   (a parallelogram with one link 3e-4 longer) is not one: the drawn assembly is
//!   then the smooth motion, and is kept.
//! * **Followed smoothly.** Past a change point the group changes side (its `sign`
//!   flips), so the motion keeps its velocity: what a guided mechanism (a
//!   parallelogram drive with a second coupler out of phase) does. A group with
//!   an even number of change points a turn returns to its drawn assembly after
//!   one turn, so the smooth motion repeats every turn.
//! * **Held where it cannot repeat.** With an odd number a turn, the smooth
//!   motion repeats only every two turns; the group then keeps its drawn assembly
//!   (the motion repeats every turn, with a jump in velocity at each change point),
//!   and its change points are reported as not followed.
//!
//! Groups are taken in solving order; a flip upstream changes what downstream
//! groups see, so the scan is repeated after each group that flips.

use std::f64::consts::TAU;

use crate::geom::{cross, dot, sub, V2};

use super::model::{LinkageError, Program, Step};
use super::solve::{Out, Pose, Prev, Seek, State, FOLD_H2_REL};

/// Crank angles of the scan over one turn that brackets the extrema (5° apart);
/// with class III groups 360 (1°), the step within which their continuation from a
/// sample to a trial angle is sure to stay on its branch ([`super::solve`]'s
/// largest path step).
const SCAN: usize = 72;
const SCAN_PATH: usize = 360;

/// The widest window flagged around a change point [rad] (0.57°).
const MAX_WINDOW: f64 = 1e-2;

/// A change point of one class II group.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChangePoint {
    /// The group's step (index into [`Program::steps`]).
    pub step: usize,
    /// The crank angle [rad], in [φ0, φ0 + 2π) from the drawn angle φ0 (0 without
    /// a drawn pose).
    pub phi: f64,
    /// The motion follows the group smoothly through it (it changes side there);
    /// false where the group has an odd number a turn and keeps its drawn side.
    pub followed: bool,
    /// Half the width [rad] of the crank angles around it flagged singular: where
    /// the group's h is below [`NEAR_H_REL`] of its radius and the closed form's
    /// analogs lose digits.
    pub window: f64,
}

/// Around a change point, crank angles where the group's h is below this fraction
/// of its radius are flagged singular (analogs NaN): the closed form takes h as
/// √(r² − x²), which cancels there, and its analogs lose digits as h falls
/// (measured on a parallelogram: accelerations off by 6e-7 of their scale at
/// h = 3e-4 of the coupler, 4e-3 at 3e-5, wholly wrong at 3e-6; 1.2e-7 at 1.5e-3,
/// 3e-9 at 5e-3).
pub const NEAR_H_REL: f64 = 1e-3;

/// Rows of every point (or `m` chosen points) over `n` angles, owned: what a solve
/// writes through [`Out`] when the rows are read back here.
struct Rows {
    xy: Vec<V2>,
    vel: Vec<V2>,
    acc: Vec<V2>,
    ok: Vec<bool>,
    singular: Vec<bool>,
    branch: Vec<bool>,
}

impl Rows {
    /// `n` rows of `m` points, with room for the analogs when `analogs`.
    fn new(n: usize, m: usize, analogs: bool) -> Rows {
        let an = if analogs { n * m } else { 0 };
        Rows {
            xy: vec![[0.0; 2]; n * m],
            vel: vec![[0.0; 2]; an],
            acc: vec![[0.0; 2]; an],
            ok: vec![false; n],
            singular: vec![false; n],
            branch: vec![false; n],
        }
    }

    fn out(&mut self) -> Out<'_> {
        Out {
            xy: &mut self.xy,
            vel: &mut self.vel,
            acc: &mut self.acc,
            ok: &mut self.ok,
            singular: &mut self.singular,
            branch: &mut self.branch,
        }
    }
}

/// Every point at the scan's crank angles (and its analogs with class III groups).
struct Scan {
    angles: Vec<f64>,
    rows: Rows,
}

/// The programs that hold between the followed change points of one turn.
pub(super) struct Branches {
    phi0: f64,
    /// Reduced crank angles (in [φ0, φ0 + 2π)) where some group changes side, sorted.
    bounds: Vec<f64>,
    /// `programs[k]` holds from `bounds[k − 1]` (or φ0) to `bounds[k]` (or the turn's
    /// end); empty when there is no bound, and the program itself holds everywhere.
    programs: Vec<Program>,
    /// Every change point found, in solving order of the groups, then by angle.
    pub(super) points: Vec<ChangePoint>,
}

impl Branches {
    fn none(phi0: f64) -> Branches {
        Branches {
            phi0,
            bounds: vec![],
            programs: vec![],
            points: vec![],
        }
    }

    /// No group changes side: the program holds on the whole turn.
    pub(super) fn is_trivial(&self) -> bool {
        self.bounds.is_empty()
    }

    /// Flag the rows within a change point's window singular, their analogs NaN.
    pub(super) fn flag(&self, angles: &[f64], m: usize, out: &mut Out<'_>) {
        if self.points.is_empty() {
            return;
        }
        let analogs = !out.vel.is_empty();
        for (i, &phi) in angles.iter().enumerate() {
            let r = self.phi0 + (phi - self.phi0).rem_euclid(TAU);
            let near = self.points.iter().any(|c| {
                let d = (r - c.phi).abs();
                d.min(TAU - d) <= c.window
            });
            if near && out.ok[i] {
                out.singular[i] = true;
                if analogs {
                    out.vel[i * m..(i + 1) * m].fill([f64::NAN; 2]);
                    out.acc[i * m..(i + 1) * m].fill([f64::NAN; 2]);
                }
            }
        }
    }

    /// The index of the program that holds at crank angle `phi` [rad].
    fn index(&self, phi: f64) -> usize {
        let r = self.phi0 + (phi - self.phi0).rem_euclid(TAU);
        self.bounds.partition_point(|&b| b <= r)
    }

    /// The program that holds at crank angle `phi` [rad].
    pub(super) fn at<'a>(&'a self, base: &'a Program, phi: f64) -> &'a Program {
        if self.bounds.is_empty() {
            base
        } else {
            &self.programs[self.index(phi)]
        }
    }

    /// The followed change points so far as bounds, each flipping its group's side.
    fn rebuild(&mut self, base: &Program) {
        let mut flips: Vec<(f64, usize)> = self
            .points
            .iter()
            .filter(|c| c.followed)
            .map(|c| (c.phi, c.step))
            .collect();
        flips.sort_by(|x, y| x.0.total_cmp(&y.0));
        self.bounds = flips.iter().map(|f| f.0).collect();
        if flips.is_empty() {
            self.programs.clear();
            return;
        }
        let mut programs = vec![base.clone()];
        for &(_, step) in &flips {
            let mut next = programs[programs.len() - 1].clone();
            // Only groups with an assembly side have change points.
            if let Step::Circles { sign, .. } | Step::Slide { sign, .. } = &mut next.steps[step] {
                *sign = -*sign;
            }
            programs.push(next);
        }
        self.programs = programs;
    }

    /// Solve closed-form rows angle by angle's program: the angles of each program
    /// together (in SIMD lanes), then scattered into their rows of `out`.
    pub(super) fn solve_rows(&self, angles: &[f64], sel: &[usize], out: &mut Out<'_>) {
        let m = sel.len();
        let analogs = !out.vel.is_empty();
        let mut groups = vec![Vec::new(); self.programs.len()];
        for (i, &phi) in angles.iter().enumerate() {
            groups[self.index(phi)].push(i);
        }
        for (prog, rows) in self.programs.iter().zip(&groups) {
            if rows.is_empty() {
                continue;
            }
            let sub: Vec<f64> = rows.iter().map(|&i| angles[i]).collect();
            let mut got = Rows::new(rows.len(), m, analogs);
            prog.solve_rows(&sub, sel, &mut got.out());
            for (r, &i) in rows.iter().enumerate() {
                let (to, from) = (i * m..(i + 1) * m, r * m..(r + 1) * m);
                out.xy[to.clone()].copy_from_slice(&got.xy[from.clone()]);
                if analogs {
                    out.vel[to.clone()].copy_from_slice(&got.vel[from.clone()]);
                    out.acc[to].copy_from_slice(&got.acc[from]);
                }
                out.ok[i] = got.ok[r];
                out.singular[i] = got.singular[r];
                out.branch[i] = got.branch[r];
            }
        }
    }
}

/// The quantity whose extremum at the sum or difference of the radii is a change
/// point, its derivative by the crank angle (NaN without analogs: `vel` empty), and
/// the group's h² and radius² there; None for steps without an assembly side or
/// where the anchors coincide.
fn gap(step: &Step, xy: &[V2], vel: &[V2], acc: &[V2]) -> Option<[f64; 4]> {
    match *step {
        Step::Circles { a, b, ra, rb, .. } => {
            // The anchors' distance l, l' = d·d'/l, and h² as the closed form takes it.
            let d = sub(xy[b], xy[a]);
            let dd = dot(d, d);
            let l = dd.sqrt();
            if l.is_nan() || l <= 0.0 {
                return None;
            }
            let x = (ra * ra - rb * rb + dd) * (0.5 * (1.0 / l));
            let dl = if vel.is_empty() {
                f64::NAN
            } else {
                dot(d, sub(vel[b], vel[a])) / l
            };
            Some([l, dl, ra * ra - x * x, ra * ra])
        }
        Step::Slide { a, r, line, .. } => {
            // The anchor's offset from the guide, off = E × (a − o)/|E|, and its
            // derivative with the guide's own analogs.
            let ln = if vel.is_empty() {
                line.at::<false>(xy, vel, acc)
            } else {
                line.at::<true>(xy, vel, acc)
            };
            let ee = dot(ln.e, ln.e);
            let el = ee.sqrt();
            if el.is_nan() || el <= 0.0 {
                return None;
            }
            let ao = sub(xy[a], ln.o);
            let c = cross(ln.e, ao);
            let off = c / el;
            let doff = if vel.is_empty() {
                f64::NAN
            } else {
                let ao1 = sub(vel[a], ln.o1);
                (cross(ln.e1, ao) + cross(ln.e, ao1)) / el - c * dot(ln.e, ln.e1) / (ee * el)
            };
            // As the closed form: the unit direction, then the cross product.
            let e = [ln.e[0] / el, ln.e[1] / el];
            let o = cross(e, ao);
            Some([off, doff, r * r - o * o, r * r])
        }
        _ => None,
    }
}

impl Program {
    /// The change points of this linkage's class II groups over one crank turn from
    /// the drawn angle (see the module [`super::change`] for the rule): which
    /// group, where, and whether the motion follows it smoothly.
    ///
    /// # Errors
    /// As [`Program::solve`] for an invalid program.
    pub fn change_points(&self) -> Result<Vec<ChangePoint>, LinkageError> {
        self.validate()?;
        Ok(self.branches()?.points)
    }

    /// Find the change points and the programs that hold between the followed ones.
    pub(super) fn branches(&self) -> Result<Branches, LinkageError> {
        let phi0 = self.drawn.as_ref().map_or(0.0, |d| d.0);
        let mut br = Branches::none(phi0);
        let held = self.held_pairs();
        let sided: Vec<usize> = (0..self.steps.len())
            .filter(|&s| match self.steps[s] {
                // A further joint of a rigid body: its anchors' distance is fixed,
                // so its h never changes and it has no change point.
                Step::Circles { a, b, .. } => !held.contains(&(a.min(b), a.max(b))),
                Step::Slide { .. } => true,
                _ => false,
            })
            .collect();
        if sided.is_empty() {
            return Ok(br);
        }
        let mut next = 0;
        // Groups ahead of the first class III group read only closed-form points:
        // searched on the program cut there, in lanes, not along a path.
        let first = self
            .steps
            .iter()
            .position(|s| matches!(s, Step::Triad { .. }));
        if let Some(cut) = first.filter(|&c| sided[0] < c) {
            let head = Program {
                n_points: self.n_points,
                fixed: self.fixed.clone(),
                steps: self.steps[..cut].to_vec(),
                drawn: self.drawn.clone(),
            };
            br.points = head.branches()?.points;
            br.rebuild(self);
            next = sided.partition_point(|&s| s < cut);
        }
        while next < sided.len() {
            let scan = self.scan(&br)?;
            while next < sided.len() {
                let s = sided[next];
                next += 1;
                let found = self.extrema(&br, &scan, s);
                if found.is_empty() {
                    continue;
                }
                let followed = found.len().is_multiple_of(2);
                br.points
                    .extend(found.iter().map(|&(phi, window)| ChangePoint {
                        step: s,
                        phi,
                        followed,
                        window,
                    }));
                if followed {
                    br.rebuild(self);
                    // Downstream groups now read the flipped positions: scan again.
                    break;
                }
            }
        }
        Ok(br)
    }

    /// The pairs of points (lower index first) whose distance the program holds
    /// fixed: both fixed, the crank's pivot and tip, a joint and each anchor of the
    /// circles that place it (or the slider's pivot, the aimed link's), and a class
    /// III group's arms and sides.
    pub(super) fn held_pairs(&self) -> Vec<(usize, usize)> {
        let pair = |x: usize, y: usize| (x.min(y), x.max(y));
        let mut held = Vec::new();
        for (i, &(x, _)) in self.fixed.iter().enumerate() {
            for &(y, _) in &self.fixed[i + 1..] {
                held.push(pair(x, y));
            }
        }
        for step in &self.steps {
            match *step {
                Step::Driver { pivot, tip, .. } => held.push(pair(pivot, tip)),
                Step::Circles { a, b, p, .. } => held.extend([pair(a, p), pair(b, p)]),
                Step::Slide { a, p, .. } => held.push(pair(a, p)),
                Step::Aim { b, c, .. } => held.push(pair(b, c)),
                Step::Triad {
                    anchors, joints, ..
                } => {
                    for i in 0..3 {
                        held.push(pair(anchors[i], joints[i]));
                        held.push(pair(joints[i], joints[(i + 1) % 3]));
                    }
                }
                _ => {}
            }
        }
        held
    }

    /// Every point at the scan's crank angles (with the flips so far; with the
    /// analogs too where class III groups need them to continue from a sample),
    /// and whether each angle assembles.
    fn scan(&self, br: &Branches) -> Result<Scan, LinkageError> {
        let p = self.n_points;
        let path = self.has_triads();
        let n = if path { SCAN_PATH } else { SCAN };
        let angles: Vec<f64> = (0..n)
            .map(|j| br.phi0 + TAU * j as f64 / n as f64)
            .collect();
        let all: Vec<usize> = (0..p).collect();
        let mut rows = Rows::new(n, p, path);
        self.solve_unflagged(br, &angles, &all, &mut rows.out())?;
        Ok(Scan { angles, rows })
    }

    /// The change points of step `s`: each extremum of its gap, bracketed by the
    /// scan's samples (a sign change of its differences) and put by Brent's method
    /// on its derivative, where the group's h² is within the fold's floor.
    fn extrema(&self, br: &Branches, scan: &Scan, s: usize) -> Vec<(f64, f64)> {
        let (p, n) = (self.n_points, scan.angles.len());
        let row = |j: usize| j * p..(j + 1) * p;
        let step = &self.steps[s];
        let path = !scan.rows.vel.is_empty();
        let g: Vec<Option<[f64; 4]>> = (0..n)
            .map(|j| {
                let r = row(j);
                let (v, a) = if path {
                    (&scan.rows.vel[r.clone()], &scan.rows.acc[r.clone()])
                } else {
                    (&[][..], &[][..])
                };
                if scan.rows.ok[j] {
                    gap(step, &scan.rows.xy[r], v, a)
                } else {
                    None
                }
            })
            .collect();
        // A gap constant over the turn (a coupler point: both anchors on its body)
        // has no extremum, only round-off.
        let vals: Vec<f64> = g.iter().flatten().map(|v| v[0]).collect();
        let (lo, hi) = vals
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
                (l.min(v), h.max(v))
            });
        if vals.is_empty() || hi - lo <= 1e-12 * hi.abs().max(lo.abs()) {
            return vec![];
        }
        let dphi = TAU / n as f64;
        let mut found: Vec<(f64, f64)> = Vec::new();
        let mut state = State::new(self.n_points);
        for j in 0..n {
            let (i0, i2) = ((j + n - 1) % n, (j + 1) % n);
            let (Some(g0), Some(g1), Some(g2)) = (g[i0], g[j], g[i2]) else {
                continue;
            };
            let (d1, d2) = (g1[0] - g0[0], g2[0] - g1[0]);
            if (d1 > 0.0) == (d2 > 0.0) || (d1 == 0.0 && d2 == 0.0) {
                continue;
            }
            let mid = scan.angles[j];
            let (a, b) = (mid - dphi, mid + dphi);
            // The gap's derivative at a trial angle, from the closed form (or, with
            // class III groups, continued from sample j, at most one sample away).
            let eval = |phi: f64, st: &mut State| -> Option<[f64; 4]> {
                let prog = br.at(self, phi);
                let r = row(j);
                let prev = path.then(|| Prev {
                    xy: &scan.rows.xy[r.clone()],
                    vel: &scan.rows.vel[r.clone()],
                    acc: &scan.rows.acc[r],
                    dphi: phi - mid,
                    seek: Seek::Follow,
                });
                let pose: Pose =
                    prog.solve_one::<true>(phi, &mut st.xy, &mut st.vel, &mut st.acc, prev);
                if pose.ok {
                    gap(&prog.steps[s], &st.xy, &st.vel, &st.acc).filter(|v| v[1].is_finite())
                } else {
                    None
                }
            };
            let (Some(fa), Some(fb)) = (eval(a, &mut state), eval(b, &mut state)) else {
                continue;
            };
            if (fa[1] <= 0.0) == (fb[1] <= 0.0) {
                continue;
            }
            let mut failed = false;
            let root = crate::cam::brent_zero(
                |phi| match eval(phi, &mut state) {
                    Some(v) => v[1],
                    None => {
                        failed = true;
                        0.0
                    }
                },
                a,
                b,
                fa[1],
                fb[1],
                0.0,
                4.0 * f64::EPSILON,
            );
            if failed {
                continue;
            }
            if let Some(v) = eval(root, &mut state) {
                if v[2].abs() <= FOLD_H2_REL * v[3] {
                    // h grows about linearly away from it: its slope from the
                    // bracket's end farther from the change point.
                    let (far, at) = if root - a > b - root {
                        (fa, a)
                    } else {
                        (fb, b)
                    };
                    let slope = far[2].max(0.0).sqrt() / (root - at).abs();
                    let window = (NEAR_H_REL * v[3].sqrt() / slope).min(MAX_WINDOW);
                    let phi = br.phi0 + (root - br.phi0).rem_euclid(TAU);
                    let phi = if phi >= br.phi0 + TAU { br.phi0 } else { phi };
                    let window = if window.is_finite() {
                        window
                    } else {
                        MAX_WINDOW
                    };
                    if !found.iter().any(|f| (f.0 - phi).abs() <= 1e-9) {
                        found.push((phi, window));
                    }
                }
            }
        }
        found.sort_by(|x, y| x.0.total_cmp(&y.0));
        found
    }
}
