//! The contact rows of B on some set of unknowns (the global free DOFs of
//! the direct path, Γ of the condensed path): every point's normal row, then
//! the tangential rows t1 (and t2) of each frictional point, with where each
//! point's tangential rows are.

use crate::model::PointModel;
use signorini_linalg::sparse::SparseRow;

/// The rows of B, normal rows first (row p of point p), then the points'
/// tangential rows in the points' order.
pub(crate) struct ContactRows {
    pub rows: Vec<SparseRow>,
    /// The row of each point's first tangent t1, if it has friction.
    pub tangent_row: Vec<Option<usize>>,
    /// The row of each point's second tangent t2 (3D), if it has friction.
    pub tangent_row2: Vec<Option<usize>>,
}

impl ContactRows {
    /// The rows of `points`, each (body, DOF, coefficient) row taken to the
    /// unknowns by `to_row`.
    pub(crate) fn of(
        points: &[PointModel],
        to_row: impl Fn(&[(usize, usize, f64)]) -> SparseRow,
    ) -> ContactRows {
        let mut rows: Vec<SparseRow> = points.iter().map(|p| to_row(&p.row)).collect();
        let m = points.len();
        let (mut tangent_row, mut tangent_row2) = (vec![None; m], vec![None; m]);
        for (pi, p) in points.iter().enumerate() {
            if let Some(t) = &p.trow {
                tangent_row[pi] = Some(rows.len());
                rows.push(to_row(t));
            }
            if let Some(t) = &p.trow2 {
                tangent_row2[pi] = Some(rows.len());
                rows.push(to_row(t));
            }
        }
        ContactRows {
            rows,
            tangent_row,
            tangent_row2,
        }
    }
}
