//! The factor of S = Σ_i S_i (course notes §8.3; docs/architecture.md, "Libraries") over a tree of subdomains:
//! a multifrontal Cholesky whose fronts are the subdomains' dense Schur
//! complements, merged two by two.
//!
//! The subdomains are paired by the Γ DOFs they share (most first, as the
//! two halves of a bisection), the pairs paired again, and so on. When two
//! groups merge, their blocks are added on the union of their DOFs, and
//! the DOFs no other group holds (the glue between the two, not a contact
//! DOF) are eliminated:
//!
//! ```text
//!   F = [F_EE F_ER; F_RE F_RR],   L_EE L_EEᵀ = F_EE,
//!   L_RE = F_RE L_EE⁻ᵀ,           T = F_RR − L_RE L_REᵀ
//! ```
//!
//! and T, dense on what remains, goes on up. At the top only the contact
//! DOFs C remain: L_CC L_CCᵀ = T, and W = B S⁺ Bᵀ = YᵀY with Y = L_CC⁻¹ B_C
//! as for any factor with C last. This is the sparse Cholesky of S in the
//! order of the tree (nested dissection by the decomposition itself): the
//! same flops as a supernodal factor in that order, but the merges of one
//! level are independent and run side by side, one per core, and S is never
//! assembled (the blocks are added into the fronts).
//!
//! Floating bodies: the fixing DOFs J of their kernel (FETI's generalised
//! inverse, `interface` module doc) have their rows and columns dropped
//! from every block and `scale` on their diagonal: S̃, factorised the same
//! way; S⁺ = S̃⁻¹ Z.

use faer::linalg::matmul::triangular::{matmul, BlockStructure};
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, Mat, MatMut, Par};

use signorini_linalg::ordered_cholesky::{add_trailing_delassus, dense_solve};
use signorini_linalg::sparse::SparseRow;

/// One subdomain's Schur complement: dense (column-major) on its Γ DOFs.
pub struct SchurBlock {
    pub gamma: Vec<usize>,
    pub values: Vec<f64>,
}

/// A group of subdomains merged so far: the Γ DOFs it still holds and
/// what S̃ is on them once the group's own glue is gone.
struct Group {
    dofs: Vec<usize>,
    t: Entries,
}

/// A group's matrix: a subdomain's block as it came (column-major, both
/// triangles, on its Γ DOFs in their order; `leaf` its index), or the lower
/// triangle of what a merge left.
enum Entries {
    Block { values: Vec<f64>, leaf: usize },
    Lower(Mat<f64>),
}

/// The fixing DOFs: their rows and columns of the blocks are dropped, and
/// `scale` goes on their diagonal from the first block holding them.
struct Fixing {
    is_fixed: Vec<bool>,
    first_holder: Vec<usize>,
    scale: f64,
}

/// One merge: the DOFs it eliminated, those it passed on, and its factor.
struct Front {
    eliminated: Vec<usize>,
    remaining: Vec<usize>,
    l_ee: Mat<f64>,
    l_re: Mat<f64>,
}

/// S̃ = P L Lᵀ Pᵀ over the tree of subdomains (module doc).
pub struct TreeFactor {
    /// Children before parents.
    fronts: Vec<Front>,
    /// The groups left at the top (one per set of subdomains sharing Γ
    /// DOFs, i.e. per body) on their contact DOFs.
    tops: Vec<Top>,
    /// Flops of the factorisation.
    pub flops: f64,
    /// Bytes of the factor.
    pub bytes: usize,
}

/// A top group: its contact DOFs (sorted) and L_CC L_CCᵀ of what S̃ is there.
struct Top {
    dofs: Vec<usize>,
    l: Mat<f64>,
}

/// The factorisation met a pivot that is not positive: S̃ is not positive
/// definite. `dof` is the Γ DOF of that pivot (S̃ is block diagonal over
/// the disconnected pieces of Γ, so the DOF lies in a piece that is
/// singular).
#[derive(Debug)]
pub struct NotPositiveDefinite {
    pub dof: usize,
}

impl TreeFactor {
    /// Factorises S̃ (module doc) of the `blocks` on n Γ DOFs with the
    /// `contact` DOFs last, the `fixed` DOFs (sorted) replaced by `scale`·I.
    pub fn new(
        n: usize,
        blocks: Vec<SchurBlock>,
        contact: &[usize],
        fixed: &[usize],
        scale: f64,
    ) -> Result<Self, NotPositiveDefinite> {
        let mut keep = vec![false; n];
        contact
            .iter()
            .filter(|&&i| i < n)
            .for_each(|&i| keep[i] = true);
        let (mut groups, mut holders, fixing) = leaves(n, blocks, fixed, scale);
        let mut fronts = Vec::new();
        let mut flops = 0.0;
        while let Some(sets) = pairing(&groups, n) {
            let (merged, level_fronts, level_flops) =
                merge_level(groups, sets, &holders, &keep, &fixing)?;
            holders.iter_mut().for_each(|h| *h = 0);
            merged
                .iter()
                .for_each(|g| g.dofs.iter().for_each(|&d| holders[d] += 1));
            groups = merged;
            fronts.extend(level_fronts);
            flops += level_flops;
        }
        // The groups left share no DOF (one per body): each eliminates all
        // but its contact DOFs, then L_CC of its own.
        let par = faer::get_global_parallelism();
        let mut tops = Vec::with_capacity(groups.len());
        for g in groups {
            let (front, dofs, mut l, top_flops) =
                merge_and_eliminate(vec![g], |d, _| !keep[d], &fixing, par)?;
            fronts.extend(front);
            signorini_linalg::recursive_cholesky::cholesky(l.as_mut(), par)
                .map_err(|i| NotPositiveDefinite { dof: dofs[i] })?;
            flops += top_flops + (l.nrows() as f64).powi(3) / 3.0;
            tops.push(Top { dofs, l });
        }
        let bytes = 8 * fronts
            .iter()
            .map(|f| f.l_ee.nrows() * f.l_ee.ncols() + f.l_re.nrows() * f.l_re.ncols())
            .chain(tops.iter().map(|t| t.l.nrows() * t.l.ncols()))
            .sum::<usize>();
        Ok(Self {
            fronts,
            tops,
            flops,
            bytes,
        })
    }

    /// The lower triangle of W += B S⁺ Bᵀ for the contact rows `b`
    /// (module doc: Σ YᵀY over the top groups, Y = L_CC⁻¹ B_C), the
    /// entries of B on the `fixed` DOFs dropped (S⁺ = S̃⁻¹ Z).
    pub(super) fn add_delassus(
        &self,
        w: &mut Mat<f64>,
        b: &[SparseRow],
        fixed: &[usize],
        par: Par,
    ) {
        for top in &self.tops {
            add_trailing_delassus(w, top.l.as_ref(), &top.dofs, fixed, b, par);
        }
    }

    /// x ← S̃⁻¹ x: forward through the fronts (children first), L_CC, and
    /// back.
    pub fn solve_in_place(&self, mut x: MatMut<'_, f64>, par: Par) {
        let k = x.ncols();
        let gather = |x: &MatMut<'_, f64>, rows: &[usize]| {
            Mat::<f64>::from_fn(rows.len(), k, |i, j| x[(rows[i], j)])
        };
        for f in &self.fronts {
            let mut xe = gather(&x, &f.eliminated);
            solve_lower_triangular_in_place(f.l_ee.as_ref(), xe.as_mut(), par);
            let update = &f.l_re * &xe;
            scatter(&mut x, &f.eliminated, &xe, false);
            scatter(&mut x, &f.remaining, &(-update), true);
        }
        for top in &self.tops {
            dense_solve(&top.l, &top.dofs, x.rb_mut(), par);
        }
        for f in self.fronts.iter().rev() {
            let xr = gather(&x, &f.remaining);
            let mut xe = gather(&x, &f.eliminated);
            xe -= f.l_re.transpose() * &xr;
            solve_upper_triangular_in_place(f.l_ee.transpose(), xe.as_mut(), par);
            scatter(&mut x, &f.eliminated, &xe, false);
        }
    }
}

/// x[rows] = v, or x[rows] += v with `add`.
fn scatter(x: &mut MatMut<'_, f64>, rows: &[usize], v: &Mat<f64>, add: bool) {
    for j in 0..v.ncols() {
        for (i, &r) in rows.iter().enumerate() {
            let old = if add { x[(r, j)] } else { 0.0 };
            x[(r, j)] = old + v[(i, j)];
        }
    }
}

/// The subdomains' blocks as groups (moved, not copied: each leaves memory
/// once merged), how many hold each Γ DOF, and the fixing DOFs with the
/// first block holding each.
fn leaves(
    n: usize,
    blocks: Vec<SchurBlock>,
    fixed: &[usize],
    scale: f64,
) -> (Vec<Group>, Vec<usize>, Fixing) {
    let mut holders = vec![0usize; n];
    let mut fixing = Fixing {
        is_fixed: vec![false; n],
        first_holder: vec![usize::MAX; n],
        scale,
    };
    fixed.iter().for_each(|&d| fixing.is_fixed[d] = true);
    for (leaf, b) in blocks.iter().enumerate().rev() {
        for &d in &b.gamma {
            holders[d] += 1;
            fixing.first_holder[d] = leaf;
        }
    }
    let groups = blocks
        .into_iter()
        .enumerate()
        .map(|(leaf, b)| Group {
            dofs: b.gamma,
            t: Entries::Block {
                values: b.values,
                leaf,
            },
        })
        .collect();
    (groups, holders, fixing)
}

/// The groups of one level in sets to merge: pairs sharing the most DOFs
/// first, each group in one set; a group left over passes on alone. None
/// when no two groups share a DOF (what is left is one group per body).
fn pairing(groups: &[Group], n: usize) -> Option<Vec<Vec<usize>>> {
    let mut holder_of: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (g, group) in groups.iter().enumerate() {
        group.dofs.iter().for_each(|&d| holder_of[d].push(g));
    }
    let mut shared: std::collections::HashMap<(usize, usize), usize> = Default::default();
    for h in holder_of.iter().filter(|h| h.len() > 1) {
        for (a, &ga) in h.iter().enumerate() {
            for &gb in &h[a + 1..] {
                *shared.entry((ga, gb)).or_default() += 1;
            }
        }
    }
    if shared.is_empty() {
        return None;
    }
    let mut candidates: Vec<((usize, usize), usize)> = shared.into_iter().collect();
    candidates.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    let mut taken = vec![false; groups.len()];
    let mut sets = Vec::new();
    for ((a, b), _) in candidates {
        if !taken[a] && !taken[b] {
            taken[a] = true;
            taken[b] = true;
            sets.push(vec![a, b]);
        }
    }
    sets.extend((0..groups.len()).filter(|&g| !taken[g]).map(|g| vec![g]));
    Some(sets)
}

/// Merges each set of groups and eliminates the DOFs no other group holds
/// (`holders` counts the groups holding each DOF) unless kept; the merges
/// run side by side, one per core, when there are enough of them.
fn merge_level(
    groups: Vec<Group>,
    sets: Vec<Vec<usize>>,
    holders: &[usize],
    keep: &[bool],
    fixing: &Fixing,
) -> Result<(Vec<Group>, Vec<Front>, f64), NotPositiveDefinite> {
    let mut slots: Vec<Option<Group>> = groups.into_iter().map(Some).collect();
    let sets: Vec<Vec<Group>> = sets
        .iter()
        .map(|set| set.iter().filter_map(|&g| slots[g].take()).collect())
        .collect();
    let global = faer::get_global_parallelism();
    let merges = sets.iter().filter(|s| s.len() > 1).count();
    let (workers, par) = if merges >= 2 && global.degree() >= 2 {
        (global.degree(), Par::Seq)
    } else {
        (1, global)
    };
    let own = |d: usize, held: usize| held == holders[d] && !keep[d];
    let results = signorini_linalg::threads::map_side_by_side(sets, workers, |set| {
        let set = match <[Group; 1]>::try_from(set) {
            Ok([alone]) => return Ok((None, alone, 0.0)),
            Err(set) => set,
        };
        let (front, dofs, t, flops) = merge_and_eliminate(set, own, fixing, par)?;
        let t = Entries::Lower(t);
        Ok((front, Group { dofs, t }, flops))
    });
    let mut out = Vec::with_capacity(results.len());
    let mut fronts = Vec::new();
    let mut flops = 0.0;
    for r in results {
        let (front, group, f) = r?;
        out.push(group);
        fronts.extend(front);
        flops += f;
    }
    Ok((out, fronts, flops))
}

/// What a merge gives: its front (None when it eliminated nothing), the
/// DOFs that remain (sorted), the lower triangle T on them, its flops.
type Merged = (Option<Front>, Vec<usize>, Mat<f64>, f64);

/// Adds the groups of `set` on the union of their DOFs, ordered with the
/// DOFs `own(dof, groups of the set holding it)` first, and eliminates
/// those (module doc).
fn merge_and_eliminate(
    set: Vec<Group>,
    own: impl Fn(usize, usize) -> bool,
    fixing: &Fixing,
    par: Par,
) -> Result<Merged, NotPositiveDefinite> {
    let mut union: Vec<usize> = set.iter().flat_map(|g| g.dofs.iter().copied()).collect();
    union.sort_unstable();
    let mut held: Vec<(usize, usize)> = Vec::with_capacity(union.len());
    for d in union {
        match held.last_mut() {
            Some((last, count)) if *last == d => *count += 1,
            _ => held.push((d, 1)),
        }
    }
    let (eliminated, remaining): (Vec<usize>, Vec<usize>) = {
        let (e, r): (Vec<&(usize, usize)>, Vec<_>) = held.iter().partition(|&&(d, c)| own(d, c));
        (
            e.into_iter().map(|p| p.0).collect(),
            r.into_iter().map(|p| p.0).collect(),
        )
    };
    let (ne, u) = (eliminated.len(), held.len());
    let mut f = Mat::<f64>::zeros(u, u);
    for g in &set {
        let at: Vec<usize> = g
            .dofs
            .iter()
            .map(|d| match eliminated.binary_search(d) {
                Ok(i) => i,
                Err(_) => ne + remaining.binary_search(d).unwrap_or(0),
            })
            .collect();
        add_lower(&mut f, &at, g, fixing);
    }
    drop(set);
    if ne == 0 {
        return Ok((None, remaining, f, 0.0));
    }
    let (mut ee, _, mut re, mut rr) = f.as_mut().split_at_mut(ne, ne);
    signorini_linalg::recursive_cholesky::cholesky(ee.rb_mut(), par)
        .map_err(|i| NotPositiveDefinite { dof: eliminated[i] })?;
    // L_REᵀ = L_EE⁻¹ F_ERᵀ, then T = F_RR − L_RE L_REᵀ (lower triangle).
    solve_lower_triangular_in_place(ee.rb(), re.rb_mut().transpose_mut(), par);
    matmul(
        rr.rb_mut(),
        BlockStructure::TriangularLower,
        Accum::Add,
        re.rb(),
        BlockStructure::Rectangular,
        re.rb().transpose(),
        BlockStructure::Rectangular,
        -1.0,
        par,
    );
    let nr = u - ne;
    let flops = (ne as f64).powi(3) / 3.0 + (ne * ne * nr) as f64 + (ne * nr * nr) as f64;
    let front = Front {
        l_ee: ee.rb().to_owned(),
        l_re: re.rb().to_owned(),
        eliminated,
        remaining: remaining.clone(),
    };
    let t = rr.rb().to_owned();
    Ok((Some(front), remaining, t, flops))
}

/// Adds the lower triangle of group `g` into that of `f`, its DOF k at
/// row `at[k]` of f (a block's fixing DOFs as [`Fixing`] says).
fn add_lower(f: &mut Mat<f64>, at: &[usize], g: &Group, fixing: &Fixing) {
    let nb = at.len();
    let mut add = |i: usize, j: usize, v: f64| {
        let (a, b) = (at[i].max(at[j]), at[i].min(at[j]));
        f[(a, b)] += v;
    };
    match &g.t {
        Entries::Lower(t) => (0..nb).for_each(|j| (j..nb).for_each(|i| add(i, j, t[(i, j)]))),
        Entries::Block { values, leaf } => {
            let fixed = |k: usize| fixing.is_fixed[g.dofs[k]];
            for j in 0..nb {
                if fixed(j) {
                    if fixing.first_holder[g.dofs[j]] == *leaf {
                        add(j, j, fixing.scale);
                    }
                    continue;
                }
                for i in (j..nb).filter(|&i| !fixed(i)) {
                    add(i, j, values[i + nb * j]);
                }
            }
        }
    }
}
