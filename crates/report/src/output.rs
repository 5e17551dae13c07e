//! The output files of a run (docs/reference/scene-format.md, "Output"): contact.csv, steps.csv,
//! friction.svg, displacement.csv, stress.csv, the VTU series and
//! report.json, and the run's summary for the terminal. The run's fields come
//! in [`RunOutput`]; what the scene asks for, in [`OutputRequest`]
//! (`crate::results`).

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use crate::results::RunOutput;
use crate::stream::FieldWriter;
use crate::Certificate;

/// The files of a run whose steps streamed to `writer` (contact.csv and the
/// VTU series): moves them into place, then writes steps.csv, friction.svg,
/// displacement.csv and stress.csv (the last step) and report.json.
pub fn write_outputs(
    writer: &mut FieldWriter,
    output: &mut RunOutput,
    t: Instant,
) -> std::io::Result<()> {
    writer.commit()?;
    let mut written = writer.written();
    let (dir, request) = (writer.dir(), writer.request());
    let dim = request.dim;
    crate::write_steps_csv(&dir.join("steps.csv"), &output.report.steps)?;
    // With friction and several steps: the tangential force against the slip
    // (a hysteresis loop under cyclic loading).
    let friction = output
        .report
        .steps
        .iter()
        .any(|s| s.sticking + s.slipping > 0);
    if friction && output.report.steps.len() >= 3 {
        use crate::plot::{plot_svg, Axes, Series};
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
        if let Err(e) = plot_svg(
            &dir.join("friction.svg"),
            "Tangential force against slip",
            ("mean slip", "tangential contact force"),
            &series,
            Axes::Linear,
        ) {
            output
                .report
                .messages
                .push(format!("no friction plot: {e}"));
        } else {
            written.insert("friction.svg".into());
        }
    }
    if request.wants("displacement") {
        written.insert("displacement.csv".into());
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
        written.insert("stress.csv".into());
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
    remove_earlier(dir, &written, output);
    // The steps streamed during the run are in `output` and `total` already.
    let tim = &mut output.report.timings_s;
    let written = t.elapsed().as_secs_f64();
    tim.output += written;
    tim.total += tim.setup + written;
    crate::write_report(&dir.join("report.json"), &output.report)
}

/// Removes what an earlier run left in `dir` that this run did not write
/// again ([`crate::stale`]), saying so in the report's messages.
fn remove_earlier(dir: &Path, written: &std::collections::BTreeSet<String>, o: &mut RunOutput) {
    let stems: Vec<String> = (o.bodies.iter()).map(|b| b.file_stem.clone()).collect();
    let message = match crate::stale::remove_stale(dir, &stems, written) {
        Ok(removed) if removed.is_empty() => return,
        Ok(removed) => {
            let shown: Vec<&str> = removed.iter().take(6).map(String::as_str).collect();
            let more = if removed.len() > shown.len() {
                ", …"
            } else {
                ""
            };
            format!(
                "removed {} file(s) an earlier run left in {} that this run does not write: {}{more}",
                removed.len(),
                dir.display(),
                shown.join(", ")
            )
        }
        Err(e) => format!(
            "files an earlier run left in {} may remain (cannot remove them: {e})",
            dir.display()
        ),
    };
    o.report.messages.push(message);
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
    if let Some(c) = r.path_choice.as_ref().filter(|c| c.requested == "auto") {
        out += &format!("  path auto: {} ({})\n", c.chosen, c.reason);
    }
    for (i, s) in r.steps.iter().enumerate() {
        out += &format!(
            "  step {}: {} iterations, {} active, by {}\n",
            i + 1,
            s.iterations,
            s.active,
            s.method
        );
        if let Some(f) = &s.fallback {
            out += &format!("    (after {f})\n");
        }
    }
    out += &format!(
        "  contact force ({}); certificate max {:.2e} ({})\n",
        r.contact_force
            .iter()
            .map(|f| format!("{f:.6e}"))
            .collect::<Vec<_>>()
            .join(", "),
        r.certificate.max(),
        certificate_terms(&r.certificate)
    );
    if let Some(last) = r.steps.last() {
        out += &carried(last, r.steps.len());
    }
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

/// The summary's lines of what the supports and the contacts carry at the
/// last step (`n`: the number of steps): each reaction's force and moment,
/// each contact's normal and tangential sums.
fn carried(last: &crate::StepReport, n: usize) -> String {
    let at = if n > 1 {
        format!(" at step {n}")
    } else {
        String::new()
    };
    let list = |v: &[f64]| {
        v.iter()
            .map(|f| format!("{f:.6e}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut out = String::new();
    for re in &last.reactions {
        let moment = match &re.moment {
            Some(m) => format!(", moment ({})", list(m)),
            None => String::new(),
        };
        out += &format!(
            "  reaction \"{}\" on {}{at}: force ({}){moment}\n",
            re.boundary,
            re.body,
            list(&re.force)
        );
    }
    for c in &last.contacts {
        let t2 = match c.tangential_force_2 {
            Some(t) => format!(", {t:.6e}"),
            None => String::new(),
        };
        out += &format!(
            "  contact \"{}\"{at}: normal force {:.6e}, tangential force {:.6e}{t2}\n",
            c.name, c.normal_force, c.tangential_force
        );
    }
    out
}

/// The certificate's terms for the summary line: the four of every run,
/// then those of friction and of regularised laws where they are not zero.
fn certificate_terms(c: &Certificate) -> String {
    let mut terms = vec![
        ("equilibrium", c.equilibrium),
        ("penetration", c.penetration),
        ("tension", c.tension),
        ("complementarity", c.complementarity),
    ];
    terms.extend(
        [
            ("cone", c.cone),
            ("dissipation", c.dissipation),
            ("law", c.law),
        ]
        .into_iter()
        .filter(|(_, v)| *v != 0.0),
    );
    terms
        .iter()
        .map(|(name, v)| format!("{name} {v:.1e}"))
        .collect::<Vec<_>>()
        .join(", ")
}
