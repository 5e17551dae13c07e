//! One driver for the status (active set) method: course notes §3.3 for
//! frictionless contact, §4.5 for friction.
//!
//! Each iteration imposes the equations of the current statuses, solves, and
//! checks the statuses against the solution; the points whose status is
//! violated change, and the loop stops when no status changes ("jusqu'à ce
//! que les mêmes statuts de contact soient obtenus à deux itérations
//! successives", §3.3). What the two uses share lives here:
//!
//! - the iteration with its limit;
//! - the seen-set of status vectors: a status vector that comes back is a
//!   cycle (a flip-flop at the edge of a coarse contact zone, §3.3);
//! - the way out of a cycle met when changing every violated status at once:
//!   first, once, the statuses of a method that cannot cycle when the rule
//!   has one ([`StatusRule::leave_cycle`]: complementary pivoting for normal
//!   contact), then the switch to one status change per iteration, the most
//!   violated first (the variant of §3.3 with the convergence proof);
//!   cycling then stops the method;
//! - the singular-system fallback: the driver keeps the last statuses that
//!   gave a regular system, and when a status vector gives a singular one
//!   (a floating body no longer held) it asks the rule where to go from there;
//! - the stopping reasons ([`Stop`]).
//!
//! A [`StatusRule`] supplies what differs: the status type, the linear solve
//! for a status vector, the violated statuses of a solution, and the fallback
//! policy. [`crate::active_set::signorini`] (normal contact, §3.3) and [`crate::friction`]
//! (Tresca, the friction status method of §4.5, and the inner problems of the
//! Coulomb fixed point and of Norton–Hoff) are rules over this driver.

pub mod friction_status;
pub mod signorini;

use std::collections::HashSet;
use std::hash::Hash;

use crate::ContactError;

/// A violated status: the point, its new status, and the size of the
/// violation (scaled so that forces and gaps compare).
pub type Change<S> = (usize, S, f64);

/// The last status vector that gave a regular system, with its solution and
/// its violations (most violated first); `tried` lists the points a fallback
/// has already changed from it.
#[derive(Debug, Clone)]
pub struct Regular<S, Sol> {
    pub statuses: Vec<S>,
    pub solution: Sol,
    pub changes: Vec<Change<S>>,
    pub tried: Vec<usize>,
}

/// Where to go after a singular system.
#[derive(Debug, Clone)]
pub enum Fallback<S> {
    /// Start again from these statuses, keeping the number of changes per
    /// iteration.
    Restart(Vec<S>),
    /// Go on from these statuses with one change per iteration.
    OneChange(Vec<S>),
}

/// What differs between the status methods over the [`drive`] loop.
pub trait StatusRule {
    /// The status of one point.
    type Status: Clone + Eq + Hash;
    /// The solution of one status vector (forces and gaps).
    type Solution: Clone;

    /// Solves the equations the statuses impose (one call per iteration).
    fn solve(&mut self, statuses: &[Self::Status]) -> Result<Self::Solution, ContactError>;

    /// The violated statuses of `solution` (of iteration `iteration`). The
    /// driver orders them most violated first by a stable sort, so among
    /// equal violations the one listed first is changed first. An error here
    /// (an unusable solution) stops the method, without fallback.
    fn violations(
        &mut self,
        iteration: usize,
        statuses: &[Self::Status],
        solution: &Self::Solution,
    ) -> Result<Vec<Change<Self::Status>>, ContactError>;

    /// The statuses to try after the system of `statuses` was singular, from
    /// the last regular statuses (`None` before any regular solve, or if the
    /// rule took them); `None` gives up with the singular error.
    fn singular(
        &mut self,
        iteration: usize,
        statuses: &[Self::Status],
        last: &mut Option<Regular<Self::Status, Self::Solution>>,
    ) -> Option<Fallback<Self::Status>>;

    /// Statuses from a method that cannot cycle (complementary pivoting),
    /// to leave a cycle met from `statuses` in one step: the driver goes on
    /// from them, checking them like any other. `None` when the rule has no
    /// such method (the driver then changes one status per iteration).
    fn leave_cycle(
        &mut self,
        _statuses: &[Self::Status],
    ) -> Result<Option<Vec<Self::Status>>, ContactError> {
        Ok(None)
    }

    /// How many points `statuses` hold in contact, for the observer of
    /// [`crate::observe`] (0 if the rule does not say).
    fn in_contact(&self, _statuses: &[Self::Status]) -> usize {
        0
    }

    /// Whether the wall-clock budget of the solve has run out: the driver
    /// then stops before its next solve, as at its iteration limit.
    fn out_of_time(&self) -> bool {
        false
    }
}

/// Why the driver stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// No status is violated: the statuses repeat.
    Converged,
    /// A status vector came back even with one change per iteration.
    Cycling,
    /// The iteration limit (or the rule's time limit,
    /// [`StatusRule::out_of_time`]) was reached with statuses still changing.
    Limit,
}

/// The end of a [`drive`] run.
#[derive(Debug, Clone)]
pub struct Driven<S, Sol> {
    pub stop: Stop,
    /// Iterations (solves, regular or not) of this run.
    pub iterations: usize,
    /// The statuses at the end: those of the last solve if it converged or
    /// cycled, else the next ones to try.
    pub statuses: Vec<S>,
    /// The last regular solution, if any.
    pub solution: Option<Sol>,
    /// Iteration of the first cycle detected, if any.
    pub cycle_at: Option<usize>,
    /// Whether the run ended with one change per iteration.
    pub one_change: bool,
    /// Iteration at which a cycle was left by [`StatusRule::leave_cycle`],
    /// if one was.
    pub left_cycle_at: Option<usize>,
}

/// The status method loop (course notes §3.3, §4.5) from `statuses`, at most
/// `max_iterations` solves; with `one_change` only the most violated status
/// changes per iteration from the start.
pub fn drive<R: StatusRule>(
    rule: &mut R,
    mut statuses: Vec<R::Status>,
    one_change: bool,
    max_iterations: usize,
) -> Result<Driven<R::Status, R::Solution>, ContactError> {
    let mut seen: HashSet<Vec<R::Status>> = HashSet::new();
    let (mut single, mut cycle_at, mut solution) = (one_change, None, None);
    let mut left_cycle_at = None;
    let mut last: Option<Regular<R::Status, R::Solution>> = None;
    let (mut iterations, mut stop) = (0, Stop::Limit);
    while iterations < max_iterations && !(iterations > 0 && rule.out_of_time()) {
        iterations += 1;
        seen.insert(statuses.clone());
        let sol = match rule.solve(&statuses) {
            Ok(v) => v,
            Err(ContactError::Singular(msg)) => {
                match rule.singular(iterations, &statuses, &mut last) {
                    Some(Fallback::Restart(next)) => statuses = next,
                    Some(Fallback::OneChange(next)) => (statuses, single) = (next, true),
                    None => return Err(ContactError::Singular(msg)),
                }
                continue;
            }
            Err(e) => return Err(e),
        };
        let mut changes = rule.violations(iterations, &statuses, &sol)?;
        solution = Some(sol.clone());
        if changes.is_empty() {
            observe(rule, iterations, &statuses, &changes);
            stop = Stop::Converged;
            break;
        }
        changes.sort_by(|a, b| b.2.total_cmp(&a.2));
        observe(rule, iterations, &statuses, &changes);
        let mut next = changed(&statuses, &changes, single);
        if seen.contains(&next) {
            cycle_at.get_or_insert(iterations);
            if single {
                // Cycling even with one change per iteration: stop on the
                // statuses just solved.
                stop = Stop::Cycling;
                break;
            }
            seen.clear();
            match left_cycle_at {
                None => match rule.leave_cycle(&statuses)? {
                    // Leave the cycle by a step that cannot cycle, once.
                    Some(pivoted) => (next, left_cycle_at) = (pivoted, Some(iterations)),
                    None => single = true,
                },
                Some(_) => single = true,
            }
            if single {
                // Flip-flop: one change per iteration (course notes §3.3).
                next = changed(&statuses, &changes, true);
            }
        }
        last = Some(Regular {
            statuses: std::mem::replace(&mut statuses, next),
            solution: sol,
            changes,
            tried: Vec::new(),
        });
    }
    Ok(Driven {
        stop,
        iterations,
        statuses,
        solution,
        cycle_at,
        one_change: single,
        left_cycle_at,
    })
}

/// Tells the observer (if any) of an iteration: the points in contact and
/// the largest violation (changes are scaled to the tolerance).
fn observe<R: StatusRule>(
    rule: &R,
    iteration: usize,
    statuses: &[R::Status],
    changes: &[Change<R::Status>],
) {
    crate::observe::iteration(crate::observe::Iteration {
        method: "status",
        iteration,
        active: rule.in_contact(statuses),
        residual: changes.first().map_or(0.0, |c| c.2),
    });
}

/// `statuses` after `changes` (most violated first): all of them, or with
/// `single` only the first.
fn changed<S: Clone>(statuses: &[S], changes: &[Change<S>], single: bool) -> Vec<S> {
    let mut next = statuses.to_vec();
    let n = if single { 1 } else { changes.len() };
    for (p, st, _) in &changes[..n] {
        next[*p] = st.clone();
    }
    next
}

/// The tolerances on forces and gaps of a solution (r, g): `tolerance`
/// relative to max(force_scale, ‖r‖∞) and max(gap_scale, ‖g‖∞).
pub fn scaled_tolerances(
    tolerance: f64,
    force_scale: f64,
    gap_scale: f64,
    r: &[f64],
    g: &[f64],
) -> (f64, f64) {
    let rmax = r.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let gmax = g.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    (
        tolerance * force_scale.max(rmax),
        tolerance * gap_scale.max(gmax),
    )
}
