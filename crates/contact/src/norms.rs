//! The largest entry of a residual, for stopping tests and certificates.
//!
//! `f64::max` drops a NaN (`0.0f64.max(NaN)` is 0), so a fold of it reads
//! an iterate that has broken down into NaN as a zero residual: a
//! "converged" answer made of NaN. These keep the NaN, and every test of
//! the form `residual <= tolerance` then fails as it should.

/// max(a, b), NaN when either is NaN.
pub fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// |min(a, b)|, the natural map of a complementarity pair (a, b ≥ 0,
/// a b = 0 exactly when it is zero), NaN when either is NaN (`f64::min`
/// would return the other).
pub fn natural_map(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.min(b).abs()
    }
}

/// ‖v‖∞ = max |v_i| (0 for an empty v), NaN when some v_i is NaN.
pub fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |a, x| nan_max(a, x.abs()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_nan_entry_is_not_a_zero_residual() {
        assert_eq!(max_abs(&[1.0, -3.0, 2.0]), 3.0);
        assert_eq!(max_abs(&[]), 0.0);
        assert!(max_abs(&[1.0, f64::NAN, 2.0]).is_nan());
        assert!(max_abs(&[f64::NAN]).is_nan());
        assert_eq!(max_abs(&[1.0, f64::NEG_INFINITY]), f64::INFINITY);
        assert!(nan_max(f64::NAN, 1.0).is_nan() && nan_max(1.0, f64::NAN).is_nan());
        assert_eq!(max_abs(&[0.0, f64::NAN]).partial_cmp(&1e-10), None);
        assert_eq!(natural_map(2.0, -3.0), 3.0);
        assert!(natural_map(f64::NAN, 1.0).is_nan() && natural_map(1.0, f64::NAN).is_nan());
    }
}
