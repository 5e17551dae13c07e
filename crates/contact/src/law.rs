//! The friction law of a contact point and the layout of the friction rows,
//! one type each for 2D and 3D (course notes §4.1).

use crate::ContactError;

pub mod cone;
pub mod hardening;
pub mod norton_hoff;
pub mod regularised;
pub use cone::natural_residual;

/// The friction law of one contact point (course notes §4.1).
///
/// One Coulomb variant carries the coefficients along the two tangents,
/// (λ_t1/μ1)² + (λ_t2/μ2)² ≤ λ_n² (the elliptic cone of §4.1.2; μ1 = μ2 is
/// the isotropic cone ‖λ_t‖ ≤ μ λ_n): the isotropic and the anisotropic
/// law have the same algebra (semi-axes μ_i λ_n), so a separate
/// anisotropic variant would only double every match. A point with one
/// tangential row (2D, or 3D with the second tangent prescribed by a
/// support) reads `mu[0]`; [`FrictionLaw::coulomb`] builds the isotropic law.
///
/// Norton–Hoff (§4.1.4, eq. 19) is a law of its own: its threshold
/// μ λ_n |Δs|^ρ depends on the slip, solved by
/// [`crate::friction::norton_hoff`]; the Tresca solvers see it unbounded.
/// The regularised Coulomb law (§4.1.3) is not a variant: its elastic slip
/// is the compliance 1/k_e added to W ([`regularised`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FrictionLaw {
    /// Frictionless: the tangential force (if the point has tangential
    /// rows) is zero.
    None,
    /// Tresca (§4.1.1): the tangential force is bounded by this threshold (a
    /// force), ‖λ_t‖ ≤ g.
    Tresca(f64),
    /// Coulomb (§4.1.2): (λ_t1/μ1)² + (λ_t2/μ2)² ≤ λ_n².
    Coulomb { mu: [f64; 2] },
    /// Norton–Hoff (§4.1.4): λ_t = −μ λ_n ‖Δs‖^(ρ−1) Δs, 0 < ρ < 1 (in 3D
    /// isotropic in the tangent plane).
    NortonHoff { mu: f64, rho: f64 },
}

impl FrictionLaw {
    /// The isotropic Coulomb law ‖λ_t‖ ≤ μ λ_n.
    pub fn coulomb(mu: f64) -> Self {
        FrictionLaw::Coulomb { mu: [mu, mu] }
    }

    /// The coefficients (μ1, μ2) of a Coulomb law.
    pub fn coulomb_mu(&self) -> Option<[f64; 2]> {
        match *self {
            FrictionLaw::Coulomb { mu } => Some(mu),
            _ => None,
        }
    }

    /// Whether it is Norton–Hoff's law.
    pub fn is_norton_hoff(&self) -> bool {
        matches!(self, FrictionLaw::NortonHoff { .. })
    }

    /// The semi-axes (g1, g2) of the admissible tangential forces with the
    /// normal force λ_n: Tresca (g, g), Coulomb μ_i max(λ_n, 0),
    /// frictionless zero; Norton–Hoff infinite (no bound: its threshold
    /// depends on the slip).
    pub fn semi_axes(&self, normal: f64) -> [f64; 2] {
        match *self {
            FrictionLaw::None => [0.0, 0.0],
            FrictionLaw::Tresca(g) => [g, g],
            FrictionLaw::Coulomb { mu } => {
                let n = normal.max(0.0);
                [mu[0] * n, mu[1] * n]
            }
            FrictionLaw::NortonHoff { .. } => [f64::INFINITY; 2],
        }
    }

    /// Whether the parameters are admissible: finite and non-negative, and
    /// for Norton–Hoff 0 < ρ < 1.
    fn is_valid(&self) -> bool {
        let ok = |v: f64| v >= 0.0 && v.is_finite();
        match *self {
            FrictionLaw::None => true,
            FrictionLaw::Tresca(g) => ok(g),
            FrictionLaw::Coulomb { mu } => mu.into_iter().all(ok),
            FrictionLaw::NortonHoff { mu, rho } => ok(mu) && rho > 0.0 && rho < 1.0,
        }
    }
}

/// The layout of the forces (and gaps) of the condensed problem with
/// friction: rows 0..m are the normal rows of the m contact points, then
/// each frictional point has its tangential rows (any rows ≥ m, each used
/// once): one in 2D; in 3D two, (t1, t2), or one, (t1), where a support
/// prescribes the slip along the other tangent (the admissible set is then
/// the segment |λ_t1| ≤ g1).
#[derive(Debug, Clone)]
pub struct FrictionLayout {
    /// The tangential rows of each point; empty for a frictionless point.
    pub tangent_rows: Vec<Vec<usize>>,
    /// The law of each point.
    pub law: Vec<FrictionLaw>,
    /// 2D: for a point whose tangential row constrains the same motion as
    /// the normal row of another point (a corner node on a frictional floor
    /// and against a wall: its slip along the floor is the wall's gap), that
    /// other point (see `signorini_geometry::redundancy::tangent_shadows`); may be
    /// empty.
    pub shadow: Vec<Option<usize>>,
}

impl FrictionLayout {
    pub fn n_points(&self) -> usize {
        self.tangent_rows.len()
    }

    /// The tangential row of point p in 2D (its only one), if it has friction.
    pub fn tangent_row(&self, p: usize) -> Option<usize> {
        self.tangent_rows[p].first().copied()
    }

    /// Whether a point with tangential rows has a Coulomb law.
    pub fn has_coulomb(&self) -> bool {
        self.law
            .iter()
            .zip(&self.tangent_rows)
            .any(|(l, t)| !t.is_empty() && l.coulomb_mu().is_some())
    }

    /// Whether a point with tangential rows has a Norton–Hoff law.
    pub fn has_norton_hoff(&self) -> bool {
        (self.law.iter().zip(&self.tangent_rows)).any(|(l, t)| !t.is_empty() && l.is_norton_hoff())
    }

    /// The semi-axes of each point's admissible set of tangential forces,
    /// Coulomb ones from the normal forces `r` ([`FrictionLaw::semi_axes`]).
    pub fn thresholds(&self, r: &[f64]) -> Vec<[f64; 2]> {
        let laws = self.law.iter().enumerate();
        laws.map(|(p, law)| law.semi_axes(r[p])).collect()
    }

    /// Checks the layout of a problem with `n_rows` rows in dimension `dim`
    /// (2 or 3): one law per point, at most dim − 1 tangential rows per
    /// point, every row owned by exactly one point, admissible parameters
    /// (Norton–Hoff 0 < ρ < 1).
    pub fn validate(&self, n_rows: usize, dim: usize) -> Result<(), ContactError> {
        let m = self.n_points();
        let bad = |what: String| Err(ContactError::Geometry(format!("friction {dim}D: {what}")));
        if self.law.len() != m {
            return bad(format!("{} laws for {m} contact points", self.law.len()));
        }
        if m > n_rows {
            return bad(format!("{m} contact points but only {n_rows} rows"));
        }
        let mut owner = vec![false; n_rows];
        owner[..m].iter_mut().for_each(|o| *o = true);
        for (p, rows) in self.tangent_rows.iter().enumerate() {
            if rows.len() > dim - 1 {
                let n = rows.len();
                return bad(format!(
                    "point {p} has {n} tangential rows (at most {})",
                    dim - 1
                ));
            }
            for &t in rows {
                if t < m || t >= n_rows || owner[t] {
                    return bad(format!(
                        "tangential row {t} of point {p} is out of range or used twice"
                    ));
                }
                owner[t] = true;
            }
        }
        if let Some(i) = owner.iter().position(|o| !o) {
            return bad(format!("row {i} belongs to no contact point"));
        }
        for (p, law) in self.law.iter().enumerate() {
            if !law.is_valid() {
                return bad(format!(
                    "point {p} has a negative or non-finite friction parameter"
                ));
            }
        }
        Ok(())
    }
}
