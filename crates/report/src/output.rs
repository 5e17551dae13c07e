//! The output files of a run (SCENE.md, "Output"): contact.csv, steps.csv,
//! friction.svg, displacement.csv, stress.csv, the VTU series and
//! report.json, and the run's summary for the terminal. The run's fields come
//! in [`RunOutput`]; what the scene asks for, in [`OutputRequest`].

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use crate::{ContactRow, Report};

/// The fields of one body at one load step.
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

/// One body's mesh and its fields at every load step.
pub struct BodyResult {
    pub name: String,
    pub coords: Vec<[f64; 3]>,
    pub cells: Vec<Vec<usize>>,
    /// METIS part of each cell.
    pub parts: Vec<usize>,
    /// The fields at every load step (at least one).
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

pub fn write_outputs(
    dir: &Path,
    request: &OutputRequest,
    output: &mut RunOutput,
    t: Instant,
) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let dim = request.dim;
    crate::write_contact_csv(&dir.join("contact.csv"), &output.contact_rows, dim)?;
    crate::write_steps_csv(&dir.join("steps.csv"), &output.report.steps)?;
    // With friction and several steps: the tangential force against the slip
    // (a hysteresis loop under cyclic loading).
    let friction = output
        .report
        .steps
        .iter()
        .any(|s| s.sticking + s.slipping > 0);
    if friction && output.report.steps.len() >= 3 {
        use crate::plot::{linear_svg, Series};
        let points = std::iter::once((0.0, 0.0))
            .chain(
                output
                    .report
                    .steps
                    .iter()
                    .map(|s| (s.mean_slip, s.tangential_force)),
            )
            .collect();
        let series = [Series {
            label: "tangential contact force".into(),
            points,
        }];
        if let Err(e) = linear_svg(
            &dir.join("friction.svg"),
            "Tangential force against slip",
            "mean slip",
            "tangential contact force",
            &series,
        ) {
            output
                .report
                .messages
                .push(format!("no friction plot: {e}"));
        }
    }
    write_vtu_fields(dir, request, output).map_err(std::io::Error::other)?;
    if request.wants("displacement") {
        let mut w = std::io::BufWriter::new(std::fs::File::create(dir.join("displacement.csv"))?);
        let axes = &["x", "y", "z"][..dim];
        let header: Vec<String> = axes
            .iter()
            .map(|a| a.to_string())
            .chain(axes.iter().map(|a| format!("u{a}")))
            .collect();
        writeln!(w, "body,node,{}", header.join(","))?;
        for b in &output.bodies {
            for (n, x) in b.coords.iter().enumerate() {
                write!(w, "{},{}", b.name, n)?;
                for xk in &x[..dim] {
                    write!(w, ",{xk:e}")?;
                }
                for uk in &b.last().displacement[dim * n..dim * (n + 1)] {
                    write!(w, ",{uk:e}")?;
                }
                writeln!(w)?;
            }
        }
    }
    if request.wants("stress") {
        // Voigt [xx, yy, zz, xy, yz, xz]; 2D keeps its historical columns
        // (axisymmetric: x = r, y = z, szz = the hoop stress σ_θθ).
        let mut w = std::io::BufWriter::new(std::fs::File::create(dir.join("stress.csv"))?);
        if dim == 3 {
            writeln!(w, "body,cell,sxx,syy,szz,sxy,syz,sxz,von_mises")?;
        } else {
            writeln!(w, "body,cell,sxx,syy,sxy,szz,von_mises")?;
        }
        for b in &output.bodies {
            let last = b.last();
            for (c, s) in last.stress.iter().enumerate() {
                if dim == 3 {
                    writeln!(
                        w,
                        "{},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
                        b.name, c, s[0], s[1], s[2], s[3], s[4], s[5], last.von_mises[c]
                    )?;
                } else {
                    writeln!(
                        w,
                        "{},{},{:e},{:e},{:e},{:e},{:e}",
                        b.name, c, s[0], s[1], s[3], s[2], last.von_mises[c]
                    )?;
                }
            }
        }
    }
    let tim = &mut output.report.timings_s;
    tim.output = t.elapsed().as_secs_f64();
    tim.total += tim.setup + tim.output;
    crate::write_report(&dir.join("report.json"), &output.report)
}

/// DIR/<body>_<step>.vtu for every body and load step, and DIR/fields.pvd,
/// the time series (timestep = step number) that ParaView opens as one
/// dataset, with the fields that `[output] fields` asks for: displacement;
/// contact pressure, status (−1 no contact point, 0 open, 1 contact, 2 stick,
/// 3 slip) and tangential force at the slave nodes; stress (Voigt
/// [xx, yy, zz, xy, yz, xz]; axisymmetric: x = r, y = z, zz = hoop) and von
/// Mises per cell; the METIS subdomain of each cell.
fn write_vtu_fields(dir: &Path, request: &OutputRequest, output: &RunOutput) -> Result<(), String> {
    use crate::vtu::{write_pvd, write_vtu, PvdEntry, VtuPiece};
    if request.fields.is_empty() {
        return Ok(());
    }
    let dim = request.dim;
    let mut entries = Vec::new();
    for (bi, b) in output.bodies.iter().enumerate() {
        let n = b.coords.len();
        let safe: String = b
            .name
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        for (si, fields) in b.history.iter().enumerate() {
            let step = si + 1;
            let mut point_data = Vec::new();
            if request.wants("displacement") {
                let u: Vec<f64> = (0..n)
                    .flat_map(|i| {
                        let mut v = [0.0; 3];
                        v[..dim].copy_from_slice(&fields.displacement[dim * i..dim * (i + 1)]);
                        v
                    })
                    .collect();
                point_data.push(("displacement".to_string(), 3, u));
            }
            if request.wants("contact") {
                let mut pressure = vec![0.0; n];
                let mut status = vec![-1.0; n];
                let mut tangential = vec![0.0; n];
                for r in output
                    .contact_rows
                    .iter()
                    .filter(|r| r.step == step && r.body == b.name)
                {
                    pressure[r.point] = r.pressure;
                    tangential[r.point] = r.tangential_force;
                    status[r.point] = match r.status {
                        "open" => 0.0,
                        "contact" => 1.0,
                        "stick" => 2.0,
                        _ => 3.0,
                    };
                }
                point_data.push(("contact_pressure".to_string(), 1, pressure));
                point_data.push(("contact_status".to_string(), 1, status));
                point_data.push(("tangential_force".to_string(), 1, tangential));
            }
            let mut cell_data = vec![(
                "subdomain".to_string(),
                1,
                b.parts.iter().map(|&p| p as f64).collect(),
            )];
            if request.wants("stress") && !fields.stress.is_empty() {
                cell_data.push((
                    "stress".to_string(),
                    6,
                    fields
                        .stress
                        .iter()
                        .flat_map(|s| s.iter().copied())
                        .collect(),
                ));
                cell_data.push(("von_mises".to_string(), 1, fields.von_mises.clone()));
            }
            let file = format!("{safe}_{step}.vtu");
            write_vtu(
                &dir.join(&file),
                &VtuPiece {
                    title: format!("{} step {step}", b.name),
                    dim,
                    coords: &b.coords,
                    cells: &b.cells,
                    point_data,
                    cell_data,
                },
            )?;
            entries.push(PvdEntry {
                timestep: step as f64,
                part: bi,
                file,
            });
        }
    }
    write_pvd(&dir.join("fields.pvd"), &entries).map_err(|e| e.to_string())
}

/// The run in a few lines for the terminal: sizes, per-step iterations,
/// the contact force, the certificate, warnings and notes, the reference
/// errors, the total time and where the report is.
pub fn summary(dir: &Path, o: &RunOutput) -> String {
    let mut out = String::new();
    let r = &o.report;
    out += &format!(
        "{}: {} DOFs, {} interface DOFs, {} contact points, method {} ({} path): {}\n",
        r.scene,
        r.dofs,
        r.interface_dofs,
        r.contact_points,
        r.method,
        r.path,
        if r.converged {
            "converged"
        } else {
            "NOT converged"
        }
    );
    for (i, s) in r.steps.iter().enumerate() {
        out += &format!(
            "  step {}: {} iterations, {} active\n",
            i + 1,
            s.iterations,
            s.active
        );
    }
    out += &format!(
        "  contact force ({}); certificate max {:.2e} (equilibrium {:.1e}, penetration {:.1e}, tension {:.1e}, complementarity {:.1e})\n",
        r.contact_force
            .iter()
            .map(|f| format!("{f:.6e}"))
            .collect::<Vec<_>>()
            .join(", "),
        r.certificate.max(),
        r.certificate.equilibrium,
        r.certificate.penetration,
        r.certificate.tension,
        r.certificate.complementarity
    );
    let warning = r.conditioning.as_ref().and_then(|c| c.warning.as_ref());
    if let Some(w) = warning {
        out += &format!("  warning: {w}\n");
    }
    for m in r.messages.iter().filter(|m| Some(*m) != warning) {
        out += &format!("  note: {m}\n");
    }
    if let Some(refr) = &r.reference {
        for (k, q) in &refr.quantities {
            out += &format!(
                "  {} {k}: computed {:.6e}, exact {:.6e}, relative error {:.3e}\n",
                refr.kind, q.computed, q.exact, q.relative_error
            );
        }
    }
    out += &format!(
        "  total {:.3} s; report in {}\n",
        r.timings_s.total,
        dir.join("report.json").display()
    );
    out
}
