//! The whole system of the direct path: every body's sparse stiffness and
//! the global one on the free DOFs (tied DOFs eliminated, `crate::ties`), a
//! step's loads, the floating bodies' equilibrium check, each body's full
//! displacement and the equilibrium residuals; what the frictionless
//! ([`crate::direct_path`]) and the frictional ([`crate::direct_friction`])
//! direct paths share.

use crate::checks::{check_floating_equilibrium, inf_norm};
use crate::direct_balance::contact_forces;
use crate::error::SolveError;
use crate::friction_step::deadline;
use crate::model::{BodyModel, PointModel, Ties};
use crate::root::{body_step, resultant};
use crate::step::{FrictionStep, Residuals};
use crate::ties::TieReduction;
use faer::sparse::SparseColMat;
use signorini_condense::{spmv, spmv_with_magnitude, submatrix};
use signorini_contact::options::default_time_limit;
use std::time::Instant;

/// Seconds a solve on the direct path (the status method without friction,
/// the semi-smooth Newton method with it) may take by default for each
/// unknown of its whole system (u and λ), beside the dense problem's
/// [`default_time_limit`] (sized for a factorisation of W, not of the whole
/// system): each Newton iteration here is one sparse LU of the whole
/// Jacobian, about 2e-5 s an unknown on the idle 2-core machine of
/// docs/performance (2.6 s for the 122 000 unknowns of the 100 × 100 pad),
/// a solve may take a hundred iterations with its retry (the three-body
/// assembly's first step: 78), and a loaded machine several times longer:
/// the Cattaneo example's first step (42 281 DOFs) was cut at the dense
/// default of 10 s while still converging.
const SECONDS_PER_UNKNOWN: f64 = 2e-2;

/// The stiffness of the direct path: each body's whole stiffness, and the
/// global one over the free DOFs of all bodies, body after body.
pub(crate) struct DirectSystem {
    pub(crate) k_full: Vec<SparseColMat<usize, f64>>,
    /// Where each body's free DOFs start in the global numbering.
    pub(crate) offset: Vec<usize>,
    pub(crate) k_global: SparseColMat<usize, f64>,
    pub(crate) n_free: usize,
    /// The elimination of the tied DOFs from the free ones (`crate::ties`):
    /// `k_global` is then Tᵀ K T.
    pub(crate) ties: Option<TieReduction>,
    /// The tied DOFs (for the ties' forces).
    pub(crate) tied: Ties,
}

impl DirectSystem {
    /// The time at which a step's contact solve of `rows` contact rows
    /// stops: `time_limit` (the scene's `solver.time_limit`) seconds from
    /// now, by default that of the dense problem of `rows` rows
    /// ([`default_time_limit`]) plus [`SECONDS_PER_UNKNOWN`] for each
    /// unknown of the whole system.
    pub(crate) fn deadline(&self, time_limit: Option<f64>, rows: usize) -> Instant {
        let unknowns = (self.k_global.nrows() + rows) as f64;
        let seconds =
            time_limit.unwrap_or_else(|| default_time_limit(rows) + SECONDS_PER_UNKNOWN * unknowns);
        deadline(Some(seconds), rows)
    }
}

/// Assembles every body's stiffness and the global stiffness on the free
/// DOFs (the bodies' free-free blocks on the diagonal).
pub(crate) fn assemble_direct(
    bodies: &[BodyModel],
    tied: &Ties,
) -> Result<DirectSystem, SolveError> {
    let mut k_full = Vec::new();
    let mut offset = Vec::new();
    let mut triplets = Vec::new();
    let mut n_free = 0;
    for b in bodies {
        let par = faer::get_global_parallelism();
        let k = signorini_fem::try_assemble_stiffness_par(&b.mesh, &b.material, par)
            .map_err(|e| SolveError::Input(format!("bodies[{}].mesh: {e}", b.scene_index)))?;
        let kff = submatrix(k.as_ref(), &b.free, &b.free);
        for j in 0..kff.ncols() {
            for (&i, &v) in kff.row_idx_of_col_raw(j).iter().zip(kff.val_of_col(j)) {
                triplets.push(faer::sparse::Triplet::new(n_free + i, n_free + j, v));
            }
        }
        offset.push(n_free);
        n_free += b.free.len();
        k_full.push(k);
    }
    let mut k_global = SparseColMat::<usize, f64>::try_new_from_triplets(n_free, n_free, &triplets)
        .map_err(|e| SolveError::Internal(format!("{e:?}")))?;
    let index: Vec<Vec<usize>> = bodies
        .iter()
        .zip(&offset)
        .map(|(b, &o)| {
            (b.free_index.iter())
                .map(|&i| if i == usize::MAX { i } else { o + i })
                .collect()
        })
        .collect();
    let ties = TieReduction::new(tied, &index, n_free);
    if let Some(t) = &ties {
        k_global = t.reduce_matrix(&k_global)?;
    }
    Ok(DirectSystem {
        k_full,
        offset,
        k_global,
        n_free,
        ties,
        tied: tied.clone(),
    })
}

/// Checks that each floating body's loads can be balanced by contact
/// (`check_floating_equilibrium`): the work e = −Rᵀ f of the free load on
/// its rigid motions, and the resultant of its external force.
pub(crate) fn check_floating(
    bodies: &[BodyModel],
    points: &[PointModel],
    system: &DirectSystem,
    loads: &DirectLoads,
    si: usize,
) -> Result<(), SolveError> {
    let e_of: Vec<Vec<f64>> = bodies
        .iter()
        .enumerate()
        .map(|(bi, b)| {
            b.kernel
                .iter()
                .map(|r| {
                    -b.free
                        .iter()
                        .enumerate()
                        .map(|(i, &d)| r[d] * loads.f[system.offset[bi] + i])
                        .sum::<f64>()
                })
                .collect()
        })
        .collect();
    let res: Vec<Vec<f64>> = loads
        .forces
        .iter()
        .zip(bodies)
        .map(|(f, b)| resultant(f, b.mesh.dim))
        .collect();
    check_floating_equilibrium(bodies, points, &e_of, &res, si)?;
    Ok(())
}

/// Each body's full displacement: the prescribed `u_p`, and on its free
/// DOFs the global solution `u`.
pub(crate) fn full_displacements(
    bodies: &[BodyModel],
    system: &DirectSystem,
    u_p: &[Vec<f64>],
    u: &[f64],
) -> Vec<Vec<f64>> {
    bodies
        .iter()
        .enumerate()
        .map(|(bi, b)| {
            let mut full = u_p[bi].clone();
            for (i, &d) in b.free.iter().enumerate() {
                full[d] = u[system.offset[bi] + i];
            }
            full
        })
        .collect()
}

/// The loads of a step on the direct path.
pub(crate) struct DirectLoads {
    /// Global load on the free DOFs: f − K u_p.
    pub(crate) f: Vec<f64>,
    /// Each body's prescribed displacement.
    pub(crate) u_p: Vec<Vec<f64>>,
    /// Each body's external force.
    pub(crate) forces: Vec<Vec<f64>>,
    /// The largest external or free-DOF load entry.
    pub(crate) f_scale: f64,
}

/// A step's loads: each body's prescribed displacement and force at the
/// step's scales, and the global load f − K u_p on the free DOFs.
pub(crate) fn direct_loads(
    bodies: &[BodyModel],
    system: &DirectSystem,
    st: &[Vec<f64>],
) -> DirectLoads {
    let mut f = vec![0.0; system.n_free];
    let mut u_p = Vec::new();
    let mut forces = Vec::new();
    let mut f_scale = 0.0f64;
    for (bi, b) in bodies.iter().enumerate() {
        let (u, force) = body_step(b, &st[bi]);
        let ku = spmv(system.k_full[bi].as_ref(), &u);
        for (i, &d) in b.free.iter().enumerate() {
            f[system.offset[bi] + i] = force[d] - ku[d];
        }
        f_scale = f_scale.max(inf_norm(&force));
        u_p.push(u);
        forces.push(force);
    }
    f_scale = f_scale.max(inf_norm(&f));
    DirectLoads {
        f,
        u_p,
        forces,
        f_scale,
    }
}

/// Equilibrium residual of the direct path on the free DOFs of every body:
/// K u − f − Bᵀλ (with `friction`, the tangential rows times the
/// tangential forces in Bᵀλ); and K u − f on the prescribed ones (the
/// reactions).
pub(crate) fn direct_residuals(
    bodies: &[BodyModel],
    k_full: &[SparseColMat<usize, f64>],
    points: &[PointModel],
    forces: &[Vec<f64>],
    u_full: &[Vec<f64>],
    lambda: &[f64],
    friction: Option<&FrictionStep>,
) -> Residuals {
    let contact_force = contact_forces(bodies, points, lambda, friction);
    let mut eq = 0.0f64;
    let mut scale = 0.0f64;
    let mut support = Vec::new();
    for (bi, b) in bodies.iter().enumerate() {
        let (ku, abs_ku) = spmv_with_magnitude(k_full[bi].as_ref(), &u_full[bi]);
        support.extend(
            (0..b.n_dof)
                .filter(|&d| b.prescribed[d])
                .map(|d| (bi, d, ku[d] - forces[bi][d])),
        );
        for d in (0..b.n_dof).filter(|&d| !b.prescribed[d]) {
            eq = eq.max((ku[d] - forces[bi][d] - contact_force[bi][d]).abs());
            scale = scale
                .max(abs_ku[d])
                .max(forces[bi][d].abs())
                .max(contact_force[bi][d].abs());
        }
    }
    Residuals {
        equilibrium: eq,
        force_scale: scale,
        support,
        ties: Vec::new(),
    }
}

/// The residual K u − f − Bᵀλ on the free DOFs of every body (in the
/// global numbering): at the tied slave DOFs, the force the tie exerts; the
/// equilibrium residual is Tᵀ r (the tie's forces are internal).
pub(crate) fn tied_residual(
    bodies: &[BodyModel],
    system: &DirectSystem,
    forces: &[Vec<f64>],
    u_full: &[Vec<f64>],
    points: &[PointModel],
    lambda: &[f64],
) -> Vec<f64> {
    let mut r = vec![0.0; system.n_free];
    for (bi, b) in bodies.iter().enumerate() {
        let ku = spmv(system.k_full[bi].as_ref(), &u_full[bi]);
        for (i, &d) in b.free.iter().enumerate() {
            r[system.offset[bi] + i] = ku[d] - forces[bi][d];
        }
    }
    for (p, &l) in points.iter().zip(lambda) {
        for &(b, d, c) in p.row.iter().filter(|&&(b, d, _)| !bodies[b].prescribed[d]) {
            r[system.offset[b] + bodies[b].free_index[d]] -= c * l;
        }
    }
    r
}
