//! Numbers in answers printed as text: every digit a double needs to read
//! back, positional where that is short and with an exponent where it is not
//! (a radius of 2e-151 would otherwise fill a line with zeros).

use std::fmt;

/// `x` in as few digits as read back to it.
pub struct Real(pub f64);

impl fmt::Display for Real {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let x = self.0;
        if x == 0.0 || !x.is_finite() || (1e-5..1e16).contains(&x.abs()) {
            write!(f, "{x}")
        } else {
            write!(f, "{x:e}")
        }
    }
}

/// `x` to `digits` places, or to `digits` significant digits where places
/// would show none or too many.
pub struct Rounded(pub f64, pub usize);

impl fmt::Display for Rounded {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Rounded(x, digits) = *self;
        if x == 0.0 || !x.is_finite() || (1e-3..1e16).contains(&x.abs()) {
            write!(f, "{x:.digits$}")
        } else {
            write!(f, "{x:.digits$e}")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_where_positional_is_short() {
        assert_eq!(Real(53.0).to_string(), "53");
        assert_eq!(Real(1000000000000064.0).to_string(), "1000000000000064");
        assert_eq!(
            Real(-2.745966692414834e-151).to_string(),
            "-2.745966692414834e-151"
        );
        assert_eq!(Real(1e300).to_string(), "1e300");
        assert_eq!(Rounded(0.43182, 4).to_string(), "0.4318");
        assert_eq!(Rounded(2.7e-151, 4).to_string(), "2.7000e-151");
    }
}
