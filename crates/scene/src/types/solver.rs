//! `[solver]`: the contact algorithm, the path, the friction loop and their
//! limits.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// `[solver]`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Solver {
    /// The contact algorithm (default `status`).
    pub method: Method,
    /// `auto` (default: the cheaper of the two, estimated), `condensed`
    /// (static condensation onto the interface) or `direct`.
    pub path: SolvePath,
    /// Convergence tolerance, 0 < tol < 1 (default 1e-10).
    pub tolerance: f64,
    /// ≥ 1 (default 500).
    #[serde(deserialize_with = "crate::serde_impls::max_iterations")]
    pub max_iterations: usize,
    /// Friction outer loop: `fixed_point` (default), `status`, `newton` or `nsgs`.
    pub friction: FrictionSolver,
    /// The wall-clock budget of each contact solve, in seconds (> 0): every
    /// method on the condensed path, friction solves on the direct path;
    /// default: 10 s + 2e-9 s × rows³ of the solve's problem. A solve that
    /// reaches it stops, not converged.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_limit: Option<f64>,
    /// Status method: `all` statuses changed at each iteration (default) or a
    /// `single` one (the variant with the convergence proof, course notes §3.3).
    pub status_changes: StatusChanges,
    /// Status method: impose the active constraints by `multipliers`
    /// (default) or by `penalty` (course notes §3.3, step 1).
    pub constraints: Constraints,
    /// Penalty stiffness of `method = "penalty"` and of the penalty-imposed
    /// status method, as a multiple of the contact stiffness 1/mean diag(W)
    /// (default 1e8). A `law = { penalty = k }` contact uses its own k.
    pub penalty: f64,
    /// Also the condition estimates that cost a factorisation of their own
    /// (κ(K) on the direct path: one more sparse LDLᵀ of the whole
    /// stiffness); default false: only those the run's own factors give.
    pub condition_estimate: bool,
}

/// `solver.status_changes`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StatusChanges {
    #[default]
    All,
    Single,
}

/// `solver.constraints`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Constraints {
    #[default]
    Multipliers,
    Penalty,
}

impl Default for Solver {
    fn default() -> Self {
        Solver {
            method: Method::Status,
            path: SolvePath::Auto,
            tolerance: 1e-10,
            max_iterations: 500,
            friction: FrictionSolver::FixedPoint,
            time_limit: None,
            status_changes: StatusChanges::All,
            constraints: Constraints::Multipliers,
            penalty: 1e8,
            condition_estimate: false,
        }
    }
}

/// `Display` (the spelling `as_str` gives) and `FromStr` (one of the
/// spellings of `ALL`, `-` accepted for `_`: `projected-gradient`; else an
/// error naming the valid ones) of a `[solver]` choice, the scene file's and
/// the command line's.
macro_rules! spelled_choice {
    ($choice:ident, $what:literal) => {
        impl fmt::Display for $choice {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.as_str())
            }
        }

        impl FromStr for $choice {
            type Err = String;
            fn from_str(s: &str) -> Result<Self, String> {
                let key = s.trim().replace('-', "_");
                $choice::ALL
                    .into_iter()
                    .find(|m| m.as_str() == key)
                    .ok_or_else(|| {
                        format!(
                            concat!("unknown ", $what, " \"{}\"; valid ", $what, "s: {}"),
                            s,
                            $choice::ALL.map($choice::as_str).join(", ")
                        )
                    })
            }
        }
    };
}

/// `solver.method`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    #[default]
    Status,
    Lemke,
    ProjectedGradient,
    Mprgp,
    Uzawa,
    AugmentedLagrangian,
    Penalty,
    /// Projected conjugate gradient (an addition to docs/reference/scene-format.md's list).
    ProjectedConjugateGradient,
}

impl Method {
    /// Every method, in the order of `docs/reference/scene-format.md`, then the additions.
    pub const ALL: [Method; 8] = [
        Method::Status,
        Method::Lemke,
        Method::ProjectedGradient,
        Method::Mprgp,
        Method::Uzawa,
        Method::AugmentedLagrangian,
        Method::Penalty,
        Method::ProjectedConjugateGradient,
    ];

    /// The scene-file / CLI spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            Method::Status => "status",
            Method::Lemke => "lemke",
            Method::ProjectedGradient => "projected_gradient",
            Method::Mprgp => "mprgp",
            Method::Uzawa => "uzawa",
            Method::AugmentedLagrangian => "augmented_lagrangian",
            Method::Penalty => "penalty",
            Method::ProjectedConjugateGradient => "projected_conjugate_gradient",
        }
    }
}

spelled_choice!(Method, "method");

/// `solver.path`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SolvePath {
    /// Static condensation onto the contact interface.
    Condensed,
    /// The full system.
    Direct,
    /// The cheaper of the two for the scene, estimated from its mesh and
    /// contact sizes before anything is built (docs/guide/choosing.md).
    #[default]
    Auto,
}

impl SolvePath {
    pub const ALL: [SolvePath; 3] = [SolvePath::Condensed, SolvePath::Direct, SolvePath::Auto];

    /// The scene-file / CLI spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            SolvePath::Condensed => "condensed",
            SolvePath::Direct => "direct",
            SolvePath::Auto => "auto",
        }
    }
}

spelled_choice!(SolvePath, "path");

/// `solver.friction`: the outer loop for friction.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrictionSolver {
    #[default]
    FixedPoint,
    Status,
    /// The fixed point on the threshold with each Tresca problem solved by
    /// the semi-smooth Newton method (2D; in 3D the fixed point already
    /// does).
    Newton,
    /// The nonsmooth Gauss–Seidel method, contact by contact (2D and 3D
    /// Coulomb).
    Nsgs,
}

impl FrictionSolver {
    /// The scene-file spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            FrictionSolver::FixedPoint => "fixed_point",
            FrictionSolver::Status => "status",
            FrictionSolver::Newton => "newton",
            FrictionSolver::Nsgs => "nsgs",
        }
    }
}
