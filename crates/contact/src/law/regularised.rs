//! The regularised Coulomb law (course notes §4.1.3): before it slips, a
//! point slides elastically, λ_t = −k_e s_e, with the slip stiffness k_e (a
//! force per unit slip). The elastic slip adds the compliance 1/k_e to the
//! diagonal of the tangential rows of W
//! ([`crate::DelassusProblem::add_compliance`]) or of the whole system's
//! contact block; the threshold is Coulomb's.

/// The compliance 1/k_e on the diagonal of `n_rows` contact rows: for each
/// point, its slip stiffness (`None`: no elastic slip) and the rows of its
/// tangential forces; zero on every other row.
pub fn slip_compliance(
    n_rows: usize,
    points: impl IntoIterator<Item = (Option<f64>, [Option<usize>; 2])>,
) -> Vec<f64> {
    let mut compliance = vec![0.0; n_rows];
    for (stiffness, rows) in points {
        if let Some(k) = stiffness {
            for t in rows.into_iter().flatten() {
                compliance[t] = 1.0 / k;
            }
        }
    }
    compliance
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_compliance_is_one_over_the_stiffness_on_tangential_rows_only() {
        let points = [
            (Some(4.0), [Some(2), Some(3)]),
            (None, [Some(4), None]),
            (Some(0.5), [Some(5), None]),
        ];
        let c = slip_compliance(6, points);
        assert_eq!(c, vec![0.0, 0.0, 0.25, 0.25, 0.0, 2.0]);
    }
}
