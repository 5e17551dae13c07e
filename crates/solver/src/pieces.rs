//! `[output] pieces`: the VTU piece of every subdomain at each
//! step that writes fields, beside the gathered `<body>_<step>.vtu`. On the
//! condensed path the rank that owns a subdomain writes its piece from its
//! own recovery (its displacement, its cells' stresses computed there) and
//! the contact values the root sends; on the direct path the root writes
//! them all from the whole displacement. The root's sink writes the `.pvtu`
//! index (signorini_report::pieces).

use crate::partition;
use crate::subdomain::{RecoveredStep, SubdomainSpec};
use partition::ModelData;
use signorini_report::pieces::{ContactFields, NodalContact, SubdomainPiece};
use signorini_report::results::{BodyResult, StepFields};
use signorini_report::stream::StepSink;
use signorini_scene as scene;

/// Whether the scene writes pieces (`[output] pieces`, with some field).
pub(crate) fn wanted(sc: &scene::Scene) -> bool {
    sc.output.pieces && !sc.output.fields.is_empty()
}

/// Every subdomain that has cells, as (body, part): the pieces of the index.
pub(crate) fn subdomains(model: &ModelData) -> Vec<(usize, usize)> {
    (model.specs.iter())
        .filter(|s| !s.cells.is_empty())
        .map(|s| (s.body, s.part))
        .collect()
}

/// The piece of subdomain `spec` from `u`, the displacement of its nodes
/// (Cartesian, `dim` values per node), with the stresses of its cells when
/// the scene asks for them and the contact values `nodal`.
fn subdomain_piece(
    sc: &scene::Scene,
    model: &ModelData,
    spec: &SubdomainSpec,
    u: Vec<f64>,
    nodal: &[NodalContact],
) -> SubdomainPiece {
    let body = &model.bodies[spec.body];
    let mesh = spec.local_mesh(body);
    let stress = if sc.output.wants("stress") {
        signorini_fem::cell_stress(&mesh, &body.material, &u)
    } else {
        Vec::new()
    };
    let n = spec.nodes.len();
    let contact = ContactFields::of(nodal, &body.name, n, |p| spec.nodes.binary_search(&p).ok());
    SubdomainPiece {
        mesh: BodyResult {
            name: body.name.clone(),
            file_stem: scene::file_stem(&body.name),
            coords: mesh.coords,
            cells: mesh.cells.into_iter().map(|c| c.nodes).collect(),
            parts: vec![spec.part; spec.cells.len()],
            history: Vec::new(),
        },
        part: spec.part,
        nodes: spec.nodes.clone(),
        fields: StepFields {
            von_mises: stress.iter().map(signorini_fem::von_mises).collect(),
            displacement: u,
            stress,
        },
        contact,
    }
}

/// Writes the pieces of the subdomains this rank recovered at load step
/// `step` (1-based).
pub(crate) fn write_recovered(
    sc: &scene::Scene,
    model: &ModelData,
    recovered: &[RecoveredStep],
    step: usize,
    nodal: &[NodalContact],
    sink: &mut dyn StepSink,
) -> Result<(), String> {
    for r in recovered {
        let spec = &model.specs[r.id];
        if !spec.cells.is_empty() {
            let piece = subdomain_piece(sc, model, spec, r.displacement.clone(), nodal);
            sink.piece(step, &piece)?;
        }
    }
    Ok(())
}

/// The root writes every subdomain's piece at load step `step` from the
/// whole displacement of every body (the direct path).
pub(crate) fn write_all(
    sc: &scene::Scene,
    model: &ModelData,
    u_full: &[Vec<f64>],
    step: usize,
    nodal: &[NodalContact],
    sink: &mut dyn StepSink,
) -> Result<(), String> {
    for spec in model.specs.iter().filter(|s| !s.cells.is_empty()) {
        let dim = model.bodies[spec.body].mesh.dim;
        let u = &u_full[spec.body];
        let mine = (spec.nodes.iter())
            .flat_map(|&n| u[dim * n..dim * (n + 1)].iter().copied())
            .collect();
        sink.piece(step, &subdomain_piece(sc, model, spec, mine, nodal))?;
    }
    Ok(())
}
