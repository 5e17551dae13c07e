//! The suites run through the pipeline and the root solvers, apart from the
//! library the command line runs scenes with:
//!
//! - [`stiff`]: the stiff and extreme cases of docs/theory/validation-cases.md
//!   §8, scenes and expectations as data (`signorini bench --suite stiff`);
//! - [`rootbench`]: Delassus problems of an elastic layer built by this
//!   project's finite elements, on which every root algorithm is timed
//!   (`signorini bench --suite root`);
//! - [`bench`]: a scene over refinement levels, subdomain counts and paths
//!   (`signorini bench SCENE`).

pub mod bench;
pub mod rootbench;
pub mod stiff;
