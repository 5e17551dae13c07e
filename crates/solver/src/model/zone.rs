//! The candidate zone of every contact (scene `search_distance`): which slave
//! nodes are contact unknowns, and the check after the solve that the nodes
//! left out do not penetrate their master.
//!
//! A slave node whose initial gap g0 (the gap of the contact problem: the
//! geometric one, or the uniform `gap`) exceeds
//! L = search_distance + the largest prescribed displacement of the pair's
//! deformable bodies over the steps
//! is neither a contact unknown nor an interface DOF: it becomes an interior
//! DOF of its subdomain (course notes §8.2, the condensation is exact whatever the
//! interface). Its contact point is kept aside ([`ZonePoints::excluded`]);
//! after the solve its gap g = g0 + B u is computed with the recovered
//! displacement, and a node that would penetrate (g < −tolerance × the
//! certificate's length scale) makes the run solve again with the zone
//! widened ([`check_excluded`]): a zone too small costs time, never the
//! answer. A contact of a body held by contact alone ignores the zone (its
//! contact points must hold the body's rigid motions).

use serde::{Deserialize, Serialize};
use signorini_scene as scene;

use super::{BodyModel, PointModel};

/// The largest initial gap of a contact unknown, per contact (`None`: every
/// slave node is a candidate, the behaviour without `search_distance`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Zone {
    pub limit: Vec<Option<f64>>,
}

/// Number of widenings after which a run gives up on the zone and keeps
/// every slave node of the contacts that still penetrate.
pub const MAX_WIDENINGS: usize = 2;

impl Zone {
    /// The zone of the scene: per contact, `search_distance` plus the
    /// largest prescribed displacement of its slave and (deformable) master
    /// bodies at any step (`scales`: per step, per body, per load entry);
    /// `None` without `search_distance` or for a body held by contact.
    pub fn of_scene(sc: &scene::Scene, bodies: &[BodyModel], scales: &[Vec<Vec<f64>>]) -> Zone {
        let motion: Vec<f64> = (0..bodies.len())
            .map(|b| prescribed_motion(&bodies[b], scales.iter().map(|st| &st[b][..])))
            .collect();
        let of = |name: &str| bodies.iter().position(|b| b.name == name);
        let limit = sc
            .contact
            .iter()
            .map(|c| {
                let d = c.search_distance?;
                let sides = [of(&c.slave.body), of(&c.master.body)];
                if sides
                    .iter()
                    .flatten()
                    .any(|&b| !bodies[b].kernel.is_empty())
                {
                    return None;
                }
                Some(d + sides.iter().flatten().map(|&b| motion[b]).sum::<f64>())
            })
            .collect();
        Zone { limit }
    }

    /// Whether a point of contact `ci` with initial gap `gap0` is a contact
    /// unknown.
    pub fn includes(&self, ci: usize, gap0: f64) -> bool {
        self.limit
            .get(ci)
            .copied()
            .flatten()
            .is_none_or(|l| gap0 <= l)
    }

    /// Whether contact `ci` keeps only some of its slave nodes.
    pub fn restricts(&self, ci: usize) -> bool {
        self.limit.get(ci).copied().flatten().is_some()
    }
}

/// The largest nodal norm of a body's prescribed displacement over the
/// steps (each step: the scale of every load entry of the body).
fn prescribed_motion<'a>(b: &BodyModel, steps: impl Iterator<Item = &'a [f64]>) -> f64 {
    let dim = b.mesh.dim;
    steps
        .map(|s| {
            let u = b.combine(s, |l| &l.displacement);
            u.chunks(dim)
                .map(|v| v.iter().map(|x| x * x).sum::<f64>().sqrt())
                .fold(0.0f64, f64::max)
        })
        .fold(0.0f64, f64::max)
}

/// One note per contact whose zone left slave nodes out: how many are kept.
pub fn zone_notes(
    sc: &scene::Scene,
    zone: &Zone,
    points: &[PointModel],
    excluded: &[PointModel],
) -> Vec<String> {
    let mut notes = Vec::new();
    for (ci, c) in sc.contact.iter().enumerate() {
        let Some(limit) = zone.limit.get(ci).copied().flatten() else {
            if c.search_distance.is_some() {
                notes.push(format!(
                    "contact \"{}\": search_distance does not apply, every slave node is a contact unknown (a body of the pair is held by contact alone, or a solve before widened the zone to every node)",
                    c.name
                ));
            }
            continue;
        };
        let out = excluded.iter().filter(|p| p.contact == ci).count();
        if out == 0 {
            continue;
        }
        let kept = points.iter().filter(|p| p.contact == ci).count();
        notes.push(format!(
            "contact \"{}\": search_distance keeps {kept} of {} slave node(s) as contact unknowns (initial gap <= {limit:.3e}); the {out} others are interior DOFs, checked after the solve: none penetrates the master",
            c.name,
            kept + out
        ));
    }
    notes
}

/// The zone widened after a solve, and a note per contact that needed it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Widening {
    pub zone: Zone,
    pub notes: Vec<String>,
}

/// Checks the excluded points against the recovered displacements
/// (`lowest`: each point's lowest gap g0 + B u over the steps): a point
/// whose gap falls below −`tolerance` at some step would penetrate. Returns
/// `None` when none does; else the zone widened for each contact concerned
/// to twice the largest initial gap of its penetrating points (every slave
/// node once `widenings` reaches [`MAX_WIDENINGS`]), with a note.
pub fn check_excluded(
    sc: &scene::Scene,
    zone: &Zone,
    excluded: &[PointModel],
    lowest: &[f64],
    tolerance: f64,
    widenings: usize,
) -> Option<Widening> {
    // Per contact: (count, lowest gap, largest g0) of the penetrating points.
    let mut hits: std::collections::BTreeMap<usize, (usize, f64, f64)> = Default::default();
    for (p, &lowest) in excluded.iter().zip(lowest) {
        if lowest < -tolerance {
            let h = hits.entry(p.contact).or_insert((0, 0.0, 0.0));
            *h = (h.0 + 1, h.1.min(lowest), h.2.max(p.gap0));
        }
    }
    if hits.is_empty() {
        return None;
    }
    let mut wide = zone.clone();
    let mut notes = Vec::new();
    for (&ci, &(count, lowest, g0)) in &hits {
        let limit = (widenings < MAX_WIDENINGS).then_some(2.0 * g0);
        wide.limit[ci] = limit;
        let to = limit.map_or("every slave node".to_string(), |l| {
            format!("initial gaps <= {l:.3e}")
        });
        notes.push(format!(
            "contact \"{}\": {count} slave node(s) left out by search_distance would penetrate the master after the solve (gap down to {lowest:.3e}): solved again with the candidate zone widened to {to}",
            sc.contact[ci].name
        ));
    }
    Some(Widening { zone: wide, notes })
}
