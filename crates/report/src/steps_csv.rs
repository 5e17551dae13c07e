//! steps.csv: one row per load step. The columns of every run first (the
//! scales, the contact resultant, the sums of normal and tangential forces,
//! the mean slip, the counts, the iterations, the method that solved the
//! step and the one it took over from), then a group per
//! prescribed-displacement boundary entry (its reaction and moment) and a
//! group per contact pair (its normal and tangential sums), named after
//! the entry (docs/reference/scene-format.md).

use std::io::Write;
use std::path::Path;

use crate::{Reaction, StepContact, StepReport};

/// steps.csv: one row per load step (scales, resultants, slip, statuses,
/// reactions and each contact's sums).
pub fn write_steps_csv(path: &Path, steps: &[StepReport]) -> std::io::Result<()> {
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    let names: Vec<&String> = steps
        .first()
        .map(|s| s.scale.keys().collect())
        .unwrap_or_default();
    let scale_cols: String = names.iter().map(|n| format!(",scale_{n}")).collect();
    // 3D adds the z resultant and the second tangent, as contact.csv does.
    let dim3 = steps.first().is_some_and(|s| s.contact_force.len() == 3);
    let (z, t2, s2) = match dim3 {
        true => (",force_z", ",tangential_force_2", ",mean_slip_2"),
        false => ("", "", ""),
    };
    let groups: String = steps.first().map_or(String::new(), group_header);
    writeln!(w, "step{scale_cols},force_x,force_y{z},normal_force,tangential_force{t2},mean_slip{s2},active,sticking,slipping,iterations,method,fallback{groups}")?;
    for (i, s) in steps.iter().enumerate() {
        let sc: String = names
            .iter()
            .map(|n| format!(",{}", s.scale.get(*n).copied().unwrap_or(0.0)))
            .collect();
        let f = |k: usize| s.contact_force.get(k).copied().unwrap_or(0.0);
        let third = |x: Option<f64>| match dim3 {
            true => format!(",{:e}", x.unwrap_or(0.0)),
            false => String::new(),
        };
        writeln!(
            w,
            "{}{sc},{:e},{:e}{},{:e},{:e}{},{:e}{},{},{},{},{},{},{}{}",
            i + 1,
            f(0),
            f(1),
            third(Some(f(2))),
            s.normal_force,
            s.tangential_force,
            third(s.tangential_force_2),
            s.mean_slip,
            third(s.mean_slip_2),
            s.active,
            s.sticking,
            s.slipping,
            s.iterations,
            s.method,
            csv_field(s.fallback.as_deref().unwrap_or("")),
            group_values(s)
        )?;
    }
    w.flush()
}

const AXES: [&str; 3] = ["x", "y", "z"];

/// The names of the reaction and contact columns (each with its leading
/// comma), from a step's entries.
fn group_header(s: &StepReport) -> String {
    let mut out = String::new();
    for r in &s.reactions {
        for a in &AXES[..r.force.len()] {
            out += &format!(",{}", csv_field(&format!("reaction_{a}_{}", r.boundary)));
        }
        for a in moment_axes(r) {
            out += &format!(",{}", csv_field(&format!("moment_{a}_{}", r.boundary)));
        }
    }
    for c in &s.contacts {
        out += &format!(",{}", csv_field(&format!("normal_force_{}", c.name)));
        out += &format!(",{}", csv_field(&format!("tangential_force_{}", c.name)));
        if c.tangential_force_2.is_some() {
            out += &format!(",{}", csv_field(&format!("tangential_force_2_{}", c.name)));
        }
    }
    out
}

/// The axes of a reaction's moment: z in 2D, x, y, z in 3D, none without.
fn moment_axes(r: &Reaction) -> &'static [&'static str] {
    match r.moment.as_ref().map(Vec::len) {
        Some(1) => &AXES[2..],
        Some(3) => &AXES,
        _ => &[],
    }
}

/// A step's reaction and contact values, in [`group_header`]'s order.
fn group_values(s: &StepReport) -> String {
    let reactions = s.reactions.iter().flat_map(|r| {
        let moment = r.moment.as_deref().unwrap_or_default();
        r.force.iter().chain(moment).copied()
    });
    let contacts = s.contacts.iter().flat_map(contact_values);
    reactions
        .chain(contacts)
        .map(|v| format!(",{v:e}"))
        .collect()
}

fn contact_values(c: &StepContact) -> Vec<f64> {
    let mut v = vec![c.normal_force, c.tangential_force];
    v.extend(c.tangential_force_2);
    v
}

/// A CSV field: quoted (its quotes doubled) when it holds a comma, a quote
/// or a line break, as is.
pub fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn step(reactions: Vec<Reaction>, contacts: Vec<StepContact>) -> StepReport {
        StepReport {
            scale: [("press".to_string(), 1.0)].into(),
            contact_force: vec![0.0, 3.0],
            normal_force: 3.0,
            tangential_force: 0.5,
            tangential_resultant: [0.0; 3],
            mean_slip: 0.0,
            tangential_force_2: None,
            mean_slip_2: None,
            iterations: 2,
            active: 4,
            sticking: 0,
            slipping: 0,
            converged: true,
            stopping_reason: String::new(),
            active_history: Vec::new(),
            cycle_detected_at: None,
            solver: serde_json::Value::Null,
            regularisation: None,
            solve_s: 0.0,
            reactions,
            contacts,
            method: "coulomb_3d_fixed_point".into(),
            fallback: Some("coulomb_3d_semismooth_newton: stalled, residual 1e-2".into()),
        }
    }

    /// The groups follow the columns of every run (the method and its
    /// fallback last among them), in entry order; a name or a fallback
    /// holding a comma is one quoted field.
    #[test]
    fn reactions_and_contacts_are_column_groups_after_the_iterations() {
        let reaction = Reaction {
            boundary: "press".into(),
            body: "pad".into(),
            force: vec![0.25, -3.0],
            moment: Some(vec![1.5]),
            moment_about: Some(vec![0.0, 0.0]),
        };
        let contact = |name: &str, n: f64, t: f64| StepContact {
            name: name.into(),
            normal_force: n,
            tangential_force: t,
            tangential_force_2: None,
            force: vec![t, n],
        };
        let s = step(
            vec![reaction],
            vec![contact("a", 1.0, 0.5), contact("b,c", 2.0, 0.0)],
        );
        let path = crate::test_dir("steps_csv").join("steps.csv");
        write_steps_csv(&path, &[s]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let mut lines = text.lines();
        assert_eq!(
            lines.next().unwrap(),
            "step,scale_press,force_x,force_y,normal_force,tangential_force,mean_slip,active,sticking,slipping,iterations,method,fallback,reaction_x_press,reaction_y_press,moment_z_press,normal_force_a,tangential_force_a,\"normal_force_b,c\",\"tangential_force_b,c\""
        );
        assert_eq!(
            lines.next().unwrap(),
            "1,1,0e0,3e0,3e0,5e-1,0e0,4,0,0,2,coulomb_3d_fixed_point,\"coulomb_3d_semismooth_newton: stalled, residual 1e-2\",2.5e-1,-3e0,1.5e0,1e0,5e-1,2e0,0e0"
        );
    }
}
