//! Non-dominated (Pareto) filtering of objective vectors, lower is better.

/// Errors of the Pareto filter.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParetoError {
    #[error("points[{row}, {col}] = {value} is NaN; objectives must be numbers (inf is allowed)")]
    NaN { row: usize, col: usize, value: f64 },
    #[error("points has {len} values, not a whole number of rows of {m} objectives")]
    Shape { len: usize, m: usize },
}

/// True for every row of `points` (n rows of `m` objectives, row-major) that no
/// other row dominates: no other row is lower or equal in every objective and
/// lower in one. Equal rows do not dominate each other.
///
/// Rows are visited in order of their sum, so a row's dominators come before it
/// and only the front found so far is compared against: O(n·front·m).
pub fn pareto_mask(points: &[f64], m: usize) -> Result<Vec<bool>, ParetoError> {
    if m == 0 || !points.len().is_multiple_of(m) {
        return Err(ParetoError::Shape {
            len: points.len(),
            m,
        });
    }
    if let Some(i) = points.iter().position(|v| v.is_nan()) {
        return Err(ParetoError::NaN {
            row: i / m,
            col: i % m,
            value: points[i],
        });
    }
    let n = points.len() / m;
    let row = |i: usize| &points[i * m..(i + 1) * m];
    let sum = |i: usize| row(i).iter().sum::<f64>();
    let mut order: Vec<(f64, usize)> = (0..n).map(|i| (sum(i), i)).collect();
    // A sum of +inf and -inf is NaN: such rows go last (total_cmp orders NaN high).
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let dominates = |a: &[f64], b: &[f64]| {
        let mut strict = false;
        for (x, y) in a.iter().zip(b) {
            if x > y {
                return false;
            }
            strict |= x < y;
        }
        strict
    };
    let mut keep = vec![false; n];
    let mut front: Vec<usize> = Vec::new();
    for &(_, i) in &order {
        let p = row(i);
        if !front.iter().any(|&f| dominates(row(f), p)) {
            // A later row may still dominate an earlier one only when sums tie
            // or are not finite; drop those from the front.
            front.retain(|&f| {
                let gone = dominates(p, row(f));
                if gone {
                    keep[f] = false;
                }
                !gone
            });
            keep[i] = true;
            front.push(i);
        }
    }
    Ok(keep)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn brute(points: &[f64], m: usize) -> Vec<bool> {
        let n = points.len() / m;
        let row = |i: usize| &points[i * m..(i + 1) * m];
        (0..n)
            .map(|i| {
                !(0..n).any(|j| {
                    j != i
                        && row(j).iter().zip(row(i)).all(|(a, b)| a <= b)
                        && row(j).iter().zip(row(i)).any(|(a, b)| a < b)
                })
            })
            .collect()
    }

    proptest! {
        #[test]
        fn matches_the_quadratic_definition(
            m in 1usize..5,
            raw in proptest::collection::vec(0u8..6, 0..240),
        ) {
            let n = raw.len() / m;
            let pts: Vec<f64> = raw[..n * m].iter().map(|&v| v as f64).collect();
            prop_assert_eq!(pareto_mask(&pts, m).unwrap(), brute(&pts, m));
        }
    }

    #[test]
    fn infinities_and_bad_input() {
        let pts = [f64::INFINITY, 0.0, 0.0, f64::NEG_INFINITY, 1.0, 1.0];
        assert_eq!(pareto_mask(&pts, 2).unwrap(), brute(&pts, 2));
        assert!(pareto_mask(&[1.0, f64::NAN], 2).is_err());
        assert!(pareto_mask(&[1.0, 2.0, 3.0], 2).is_err());
    }
}
