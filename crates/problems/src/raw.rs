//! What every reader of a problem file shares: the problem as a file holds
//! it, before its row layout is resolved, and the checks made before a file
//! is read.

use std::path::Path;

use faer::Mat;

/// What a file holds before its layout is resolved.
pub(crate) struct Raw {
    pub w: Mat<f64>,
    pub q: Vec<f64>,
    pub mu: Option<Vec<f64>>,
    pub dim: Option<f64>,
    pub normal_first: bool,
}

/// Copies of an array a stand-alone solve holds at once: its bytes, their
/// f64 values, the dense matrix and the solver's working copies.
pub(crate) const NPY_COPIES: u64 = 4;

/// Refuses a device or a pipe: reading it may not end, nor fit in memory.
pub fn regular_file(path: &Path) -> Result<(), String> {
    match std::fs::metadata(path) {
        Ok(m) if !m.is_file() => Err(format!(
            "cannot read {}: not a regular file",
            path.display()
        )),
        _ => Ok(()),
    }
}
