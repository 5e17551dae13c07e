//! The root package's integration tests in one binary (one compile and one
//! link for all of them): one module a topic. The helpers they share are
//! tests/common; the MPI tests (tests/mpi.rs) and the documentation checks
//! (tests/docs.rs, which the generated docs name as `--test docs`) are
//! binaries of their own.

#[path = "../common/mod.rs"]
mod common;

mod algorithms;
mod assembly_vocabulary;
mod bad_input;
mod bad_input_limits;
mod conditioning;
mod contact_2d;
mod contact_elements;
mod direct_friction;
mod direct_ldlt;
mod disconnected_parts;
mod fclib;
mod flat_punch;
mod floating;
mod friction;
mod friction3d;
mod friction_plasticity;
mod friction_supports;
mod hertz_cli;
mod hertz_quarter;
mod incompressible;
mod mortar;
mod mortar3d;
mod normal_rules;
mod output_and_streams;
mod path_choice;
mod pieces;
mod progress;
mod quadratic;
mod quadratic_patch;
mod redundant;
mod search_distance;
mod solids;
mod sparse_interface;
mod step_friction_kept;
mod stiff;
mod streamed_steps;
mod substructuring;
mod symmetry_planes;
mod time_limits;
mod tipping;
mod tri3_meshes;
mod units;
mod units_methods;
