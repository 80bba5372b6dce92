//! Criteria over a Cartesian grid of designs, in parallel: each pin path
//! sampled once and reused for every rod length.

use rayon::prelude::*;

use crate::parallel::{pool, resolve_threads};

use super::criteria::{criteria_with, PinScan, Spec, CRITERIA};
use super::kinematics::{Design, PressError, Table};

/// The axes of a design grid, designs in C order (R, r, d, L, φ0).
pub struct Grid<'a> {
    pub big_r: &'a [f64],
    pub r: &'a [f64],
    pub d: &'a [f64],
    pub l: &'a [f64],
    pub phi0: &'a [f64],
    pub offset: f64,
}

impl Grid<'_> {
    pub fn len(&self) -> usize {
        self.big_r.len() * self.r.len() * self.d.len() * self.l.len() * self.phi0.len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn design(&self, flat: usize) -> Design {
        let (np, nl, nd, nr) = (self.phi0.len(), self.l.len(), self.d.len(), self.r.len());
        let ip = flat % np;
        let il = (flat / np) % nl;
        let id = (flat / (np * nl)) % nd;
        let ir = (flat / (np * nl * nd)) % nr;
        let ib = flat / (np * nl * nd * nr);
        Design {
            big_r: self.big_r[ib],
            r: self.r[ir],
            d: self.d[id],
            l: self.l[il],
            phi0: self.phi0[ip],
            offset: self.offset,
        }
    }
}

/// Criteria over the full Cartesian grid: `rows` (designs × 14) and `status`
/// (designs), in parallel. Each pin path (R, r, d, φ0) is sampled once and
/// reused for every rod length L.
pub fn sweep_into(
    grid: &Grid<'_>,
    spec: &Spec,
    n_threads: Option<i64>,
    rows: &mut [f64],
    status: &mut [u8],
) -> Result<(), PressError> {
    spec.validate()?;
    let n = grid.len();
    let nc = CRITERIA.len();
    if rows.len() != n * nc || status.len() != n {
        return Err(PressError::BadSpec(
            "output sizes do not match the grid".into(),
        ));
    }
    if n == 0 {
        return Ok(());
    }
    // Validate every axis value (each with the first values of the other axes),
    // and build one table per gear ratio.
    let base = grid.design(0);
    // One table per gear ratio, and for every (R, r) pair (in grid order, one per
    // block of d values) the index of its table.
    let mut tables: Vec<(f64, Table)> = Vec::new();
    let mut table_at: Vec<usize> = Vec::with_capacity(grid.big_r.len() * grid.r.len());
    for &big_r in grid.big_r {
        for &r in grid.r {
            let ratio = Design { big_r, r, ..base }.validate()?;
            let k = match tables.iter().position(|(q, _)| *q == ratio) {
                Some(k) => k,
                None => {
                    tables.push((ratio, Table::new(ratio, spec.samples)));
                    tables.len() - 1
                }
            };
            table_at.push(k);
        }
    }
    for &d in grid.d {
        Design { d, ..base }.validate()?;
    }
    for &l in grid.l {
        Design { l, ..base }.validate()?;
    }
    for &phi0 in grid.phi0 {
        Design { phi0, ..base }.validate()?;
    }
    let (nl, np) = (grid.l.len(), grid.phi0.len());
    let block = nl * np;
    // Rows of one pin path (block b = (R, r, d), φ0 index p) for every L.
    let group = |b: usize, p: usize, scan: &mut PinScan| -> (Vec<f64>, Vec<u8>) {
        let design = grid.design(b * block + p);
        // Block b is (R, r, d) in C order: its (R, r) pair is b / len(d).
        let table = &tables[table_at[b / grid.d.len()]].1;
        let mut f = design.frame();
        scan.fill(&f, table);
        let mut out = vec![0.0; nl * nc];
        let mut st = vec![0u8; nl];
        for (il, (row, s)) in out.chunks_mut(nc).zip(st.iter_mut()).enumerate() {
            f.l = grid.l[il];
            *s = criteria_with(&f, table, spec, scan, row) as u8;
        }
        (out, st)
    };
    let place = |rb: &mut [f64], sb: &mut [u8], p: usize, (out, st): (Vec<f64>, Vec<u8>)| {
        for il in 0..nl {
            let q = il * np + p;
            rb[q * nc..(q + 1) * nc].copy_from_slice(&out[il * nc..(il + 1) * nc]);
            sb[q] = st[il];
        }
    };
    let threads = resolve_threads(n_threads)?;
    let blocks = rows
        .chunks_mut(block * nc)
        .zip(status.chunks_mut(block))
        .enumerate();
    if threads == 1 {
        let mut scan = PinScan::default();
        for (b, (rb, sb)) in blocks {
            for p in 0..np {
                if crate::cancel::requested() {
                    return Ok(());
                }
                let res = group(b, p, &mut scan);
                place(rb, sb, p, res);
            }
        }
    } else {
        let blocks: Vec<_> = blocks.collect();
        pool(threads)?.install(|| {
            blocks.into_par_iter().for_each(|(b, (rb, sb))| {
                if crate::cancel::requested() {
                    return;
                }
                let res: Vec<_> = (0..np)
                    .into_par_iter()
                    .map_init(PinScan::default, |scan, p| group(b, p, scan))
                    .collect();
                for (p, r) in res.into_iter().enumerate() {
                    place(rb, sb, p, r);
                }
            })
        });
    }
    Ok(())
}
