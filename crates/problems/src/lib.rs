//! Stand-alone contact problems: a Delassus operator W, its free gaps q and,
//! for friction, a coefficient μ per contact, read from and written to JSON,
//! NumPy `.npz` and FCLib HDF5 files (`problem_file`, `fclib`), and solved by
//! any root algorithm (`local`: `signorini local`), so that the root solvers
//! can be compared with other libraries on identical data.
//!
//! Imports go one way: `local` → `problem_file` → `fclib` → `raw`. The memory
//! a solve may use is passed in (`load`'s budget), never read from the
//! process: a file whose solve would not fit is refused before it is read.
//! This crate knows nothing of scenes, the pipeline or the transport.

mod fclib;
pub mod local;
pub mod problem_file;
mod raw;

pub use raw::regular_file;
