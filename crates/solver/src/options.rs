//! What a run is given besides its scene: the command line's overrides and
//! what the process hands it (memory budget, progress observer).

use std::sync::Arc;

use crate::{memory, progress};
use signorini_scene as scene;

/// Overrides from the command line.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    pub method: Option<scene::Method>,
    pub path: Option<scene::SolvePath>,
}

/// What the process that starts a run gives it besides the scene and the
/// options: the command line's `--max-memory` and its progress line.
#[derive(Clone, Default)]
pub struct RunEnvironment {
    /// The memory the run may use: a scene estimated above it is refused
    /// before anything is built (`None`: unknown, nothing is refused).
    pub budget: Option<memory::Budget>,
    /// Who hears of the run's progress on this rank (`None`: nobody).
    pub observer: Option<Arc<dyn progress::Observer>>,
    /// A rank that fails its condensation on purpose, for the tests of the
    /// MPI path's error handling (the command line's SIGNORINI_FAIL_RANK).
    pub fail_rank: Option<usize>,
}

impl RunEnvironment {
    /// The machine's memory ([`memory::machine_memory`]), no observer.
    pub fn machine() -> Self {
        Self {
            budget: memory::machine_memory(),
            observer: None,
            fail_rank: None,
        }
    }
}
