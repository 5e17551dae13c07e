//! What a run hands to its output: each body's mesh and fields
//! ([`BodyResult`], [`StepFields`]), the report and the contact rows
//! ([`RunOutput`]), and what the scene's `[output]` asks for
//! ([`OutputRequest`]). The writers (`output`, `stream`, `pieces`) read
//! these; this module reads none of them.

use crate::{ContactRow, Report};

/// The fields of one body at one load step.
#[derive(Clone)]
pub struct StepFields {
    /// Displacement, `dim` values per node.
    pub displacement: Vec<f64>,
    /// Per cell: Voigt [sxx, syy, szz, sxy, syz, sxz] (axisymmetric: x = r,
    /// y = z, szz = the hoop stress); see `signorini_fem::cell_stress`. Empty
    /// unless `[output] fields` has "stress".
    pub stress: Vec<[f64; 6]>,
    /// Per cell: von Mises equivalent stress.
    pub von_mises: Vec<f64>,
}

/// One body's mesh and its fields at the load steps kept in memory: every
/// step that writes fields for the library's `run`, the last step alone for
/// a run that streamed its steps to a [`crate::stream::FieldWriter`].
pub struct BodyResult {
    pub name: String,
    /// The stem of the body's output files (`<stem>_<step>.vtu`, its
    /// pieces' `pieces/<stem>_<step>_s<part>.vtu`): the name made safe for
    /// a file name by the caller, which knows the naming rule.
    pub file_stem: String,
    pub coords: Vec<[f64; 3]>,
    pub cells: Vec<Vec<usize>>,
    /// METIS part of each cell.
    pub parts: Vec<usize>,
    /// The fields at the steps kept (at least one; the last is the last
    /// load step).
    pub history: Vec<StepFields>,
}

impl BodyResult {
    /// The fields at the last load step.
    pub fn last(&self) -> &StepFields {
        self.history
            .last()
            .expect("a body result holds at least one step")
    }
}

/// Everything a run hands to its output.
pub struct RunOutput {
    pub report: Report,
    pub contact_rows: Vec<ContactRow>,
    pub bodies: Vec<BodyResult>,
}

/// What the scene's `[output]` asks for.
pub struct OutputRequest {
    /// 2 or 3.
    pub dim: usize,
    /// `[output] fields`: "displacement", "contact", "stress".
    pub fields: Vec<String>,
}

impl OutputRequest {
    /// Whether `fields` asks for that field.
    pub fn wants(&self, field: &str) -> bool {
        self.fields.iter().any(|f| f == field)
    }
}
