//! The end of each load step on the root, on both paths ("many
//! load steps in flat memory"): the step's certificate, report and contact
//! rows; its fields (displacement, and stresses when asked for) handed to
//! the run's [`StepSink`] when `[output] steps` selects the step; the lowest
//! gaps of the points left out of the contact zone; and the last step's
//! displacement and fields kept for the report (probes, displacement.csv,
//! stress.csv). Nothing of a step's per-DOF data outlives it otherwise, so
//! the memory of a run does not grow with its number of steps. With
//! `[output] pieces`, the step's contact values for the subdomains' pieces
//! (pieces.rs).

use crate::certify::{conclude_step, empty_partial, StepEvidence};
use crate::checks::inf_norm;
use crate::error::SolveError;
use crate::model::BodyModel;
use crate::partition;
use crate::step::{Partial, Residuals, StepSolution};
use signorini_report::results::{BodyResult, StepFields};
use signorini_report::stream::{StepResults, StepSink};
use signorini_scene as scene;

/// What the root keeps over the load steps of one solve.
pub(crate) struct StepLoop<'a> {
    sc: &'a scene::Scene,
    model: &'a partition::ModelData,
    sink: &'a mut dyn StepSink,
    /// The scales of every step, for its report.
    scales: Vec<std::collections::BTreeMap<String, f64>>,
    pub partial: Partial,
    /// The contact values of the last step that wrote fields, for the
    /// pieces (`[output] pieces`).
    pub nodal: Vec<signorini_report::pieces::NodalContact>,
    /// Whether the root writes every subdomain's piece (the direct path).
    pub all_pieces: bool,
}

impl<'a> StepLoop<'a> {
    pub(crate) fn new(
        sc: &'a scene::Scene,
        model: &'a partition::ModelData,
        sink: &'a mut dyn StepSink,
    ) -> Self {
        let mut partial = empty_partial();
        partial.bodies = body_meshes(&model.bodies);
        partial.excluded_gaps = vec![f64::INFINITY; model.excluded.len()];
        if crate::pieces::wanted(sc) {
            sink.pieces_of(&crate::pieces::subdomains(model));
        }
        StepLoop {
            sc,
            model,
            sink,
            scales: sc.step_scales(),
            partial,
            nodal: Vec::new(),
            all_pieces: false,
        }
    }

    /// The sink of the run's steps.
    pub(crate) fn sink(&mut self) -> &mut dyn StepSink {
        &mut *self.sink
    }

    /// Ends load step `si` from its solution `sol`, final gaps, residuals
    /// and the full displacement of every body (`u_full`, Cartesian, every
    /// DOF): the certificate (against the step's own largest displacement),
    /// the report and the contact rows, the fields to the sink, and the last
    /// step kept.
    pub(crate) fn end_step(
        &mut self,
        si: usize,
        sol: &StepSolution,
        gaps: &[f64],
        res: &Residuals,
        u_full: Vec<Vec<f64>>,
        messages: &mut Vec<String>,
    ) -> Result<(), SolveError> {
        let (sc, model) = (self.sc, self.model);
        let umax = u_full.iter().fold(0.0f64, |a, u| a.max(inf_norm(u)));
        let step = StepEvidence {
            sol,
            gaps,
            res,
            umax,
            scale: &self.scales[si],
        };
        let partial = &mut self.partial;
        conclude_step(
            sc,
            &model.bodies,
            &model.points,
            si,
            &step,
            partial,
            messages,
        );
        let excluded = crate::model::gaps_of(&model.excluded, &u_full);
        for (low, g) in partial.excluded_gaps.iter_mut().zip(excluded) {
            *low = low.min(g);
        }
        let n = self.scales.len();
        let last = si + 1 == n;
        let selected = sc.output.steps.selects(si + 1, n);
        let fields = (selected || last).then(|| step_fields(sc, &model.bodies, &u_full));
        let rows = std::mem::take(&mut partial.contact_rows);
        let results = StepResults {
            step: si + 1,
            bodies: &partial.bodies,
            fields: fields.as_deref().filter(|_| selected),
            rows: &rows,
        };
        self.sink.step(results).map_err(SolveError::Internal)?;
        if selected && crate::pieces::wanted(sc) {
            self.nodal = signorini_report::pieces::NodalContact::of_rows(&rows, si + 1);
            if self.all_pieces {
                crate::pieces::write_all(sc, model, &u_full, si + 1, &self.nodal, self.sink)
                    .map_err(SolveError::Internal)?;
            }
        }
        if let (true, Some(fields)) = (last, fields) {
            for (b, f) in partial.bodies.iter_mut().zip(fields) {
                b.history = vec![f];
            }
            partial.u_last = u_full;
        }
        Ok(())
    }
}

/// Each body's mesh for the output, without fields yet.
fn body_meshes(bodies: &[BodyModel]) -> Vec<BodyResult> {
    bodies
        .iter()
        .map(|b| BodyResult {
            name: b.name.clone(),
            file_stem: scene::file_stem(&b.name),
            coords: b.mesh.coords.clone(),
            cells: b.mesh.cells.iter().map(|c| c.nodes.clone()).collect(),
            parts: b.parts.clone(),
            history: Vec::new(),
        })
        .collect()
}

/// Each body's fields at one step: its displacement, and the cell stresses
/// with their von Mises values when the scene asks for them.
fn step_fields(sc: &scene::Scene, bodies: &[BodyModel], u_full: &[Vec<f64>]) -> Vec<StepFields> {
    let want_stress = sc.output.wants("stress");
    bodies
        .iter()
        .zip(u_full)
        .map(|(b, u)| {
            let stress = if want_stress {
                signorini_fem::cell_stress(&b.mesh, &b.material, u)
            } else {
                Vec::new()
            };
            StepFields {
                von_mises: stress.iter().map(signorini_fem::von_mises).collect(),
                displacement: u.clone(),
                stress,
            }
        })
        .collect()
}
