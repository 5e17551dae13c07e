//! The semi-smooth Newton step on the Alart–Curnier equations
//! ([`crate::friction::semismooth_newton`]) reduced to its unknown forces, on the
//! reduction of the status systems (`signorini_linalg::reduced`).

mod newton;
pub(crate) use newton::{solve_newton, NewtonFactor};
