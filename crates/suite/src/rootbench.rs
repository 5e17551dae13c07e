//! The root-solver benchmark: Delassus problems W, q (μ) of a
//! rigid indenter on an elastic layer, built by this project's finite
//! elements ([`layer`], [`problem`]), on which every root algorithm runs.
//!
//! This crate owns the benchmark problems and their runs; it is not part of
//! the library the pipeline uses, and the numerics it times know nothing of
//! it.

pub mod compliance;
pub mod halfspace;
pub mod layer;
pub mod problem;
pub mod run;

pub use layer::{surface_compliance, Layer, SurfaceCompliance};
pub use problem::{indentation_problem, Indentation, RootProblem};
