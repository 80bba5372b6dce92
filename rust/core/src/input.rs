//! The caller's mistakes that every domain can make, said one way.
//!
//! A scalar outside the values its key takes, a NaN or an infinity in an array,
//! a bad thread count and an output array a kernel cannot fill in place are the
//! same mistake in every domain, so they are one type, [`InvalidInput`]. Each
//! domain's error enum wraps it as `Input(InvalidInput)` (shown as it is, with
//! `#[error(transparent)]`) beside the variants only that domain has, and
//! [`wraps_invalid_input`] gives it the `From` impls so that `?` works on both
//! an `InvalidInput` and a [`ThreadsError`]. The bindings map this type to
//! Python's `InputError` once, whichever domain it comes from.
//!
//! The texts are a public contract: users match on them and results folders
//! record them (`tests/test_error_messages.py` pins each one, domain by domain).

use std::borrow::Cow;

use crate::num_text::Num;
use crate::parallel::ThreadsError;

/// An input no kernel can use, whatever its domain (module docs).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InvalidInput {
    /// A scalar (or a count, as an f64) outside the values its key takes:
    /// `why` says which are valid and may start with the unit, as in
    /// "omega = NaN [rad/s] must be finite".
    #[error("{field} = {} {why}", Num(*value))]
    BadValue {
        field: &'static str,
        value: f64,
        why: Cow<'static, str>,
    },
    /// An entry of an array that is NaN or infinite.
    #[error("{field}[{index}] = {value} is not finite")]
    NotFinite {
        field: &'static str,
        index: usize,
        value: f64,
    },
    /// A caller's output array (`out=`) that the kernel cannot fill in place:
    /// `want` says what it must be, `got` what it is.
    #[error("{field} must be {want}; got {got}")]
    Output {
        field: &'static str,
        want: String,
        got: String,
    },
    /// `n_threads=` or `CYCLOMECH_THREADS` (the thread pools of [`crate::parallel`]).
    #[error(transparent)]
    Threads(#[from] ThreadsError),
}

impl InvalidInput {
    /// [`InvalidInput::BadValue`]: `field = value why`.
    pub fn bad_value(field: &'static str, value: f64, why: impl Into<Cow<'static, str>>) -> Self {
        InvalidInput::BadValue {
            field,
            value,
            why: why.into(),
        }
    }

    /// Every entry of `values` finite, else [`InvalidInput::NotFinite`] at the first
    /// one that is not.
    pub fn check_finite(field: &'static str, values: &[f64]) -> Result<(), InvalidInput> {
        match values.iter().position(|v| !v.is_finite()) {
            None => Ok(()),
            Some(index) => Err(InvalidInput::NotFinite {
                field,
                index,
                value: values[index],
            }),
        }
    }
}

/// `From<InvalidInput>` is the domain's `Input(#[from] InvalidInput)`; this adds
/// `From<ThreadsError>` (through [`InvalidInput::Threads`]), which thiserror cannot
/// derive twice on one variant, so that `pool(resolve_threads(n)?)?` works in
/// every kernel of the domain.
macro_rules! wraps_invalid_input {
    ($($domain:ty),+ $(,)?) => {$(
        impl From<$crate::parallel::ThreadsError> for $domain {
            fn from(e: $crate::parallel::ThreadsError) -> Self {
                Self::Input($crate::input::InvalidInput::Threads(e))
            }
        }
    )+};
}
pub(crate) use wraps_invalid_input;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_variant_says_what_is_wrong_and_what_is_valid() {
        let cases = [
            (
                InvalidInput::bad_value("omega", f64::NAN, "[rad/s] must be finite"),
                "omega = NaN [rad/s] must be finite",
            ),
            (
                InvalidInput::bad_value("delta", 1e-300, format!("must be > {}", 0)),
                "delta = 1e-300 must be > 0",
            ),
            (
                InvalidInput::check_finite("x", &[0.0, 1.0, f64::INFINITY, f64::NAN]).unwrap_err(),
                "x[2] = inf is not finite",
            ),
            (
                InvalidInput::Output {
                    field: "out",
                    want: "an array of shape (2,)".into(),
                    got: "shape (3,)".into(),
                },
                "out must be an array of shape (2,); got shape (3,)",
            ),
            (
                ThreadsError::BadCount { value: 0, max: 8 }.into(),
                "n_threads must be an integer between 1 and 8; got 0",
            ),
        ];
        for (error, want) in cases {
            assert_eq!(error.to_string(), want);
        }
        assert_eq!(InvalidInput::check_finite("x", &[0.0, -1e308]), Ok(()));
        assert_eq!(InvalidInput::check_finite("x", &[]), Ok(()));
    }
}
