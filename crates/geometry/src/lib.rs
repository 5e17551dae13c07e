//! Contact geometry: the contact points of a pair of surfaces (course notes
//! §2.4 and §3.1.2), their normals, tangents and initial gaps, and the rows
//! of B over the nodes of both sides: node-to-node, node-to-segment (2D) and
//! node-to-face (3D) against a deformable surface or a rigid plane or sphere
//! (`pairing`), mortar with dual multipliers in 2D and 3D (`mortar`,
//! `mortar3d`), and the constraints that repeat another (`redundancy`).
//!
//! Conventions (docs/theory/contact-problem.md): the normal n points from
//! master to slave; the gap is g = g0 + B u with B the row operator
//! n·(u_slave − u_master interpolated); non-penetration g ≥ 0.
//!
//! The geometry knows meshes and surfaces only: not the scene format, the
//! contact algorithms, MPI or the command line.

mod closest;
mod error;
pub mod mortar;
pub mod mortar3d;
pub mod pairing;
pub mod quadratic_slave;
mod ray;
pub mod redundancy;
mod search;

pub use error::GeometryError;
pub use pairing::{ContactPoint, MasterGeometry, NormalRule, Term, TermSide, VectorTerm};
