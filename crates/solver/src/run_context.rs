//! What the stages of a run share: the run's context (scene, plan, model,
//! transport) and what it keeps for its report as it goes.

use crate::progress::Progress;
use crate::{partition, plan};
use signorini_comm::Transport;
use signorini_report::Timings;
use signorini_scene as scene;
use std::time::Instant;

/// What a run keeps for its report as it goes.
pub(crate) struct RunLog {
    pub t_total: Instant,
    pub timings: Timings,
    pub messages: Vec<String>,
    pub stages: Vec<String>,
}

/// What every stage after the model stage reads of the run: the scene, its
/// name, the plan, the model and the transport.
#[derive(Clone, Copy)]
pub(crate) struct RunContext<'a> {
    pub sc: &'a scene::Scene,
    /// Who hears of the run's progress.
    pub progress: &'a Progress,
    pub scene_name: &'a str,
    pub plan: &'a plan::Plan,
    pub model: &'a partition::ModelData,
    pub comm: &'a dyn Transport,
}
