//! One subdomain (a body, or a METIS part of one), owned by one rank: it
//! assembles its stiffness K_i from its own cells, factorises it once with its
//! interface last, sends S_i and F'_i to the root (course notes §8.2–8.3), and later
//! recovers its interior from the interface displacement.
//!
//! The interface of a subdomain holds its free DOFs on the nodes it shares
//! with other parts of its body (glued: the assembled S makes them equal) and
//! on contact surfaces. A nodal force on a shared node is counted by the
//! lowest-numbered part that holds the node, so that the assembled load is the
//! body's.

use faer::sparse::SparseColMat;
use faer::Par;
use serde::{Deserialize, Serialize};
use signorini_condense::{spmv, spmv_with_magnitude, submatrix, Condensed, FactorStats};
use signorini_mesh::Mesh;

use crate::contact_frames::LocalFrames;
use crate::model::BodyModel;
use crate::progress::{Event, Progress};

/// Which cells and nodes of which body a subdomain holds (computed the same
/// way on every rank).
#[derive(Debug, Clone)]
pub struct SubdomainSpec {
    pub body: usize,
    pub part: usize,
    pub cells: Vec<usize>,
    /// Body node indices, sorted.
    pub nodes: Vec<usize>,
}

impl SubdomainSpec {
    /// Estimated cost of the factorisation, to deal subdomains to ranks.
    pub fn cost(&self) -> f64 {
        (self.nodes.len() as f64).powf(1.5)
    }

    /// The body DOF of local DOF `l` (`dim` DOFs per node).
    fn body_dof(&self, dim: usize, l: usize) -> usize {
        dim * self.nodes[l / dim] + l % dim
    }

    /// The subdomain's own mesh: its cells of the body, on its nodes
    /// numbered locally (no surfaces or regions).
    pub(crate) fn local_mesh(&self, body: &BodyModel) -> Mesh {
        let mut local_of = vec![usize::MAX; body.mesh.n_nodes()];
        for (l, &n) in self.nodes.iter().enumerate() {
            local_of[n] = l;
        }
        Mesh {
            dim: body.mesh.dim,
            coords: self.nodes.iter().map(|&n| body.mesh.coords[n]).collect(),
            cells: self
                .cells
                .iter()
                .map(|&c| {
                    let cell = &body.mesh.cells[c];
                    signorini_mesh::Cell {
                        kind: cell.kind,
                        nodes: cell.nodes.iter().map(|&n| local_of[n]).collect(),
                    }
                })
                .collect(),
            surfaces: Default::default(),
            regions: Default::default(),
            node_sets: Default::default(),
        }
    }
}

/// A subdomain's loads per load entry of its body, on its local DOFs.
struct LocalLoads {
    /// External force (owned nodes only).
    force: Vec<Vec<f64>>,
    /// Prescribed displacement.
    displacement: Vec<Vec<f64>>,
    /// force_f − K_fp u_p on the free local DOFs.
    free_load: Vec<Vec<f64>>,
}

impl LocalLoads {
    /// Each load entry of the body restricted to the subdomain: the force
    /// on the nodes it owns (`owner_part`), the prescribed displacement, and
    /// the load they make on its free DOFs through `k_local`.
    fn of(
        spec: &SubdomainSpec,
        body: &BodyModel,
        owner_part: &[usize],
        k_local: &SparseColMat<usize, f64>,
        free: &[usize],
        frames: &LocalFrames,
    ) -> Self {
        let dim = body.mesh.dim;
        let n_local = dim * spec.nodes.len();
        let mut out = LocalLoads {
            force: Vec::new(),
            displacement: Vec::new(),
            free_load: Vec::new(),
        };
        for load in &body.loads {
            let f: Vec<f64> = (0..n_local)
                .map(|l| {
                    let d = spec.body_dof(dim, l);
                    if owner_part[d / dim] == spec.part {
                        load.force[d]
                    } else {
                        0.0
                    }
                })
                .collect();
            let u: Vec<f64> = (0..n_local)
                .map(|l| load.displacement[spec.body_dof(dim, l)])
                .collect();
            let (f, u) = (frames.to_local(&f), frames.to_local(&u));
            let ku = spmv(k_local.as_ref(), &u);
            out.free_load
                .push(free.iter().map(|&l| f[l] - ku[l]).collect::<Vec<f64>>());
            out.force.push(f);
            out.displacement.push(u);
        }
        out
    }
}

/// Splits every body into its parts.
pub fn subdomain_specs(bodies: &[BodyModel]) -> Vec<SubdomainSpec> {
    let mut out = Vec::new();
    for (bi, b) in bodies.iter().enumerate() {
        for part in 0..b.n_parts {
            let cells: Vec<usize> = (0..b.mesh.cells.len())
                .filter(|&c| b.parts[c] == part)
                .collect();
            let mut nodes: Vec<usize> = cells
                .iter()
                .flat_map(|&c| b.mesh.cells[c].nodes.iter().copied())
                .collect();
            nodes.sort_unstable();
            nodes.dedup();
            out.push(SubdomainSpec {
                body: bi,
                part,
                cells,
                nodes,
            });
        }
    }
    out
}

/// What a subdomain sends to the root after condensation.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CondensedData {
    pub id: usize,
    /// Γ index of each interface DOF.
    pub gamma: Vec<usize>,
    /// S_i, column-major n_b × n_b.
    pub schur: Vec<f64>,
    /// F'_i of each load entry of the body, at scale 1.
    pub fprime: Vec<Vec<f64>>,
    pub dofs: usize,
    pub factor_bytes: usize,
    /// The factor's ordering, size and flops, and every ordering compared
    /// (the kept one first).
    pub factor: Vec<FactorSummary>,
    /// Estimated κ₁(K_II) of the subdomain's interior stiffness (Hager–Higham
    /// on its own factor); `None` without interior DOFs.
    pub k_ii_condition: Option<f64>,
}

impl CondensedData {
    /// What subdomain `id` sends to the root: its Γ indices, its Schur
    /// complement (column-major), the condensed load of each entry, its
    /// free DOF count and the size and condition of its factor.
    fn of(
        id: usize,
        condensed: &mut Condensed,
        gamma: &[usize],
        free_load: &[Vec<f64>],
        dofs: usize,
    ) -> Self {
        let nb = gamma.len();
        let dense = condensed.take_schur();
        let mut schur = Vec::with_capacity(nb * nb);
        for j in 0..nb {
            schur.extend_from_slice(dense.col_as_slice(j));
        }
        drop(dense);
        CondensedData {
            id,
            gamma: gamma.to_vec(),
            schur,
            fprime: free_load
                .iter()
                .map(|f| condensed.condensed_load(f))
                .collect(),
            dofs,
            factor_bytes: condensed.memory_bytes(),
            factor: condensed
                .ordering_candidates()
                .iter()
                .map(FactorSummary::of)
                .collect(),
            k_ii_condition: condensed.interior_condition_estimate(),
        }
    }
}

/// A factor's ordering, size and flops, as a subdomain sends them.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FactorSummary {
    /// `Ordering::as_str`.
    pub ordering: String,
    pub nnz: usize,
    /// Stored values (8 bytes each).
    pub values: usize,
    pub flops: f64,
}

impl FactorSummary {
    pub fn of(stats: &FactorStats) -> Self {
        FactorSummary {
            ordering: stats.ordering.as_str().to_string(),
            nnz: stats.nnz,
            values: stats.values,
            flops: stats.flops,
        }
    }
}

/// What a subdomain sends back after the recovery of one load step.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RecoveredStep {
    pub id: usize,
    /// The largest residual of K_i u_i − f_i on interior DOFs.
    pub interior_residual: f64,
    /// The largest |K_i u_i| or |f_i| entry (scale).
    pub force_scale: f64,
    /// K_i u_i − f_i on the interface DOFs, as (Γ index, value).
    pub gamma_residual: Vec<(usize, f64)>,
    /// The displacement of the subdomain's nodes (`SubdomainSpec::nodes`,
    /// `dim` values per node).
    pub displacement: Vec<f64>,
    /// K_i u_i − f_i on its prescribed DOFs, as (body DOF, value): the
    /// supports' share of the reactions (Cartesian: a node with a prescribed
    /// DOF is never rotated into a contact frame).
    pub support_residual: Vec<(usize, f64)>,
}

/// A condensed subdomain kept by its rank for the recovery.
pub struct Subdomain {
    pub id: usize,
    /// Space dimension (DOFs per node).
    dim: usize,
    spec: SubdomainSpec,
    k_local: SparseColMat<usize, f64>,
    k_ff: SparseColMat<usize, f64>,
    free: Vec<usize>,
    gamma: Vec<usize>,
    condensed: Condensed,
    /// Per load entry: external force on the local DOFs (owned nodes only).
    force: Vec<Vec<f64>>,
    /// Per load entry: prescribed displacement on the local DOFs.
    displacement: Vec<Vec<f64>>,
    /// Per load entry: force_f − K_fp u_p on the free local DOFs.
    free_load: Vec<Vec<f64>>,
    /// The contact frames of its nodes: K, the loads and the displacements
    /// above are in the rotated components ũ = Tᵀ u.
    frames: LocalFrames,
}

impl Subdomain {
    /// Assembles and condenses the subdomain. `gamma_of` maps a body DOF to
    /// its Γ index (usize::MAX if not on Γ); `owner_part` gives the part that
    /// counts the nodal forces of each body node.
    pub(crate) fn condense(
        id: usize,
        spec: &SubdomainSpec,
        body: &BodyModel,
        (gamma_of, owner_part): (&[usize], &[usize]),
        frames: LocalFrames,
        (par, progress): (Par, &Progress),
    ) -> Result<(Self, CondensedData), String> {
        let dim = body.mesh.dim;
        let mesh = spec.local_mesh(body);
        progress.emit(Event::Detail("assembling"));
        let mut k_local = signorini_fem::try_assemble_stiffness_par(&mesh, &body.material, par)
            .map_err(|e| e.to_string())?;
        if !frames.is_identity() {
            k_local = frames.rotate_stiffness(k_local)?;
        }
        let n_local = dim * spec.nodes.len();
        let free: Vec<usize> = (0..n_local)
            .filter(|&l| !body.prescribed[spec.body_dof(dim, l)])
            .collect();
        let k_ff = submatrix(k_local.as_ref(), &free, &free);
        let mut interface = Vec::new();
        let mut gamma = Vec::new();
        for (i, &l) in free.iter().enumerate() {
            let g = gamma_of[spec.body_dof(dim, l)];
            if g != usize::MAX {
                interface.push(i);
                gamma.push(g);
            }
        }
        let loads = LocalLoads::of(spec, body, owner_part, &k_local, &free, &frames);
        progress.emit(Event::Detail("factorising"));
        let mut condensed =
            Condensed::new(k_ff.as_ref(), &interface, par).map_err(|e| e.to_string())?;
        let data = CondensedData::of(id, &mut condensed, &gamma, &loads.free_load, free.len());
        Ok((
            Self {
                id,
                dim,
                spec: spec.clone(),
                k_local,
                k_ff,
                free,
                gamma,
                condensed,
                force: loads.force,
                displacement: loads.displacement,
                free_load: loads.free_load,
                frames,
            },
            data,
        ))
    }

    /// Recovers one load step (load scales `s` of the body's entries) from
    /// its interface displacement `ug` and reports the residuals the root
    /// needs for the certificate.
    pub fn recover_step(&self, s: &[f64], ug: &[f64]) -> RecoveredStep {
        let n_local = self.dim * self.spec.nodes.len();
        let mut is_interface = vec![false; n_local];
        for &i in self.condensed.interface() {
            is_interface[self.free[i]] = true;
        }
        let combine = |v: &[Vec<f64>], n: usize| {
            let mut o = vec![0.0; n];
            for (vb, &sb) in v.iter().zip(s) {
                for (oi, x) in o.iter_mut().zip(vb) {
                    *oi += sb * x;
                }
            }
            o
        };
        let fl = combine(&self.free_load, self.free.len());
        let f = combine(&self.force, n_local);
        let mut u = combine(&self.displacement, n_local);
        let ub: Vec<f64> = self.gamma.iter().map(|&g| ug[g]).collect();
        let uf = self.condensed.recover(self.k_ff.as_ref(), &fl, &ub);
        for (i, &l) in self.free.iter().enumerate() {
            u[l] = uf[i];
        }
        // The scale of the residual: the internal forces term by term
        // (|K||u|), not their sum, which cancels in a stiff body.
        let (ku, abs_ku) = spmv_with_magnitude(self.k_local.as_ref(), &u);
        let mut out = RecoveredStep {
            id: self.id,
            interior_residual: 0.0,
            force_scale: 0.0,
            gamma_residual: Vec::new(),
            displacement: Vec::new(),
            support_residual: Vec::new(),
        };
        let mut gi = 0;
        for &l in &self.free {
            let r = ku[l] - f[l];
            out.force_scale = out.force_scale.max(abs_ku[l]).max(f[l].abs());
            if is_interface[l] {
                out.gamma_residual.push((self.gamma[gi], r));
                gi += 1;
            } else {
                out.interior_residual = out.interior_residual.max(r.abs());
            }
        }
        out.support_residual = self.support_residual(&ku, &f);
        out.displacement = self.frames.to_cartesian(&u);
        out
    }

    /// K_i u_i − f_i on the prescribed local DOFs (`ku`, `f`: on every
    /// local DOF), as (body DOF, value).
    fn support_residual(&self, ku: &[f64], f: &[f64]) -> Vec<(usize, f64)> {
        let mut is_free = vec![false; ku.len()];
        for &l in &self.free {
            is_free[l] = true;
        }
        (0..ku.len())
            .filter(|&l| !is_free[l])
            .map(|l| (self.spec.body_dof(self.dim, l), ku[l] - f[l]))
            .collect()
    }
}
