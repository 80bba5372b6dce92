//! The impact domain's error and the checks of its inputs.

use crate::input::InvalidInput;

/// Errors of the impact domain.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ImpactError {
    #[error("{field} must be {want}; got {}", crate::num_text::Num(*value))]
    Param {
        field: &'static str,
        value: f64,
        want: &'static str,
    },
    #[error("{field} must be {want}; got {value}")]
    Count {
        field: &'static str,
        value: i64,
        want: &'static str,
    },
    #[error("{field} must be a C-contiguous float64 array")]
    Layout { field: &'static str },
    #[error("{field}[{index}] must be finite; got {value}")]
    NotFinite {
        field: &'static str,
        index: usize,
        value: f64,
    },
    #[error(
        "{field} must be non-decreasing (a repeated time is a jump of the force); \
         got {field}[{index}] = {value} after {field}[{prev_index}] = {prev}"
    )]
    Decreasing {
        field: &'static str,
        index: usize,
        value: f64,
        prev_index: usize,
        prev: f64,
    },
    #[error(
        "{field}[{index}] - {field}[{prev_index}] = {value} - {prev} overflows; \
         times must differ by a finite amount"
    )]
    StepOverflow {
        field: &'static str,
        index: usize,
        value: f64,
        prev_index: usize,
        prev: f64,
    },
    #[error("{field} must have {want}; got {got}")]
    Length {
        field: &'static str,
        got: usize,
        want: String,
    },
    #[error(
        "a step h = {h} with omega_n = {omega_n} and zeta = {zeta} gives non-finite \
         coefficients; rescale time so that omega_n*h and zeta*omega_n*h stay below ~1e150"
    )]
    Range { h: f64, omega_n: f64, zeta: f64 },
    #[error(
        "the response overflows f64 (q or v is not finite at t = {time}); \
         forces or initial values are too large"
    )]
    Overflow { time: f64 },
    #[error("case {row}: {error}")]
    Case { row: usize, error: Box<ImpactError> },
    #[error(
        "the link chatters: more than max_events = {max_events} contact events before \
         t = {time}; raise max_events or sample a shorter time"
    )]
    TooManyEvents { max_events: usize, time: f64 },
    #[error(
        "the first-rebound search stopped advancing at t = {time} (q̇ stays within \
         rounding of zero); refine or rescale the pulse table"
    )]
    Stalled { time: f64 },
    #[error(transparent)]
    Input(#[from] InvalidInput),
}

crate::input::wraps_invalid_input!(ImpactError);

impl ImpactError {
    pub(super) fn case(row: usize) -> impl Fn(ImpactError) -> ImpactError {
        move |e| ImpactError::Case {
            row,
            error: Box::new(e),
        }
    }
}

pub(super) fn param(
    field: &'static str,
    value: f64,
    ok: bool,
    want: &'static str,
) -> Result<(), ImpactError> {
    if ok && value.is_finite() {
        Ok(())
    } else {
        Err(ImpactError::Param { field, value, want })
    }
}

/// The range of natural frequencies ω [rad/s] and damping rates ζω [1/s] the
/// closed forms hold in: ω², (ζω)², 1/ω² and the ramp's c = slope/(mω²) stay
/// finite with room to spare. Outside it the coefficients overflow or vanish and
/// the searches cannot advance; rescale time instead.
pub const MODE_RANGE: (f64, f64) = (1e-150, 1e150);

pub(super) fn mode_range(field: &'static str, omega: f64, zeta: f64) -> Result<(), ImpactError> {
    let (lo, hi) = MODE_RANGE;
    param(
        field,
        omega,
        (lo..=hi).contains(&omega),
        "within [1e-150, 1e150] rad/s (rescale time)",
    )?;
    let rate = zeta * omega;
    param(
        "zeta * omega",
        rate,
        rate <= hi,
        "<= 1e150 1/s (rescale time or lower the damping ratio)",
    )
}

pub(super) fn finite(field: &'static str, value: f64) -> Result<(), ImpactError> {
    param(field, value, true, "finite")
}

pub(super) fn length(
    field: &'static str,
    got: usize,
    want: usize,
    what: &str,
) -> Result<(), ImpactError> {
    if got == want {
        Ok(())
    } else {
        Err(ImpactError::Length {
            field,
            got,
            want: format!("{want} entries ({what})"),
        })
    }
}

/// Every value finite (one vectorised pass; the index only on failure).
pub(super) fn check_finite(field: &'static str, x: &[f64]) -> Result<(), ImpactError> {
    // An OR of flags, unlike a float sum, is associative: LLVM vectorises it.
    if x.iter().fold(0u8, |a, v| a | u8::from(!v.is_finite())) == 0 {
        return Ok(());
    }
    let index = x.iter().position(|v| !v.is_finite()).unwrap_or(0);
    Err(ImpactError::NotFinite {
        field,
        index,
        value: x[index],
    })
}

/// A time grid: at least one time, all finite, non-decreasing, finite steps.
pub(super) fn check_times(field: &'static str, t: &[f64]) -> Result<(), ImpactError> {
    if t.is_empty() {
        return Err(ImpactError::Length {
            field,
            got: 0,
            want: "at least 1 entry".into(),
        });
    }
    check_finite(field, t)?;
    match t.windows(2).position(|w| !step_ok(w[1] - w[0])) {
        None => Ok(()),
        Some(i) => Err(time_error(field, t, i + 1)),
    }
}

#[inline(always)]
pub(super) fn step_ok(h: f64) -> bool {
    h >= 0.0 && h.is_finite()
}

/// Why the step t[k] − t[k−1] is not a valid step.
#[cold]
pub(super) fn time_error(field: &'static str, t: &[f64], k: usize) -> ImpactError {
    for index in [k - 1, k] {
        if !t[index].is_finite() {
            return ImpactError::NotFinite {
                field,
                index,
                value: t[index],
            };
        }
    }
    let (index, value, prev_index, prev) = (k, t[k], k - 1, t[k - 1]);
    if value < prev {
        ImpactError::Decreasing {
            field,
            index,
            value,
            prev_index,
            prev,
        }
    } else {
        ImpactError::StepOverflow {
            field,
            index,
            value,
            prev_index,
            prev,
        }
    }
}
