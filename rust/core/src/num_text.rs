//! Numbers in error messages: Rust prints an f64 in full decimal (1e-300 as "0."
//! and 299 zeros), so a message shows [`Num`]: the shortest text that reads back
//! as the same number, in exponent form below 1e-4 and from 1e16 in magnitude.

use std::fmt;

/// An f64 as a message shows it (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Num(pub f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.0;
        if v != 0.0 && v.is_finite() && !(1e-4..1e16).contains(&v.abs()) {
            write!(f, "{v:e}")
        } else {
            write!(f, "{v}")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_and_exact() {
        let cases = [
            (0.5, "0.5"),
            (-0.15, "-0.15"),
            (0.0, "0"),
            (1e-4, "0.0001"),
            (9.9e-5, "9.9e-5"),
            (1e-300, "1e-300"),
            (4.073646351193825e-151, "4.073646351193825e-151"),
            (1.6058642532916657e22, "1.6058642532916657e22"),
            (123456.0, "123456"),
            (f64::NAN, "NaN"),
            (f64::NEG_INFINITY, "-inf"),
        ];
        for (v, want) in cases {
            let text = Num(v).to_string();
            assert_eq!(text, want);
            // Reads back as the same number (NaN as NaN).
            let back: f64 = text.parse().unwrap();
            assert!(back == v || (back.is_nan() && v.is_nan()), "{text}");
        }
    }
}
