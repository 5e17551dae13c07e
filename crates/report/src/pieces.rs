//! Per-subdomain VTU pieces (`[output] pieces = true`): at every
//! step that writes fields, the rank that owns a subdomain writes its piece
//! `DIR/pieces/<body>_<step>_s<part>.vtu` (the subdomain's cells and nodes,
//! the same arrays as the gathered `<body>_<step>.vtu`, and the point array
//! `node`: the body node number), and the root writes the index
//! `DIR/<body>_<step>.pvtu` naming every piece of the body, and the series
//! `DIR/pieces.pvd`. The contact fields live on the root: it sends each
//! step's [`NodalContact`] values to the ranks.

use serde::{Deserialize, Serialize};

use crate::results::{BodyResult, StepFields};
use crate::ContactRow;

/// The contact values of one slave node at one step, as the root sends them
/// to the ranks.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NodalContact {
    pub body: String,
    /// The body node.
    pub point: usize,
    pub pressure: f64,
    pub tangential_force: f64,
    /// −1 no contact point, 0 open, 1 contact, 2 stick, 3 slip.
    pub status: f64,
    /// The tangential force and the total slip in global coordinates
    /// ([`ContactRow::tangential_vector`], [`ContactRow::slip_vector`]).
    pub tangential_vector: [f64; 3],
    pub slip_vector: [f64; 3],
}

impl NodalContact {
    /// The values of the contact rows of load step `step`.
    pub fn of_rows(rows: &[ContactRow], step: usize) -> Vec<NodalContact> {
        rows.iter()
            .filter(|r| r.step == step)
            .map(|r| NodalContact {
                body: r.body.clone(),
                point: r.point,
                pressure: r.pressure,
                tangential_force: r.tangential_force,
                status: match r.status {
                    "open" => 0.0,
                    "contact" => 1.0,
                    "stick" => 2.0,
                    _ => 3.0,
                },
                tangential_vector: r.tangential_vector(),
                slip_vector: r.slip_vector(),
            })
            .collect()
    }
}

/// The contact point arrays of a grid: pressure, status and tangential force
/// per point (0, −1 and 0 away from the contact points), and the tangential
/// force and slip as global 3-vectors (zero away from them).
pub struct ContactFields {
    pub pressure: Vec<f64>,
    pub status: Vec<f64>,
    pub tangential: Vec<f64>,
    pub tangential_vector: Vec<f64>,
    pub slip_vector: Vec<f64>,
}

impl ContactFields {
    /// The values of body `body` on a grid of `n` points, the body node `p`
    /// being the point `point_of(p)` (`None`: not on this grid).
    pub fn of(
        nodal: &[NodalContact],
        body: &str,
        n: usize,
        point_of: impl Fn(usize) -> Option<usize>,
    ) -> Self {
        let mut f = ContactFields {
            pressure: vec![0.0; n],
            status: vec![-1.0; n],
            tangential: vec![0.0; n],
            tangential_vector: vec![0.0; 3 * n],
            slip_vector: vec![0.0; 3 * n],
        };
        for c in nodal.iter().filter(|c| c.body == body) {
            if let Some(i) = point_of(c.point) {
                f.pressure[i] = c.pressure;
                f.status[i] = c.status;
                f.tangential[i] = c.tangential_force;
                f.tangential_vector[3 * i..3 * i + 3].copy_from_slice(&c.tangential_vector);
                f.slip_vector[3 * i..3 * i + 3].copy_from_slice(&c.slip_vector);
            }
        }
        f
    }
}

/// One subdomain's piece at one step, built on the rank that owns it.
pub struct SubdomainPiece {
    /// The subdomain's mesh (its cells on its nodes numbered locally), named
    /// after its body; `parts` holds its part number on every cell.
    pub mesh: BodyResult,
    /// The METIS part of the body (the `subdomain` cell value).
    pub part: usize,
    /// The body node of each local node.
    pub nodes: Vec<usize>,
    /// Its fields, on its nodes and cells.
    pub fields: StepFields,
    pub contact: ContactFields,
}

/// The piece file of subdomain `part` of a body at a step, relative to the
/// output directory.
pub fn piece_file(body_file: &str, step: usize, part: usize) -> String {
    format!("pieces/{body_file}_{step}_s{part}.vtu")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contact_values_land_on_the_local_points_of_their_body() {
        let nodal = vec![
            NodalContact {
                body: "a".into(),
                point: 7,
                pressure: 2.5,
                tangential_force: -1.0,
                status: 3.0,
                tangential_vector: [0.0, -1.0, 0.0],
                slip_vector: [0.0, 2.0, 0.0],
            },
            NodalContact {
                body: "b".into(),
                point: 7,
                pressure: 9.0,
                tangential_force: 9.0,
                status: 1.0,
                tangential_vector: [9.0; 3],
                slip_vector: [9.0; 3],
            },
        ];
        let nodes = [3usize, 7, 9];
        let f = ContactFields::of(&nodal, "a", 3, |p| nodes.binary_search(&p).ok());
        assert_eq!(f.pressure, vec![0.0, 2.5, 0.0]);
        assert_eq!(f.status, vec![-1.0, 3.0, -1.0]);
        assert_eq!(f.tangential, vec![0.0, -1.0, 0.0]);
        assert_eq!(f.tangential_vector[3..6], [0.0, -1.0, 0.0]);
        assert_eq!(f.slip_vector, [0., 0., 0., 0., 2., 0., 0., 0., 0.]);
        assert_eq!(piece_file("top", 2, 1), "pieces/top_2_s1.vtu");
    }
}
