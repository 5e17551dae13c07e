//! Which side of a contact pair between two deformable bodies is the slave.
//!
//! The slave's nodes (node-to-face) or shape functions (mortar) carry the
//! constraints, and the master's surface is interpolated between them: the
//! answer depends on the choice, by more than the discretisation error when
//! the slave is the stiffer and coarser side (a coarse stiff slave cannot
//! follow the finer, softer master, whose nodes between its own go through
//! or lift off). The rule: the slave is the softer side, the one with the
//! lower plane-strain modulus E/(1 − ν²); when the two moduli are within
//! [`SAME_MODULUS`] of each other, the finer side, the one with the smaller
//! mean node spacing where the two surfaces meet (the square root of the
//! area per node in 3D, the length per node in 2D, over the nodes inside
//! the intersection of the two surfaces' bounding boxes). `slave_choice = "auto"` applies it;
//! with the default `"given"` a slave that is both the stiffer and the
//! coarser side draws a warning.

use signorini_mesh::Surface;
use signorini_scene as scene;

use super::BodyModel;

/// Moduli (or spacings) within this ratio of each other are the same.
const SAME_MODULUS: f64 = 1.1;

/// One side of a pair as the rule sees it.
struct Side {
    /// E/(1 − ν²).
    modulus: f64,
    /// The mean node spacing of the surface.
    spacing: f64,
}

impl Side {
    /// The side of `body` on `surface`, its spacing measured where the pair
    /// meets: on the nodes inside `overlap`.
    fn of(body: &BodyModel, surface: &Surface, overlap: &Bounds) -> Self {
        let m = &body.material;
        let (mut measure, mut nodes) = (0.0, 0usize);
        for (n, a) in signorini_fem::tributary_measure(&body.mesh, surface, m.model) {
            if overlap.holds(&body.mesh.coords[n]) {
                measure += a;
                nodes += 1;
            }
        }
        let per_node = measure / nodes.max(1) as f64;
        Self {
            modulus: m.young / (1.0 - m.poisson * m.poisson),
            spacing: if body.mesh.dim == 3 {
                per_node.sqrt()
            } else {
                per_node
            },
        }
    }
}

/// A box [lo, hi].
#[derive(Clone, Copy)]
struct Bounds {
    lo: [f64; 3],
    hi: [f64; 3],
}

impl Bounds {
    /// The bounding box of a surface's nodes, widened by 1 % of its diagonal.
    fn of(body: &BodyModel, surface: &Surface) -> Self {
        let (lo, hi) =
            signorini_mesh::bounding_box(surface.nodes().into_iter().map(|n| &body.mesh.coords[n]));
        let d = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt();
        Self {
            lo: lo.map(|v| v - 0.01 * d),
            hi: hi.map(|v| v + 0.01 * d),
        }
    }

    fn meet(&self, other: &Bounds) -> Bounds {
        Bounds {
            lo: [0, 1, 2].map(|k| self.lo[k].max(other.lo[k])),
            hi: [0, 1, 2].map(|k| self.hi[k].min(other.hi[k])),
        }
    }

    fn holds(&self, x: &[f64; 3]) -> bool {
        (0..3).all(|k| self.lo[k] <= x[k] && x[k] <= self.hi[k])
    }
}

/// Whether `a` is the better slave than `b` by the rule.
fn better_slave(a: &Side, b: &Side) -> bool {
    if a.modulus * SAME_MODULUS < b.modulus {
        return true;
    }
    if b.modulus * SAME_MODULUS < a.modulus {
        return false;
    }
    a.spacing * SAME_MODULUS < b.spacing
}

/// The contact `c` with its sides as `slave_choice` says (swapped when
/// "auto" prefers the master), and a note or warning for `notes`: with
/// "auto", which side it chose; with "given", a warning when the slave is
/// the stiffer and the coarser side. `surface` finds a body's surface
/// (`None` for a rigid master, which is never the slave).
pub(super) fn chosen_sides<'m>(
    c: &scene::Contact,
    body: impl Fn(&str) -> Option<&'m BodyModel>,
    surface: impl Fn(&'m BodyModel, &str) -> Option<&'m Surface>,
) -> (scene::Contact, Option<String>) {
    let found = |s: &scene::ContactSide| {
        let b = body(&s.body)?;
        Some((b, surface(b, s.surface.as_deref()?)?))
    };
    let (Some((bs, ss)), Some((bm, sm))) = (found(&c.slave), found(&c.master)) else {
        return (c.clone(), None);
    };
    let overlap = Bounds::of(bs, ss).meet(&Bounds::of(bm, sm));
    let (slave, master) = (Side::of(bs, ss, &overlap), Side::of(bm, sm, &overlap));
    let name = |s: &scene::ContactSide| {
        format!(
            "body \"{}\" surface \"{}\"",
            s.body,
            s.surface.as_deref().unwrap_or_default()
        )
    };
    let mut chosen = c.clone();
    let note = match c.slave_choice {
        scene::SlaveChoice::Auto => {
            if better_slave(&master, &slave) {
                std::mem::swap(&mut chosen.slave, &mut chosen.master);
            }
            Some(format!(
                "contact \"{}\": slave_choice = \"auto\" made {} the slave (the softer side, or the finer of equally stiff sides); forces are those on it",
                c.name,
                name(&chosen.slave)
            ))
        }
        scene::SlaveChoice::Given => {
            let stiffer = slave.modulus > SAME_MODULUS * master.modulus;
            let coarser = slave.spacing > SAME_MODULUS * master.spacing;
            (stiffer && coarser).then(|| format!(
                "warning: contact \"{}\": the slave, {}, is the stiffer (E/(1 - nu^2) = {:.3e} against {:.3e}) and the coarser (node spacing {:.3e} against {:.3e}) side of the pair: the forces depend on that choice beyond the discretisation error; make {} the slave, or write slave_choice = \"auto\"",
                c.name,
                name(&c.slave),
                slave.modulus,
                master.modulus,
                slave.spacing,
                master.spacing,
                name(&c.master)
            ))
        }
    };
    (chosen, note)
}
