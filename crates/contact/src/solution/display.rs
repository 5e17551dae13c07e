//! The words of the stop reasons: the texts of `report.json`'s
//! `stopping_reason`.

use std::fmt;

use super::*;

impl fmt::Display for Measure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Measure::Natural => "natural residual",
            Measure::ProjectedGradient => "projected-gradient residual",
        })
    }
}

impl fmt::Display for MprgpSteps {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} CG, {} expansion, {} proportioning steps",
            self.cg, self.expansion, self.proportioning
        )
    }
}

impl fmt::Display for BoxPolish {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            BoxPolish::NotTried => "",
            BoxPolish::Polished => "; polished on the active set",
            BoxPolish::LeftTheBox => "; polishing rejected (left the box)",
            BoxPolish::LargerResidual => "; polishing rejected (larger residual)",
        })
    }
}

impl fmt::Display for PolishSolve {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            PolishSolve::ActiveSet => "solve on the identified active set",
            PolishSolve::SaddlePoint => "saddle-point solve on the identified active set",
        })
    }
}

impl fmt::Display for UzawaStep {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            UzawaStep::Given { factor } => write!(f, "{factor} / mean diag W"),
            UzawaStep::PowerIteration { norm } => {
                write!(f, "1.9 / ‖W‖₂ (power iteration: ‖W‖₂ ≈ {norm:.6e})")
            }
            UzawaStep::ZeroOperator => f.write_str("1 (W = 0)"),
        }
    }
}

impl DualDetail {
    /// What `report.iterations` counts.
    fn steps(&self) -> &'static str {
        match self {
            DualDetail::Uzawa { .. } => "iterations",
            DualDetail::Augmented { .. } => "outer iterations",
        }
    }

    /// The advice at the iteration limit.
    fn advice(&self) -> &'static str {
        match self {
            DualDetail::Uzawa { .. } => "Uzawa converges slowly when W is ill-conditioned",
            DualDetail::Augmented { .. } => {
                "a larger augmentation (stiffness option) converges in fewer outer iterations"
            }
        }
    }
}

impl fmt::Display for DualDetail {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DualDetail::Uzawa { step, halvings } => {
                write!(f, "ρ = {step}")?;
                if *halvings > 0 {
                    write!(
                        f,
                        ", halved {halvings} times because the dual energy increased"
                    )?;
                }
                Ok(())
            }
            DualDetail::Augmented {
                newton_steps,
                factor,
                cycles,
            } => {
                write!(
                    f,
                    "{newton_steps} inner Newton steps, r = {factor} / mean diag W"
                )?;
                if *cycles > 0 {
                    write!(
                        f,
                        "; {cycles} inner problems cycled and switched to one status change per step"
                    )?;
                }
                Ok(())
            }
        }
    }
}

impl fmt::Display for SmalbeProgress {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "after {} outer iterations ({} inner iterations; ρ = {:.3e})",
            self.outer, self.inner_iterations, self.rho
        )
    }
}

impl fmt::Display for SmalbeStop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SmalbeStop::Met {
                natural,
                feasibility,
                tolerance,
                progress,
                last_inner,
            } => write!(
                f,
                "SMALBE: natural residual {natural:.3e} and equilibrium residual {feasibility:.3e} ≤ tolerance {tolerance:.3e} {progress}; last inner: {last_inner}"
            ),
            SmalbeStop::Settled {
                progress,
                tolerance,
                last_inner,
            } => write!(
                f,
                "SMALBE: the active set settled {progress}; one saddle-point solve on it meets the tolerance {tolerance:.3e}; last inner: {last_inner}"
            ),
            SmalbeStop::InnerFailed { outer, inner } => write!(
                f,
                "SMALBE outer iteration {outer}: the inner solver did not converge: {inner}"
            ),
            SmalbeStop::Exhausted {
                outer,
                tolerance,
                natural,
                feasibility,
                rho,
                last_inner,
            } => write!(
                f,
                "SMALBE: {outer} outer iterations without meeting the tolerance {tolerance:.3e} (natural residual {natural:.3e}, equilibrium residual {feasibility:.3e}, ρ = {rho:.3e}); last inner: {last_inner}"
            ),
        }
    }
}

impl fmt::Display for StopReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use StopReason::*;
        match self {
            Pending => Ok(()),
            NoContactPoint => f.write_str("no contact point"),
            ZeroForces { residual } => write!(
                f,
                "λ = 0 already satisfies the tolerance (natural residual {residual:.3e}): no point in contact"
            ),
            NoPivot => f.write_str("q ≥ 0: λ = 0 solves the LCP (no pivot)"),
            ResidualMet {
                residual,
                tolerance,
                iterations,
            } => write!(
                f,
                "natural residual {residual:.3e} ≤ tolerance {tolerance:.3e} after {iterations} iterations"
            ),
            MprgpConverged { .. } | StartMeetsTolerance { .. } | LinearObjective { .. } => {
                self.fmt_mprgp(f)
            }
            DualConverged { .. } | DualLimit { .. } => self.fmt_dual(f),
            IterationLimit { .. } | Stagnation { .. } | LineSearchFailed { .. } => {
                self.fmt_projection(f)
            }
            PivotLimit { .. } | Pivoted { .. } | PivotedAboveTolerance { .. } => {
                self.fmt_lemke(f)
            }
            StatusesRepeated { .. } | Cycling { .. } | StatusLimit { .. } => self.fmt_status(f),
            RegularisedSolved { .. }
            | NewtonCycling { .. }
            | ActiveSetLimit { .. }
            | ByPenalty { .. } => self.fmt_penalty(f),
            InnerFailed { outer, inner } => write!(
                f,
                "inner problem of outer iteration {outer} not solved: {inner}"
            ),
            Smalbe(stop) => stop.fmt(f),
            Polished { before, by } => write!(f, "{before}; polished by one {by}"),
            FrictionStatusesRepeated { .. }
            | FrictionCycling
            | TrescaBoxSolved
            | BoxFallbacks { .. }
            | InnerTresca(_)
            | FixedPointReached { .. }
            | FixedPointLimit { .. }
            | FixedPointStalled { .. }
            | Tresca(_) => self.fmt_friction(f),
            NewtonConverged { .. } | NewtonLimit { .. } | NewtonStalled { .. } | NewtonLineSearchFailed => {
                self.fmt_newton(f)
            }
            NsgsConverged { residual, sweeps } => write!(
                f,
                "natural residual {residual:.2e} after {sweeps} NSGS sweeps"
            ),
            NsgsLimit { limit } => write!(f, "NSGS sweep limit {limit} reached"),
            NsgsStalled { best, at, since } => write!(
                f,
                "NSGS stalled: no sweep halved the residual {best:.2e} (sweep {at}) in the {since} sweeps since"
            ),
            TimeLimit {
                iterations,
                residual,
            } => write!(
                f,
                "time limit reached after {iterations} iterations at the natural residual {residual:.2e} (a larger time_limit, --time-limit, or another method)"
            ),
            RigidMotionUnbalanced {
                iterations,
                imbalance,
            } => write!(
                f,
                "after {iterations} iterations the forces leave a rigid motion of a body held by its contacts alone unbalanced ({imbalance:.1e} of the forces along it): its loads have no static equilibrium on its contacts (it tips or slides away); impose that motion (a displacement) instead of a force, or add a support"
            ),
            NonFinite { iteration } => write!(
                f,
                "the iterate became non-finite (NaN) at iteration {iteration}: the method's linear solves broke down (W singular or badly conditioned); try another method"
            ),
            FrictionOverload {
                mode,
                load,
                capacity,
            } => write!(
                f,
                "the load along rigid motion {mode} of the floating bodies, {load:.4e}, exceeds what friction can hold along it, {capacity:.4e} (μ λ_n summed over its contact points): no static equilibrium"
            ),
        }
    }
}

impl StopReason {
    fn fmt_mprgp(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StopReason::MprgpConverged {
                measure,
                residual,
                tolerance,
                iterations,
                steps,
                norm_w,
                polish,
            } => write!(
                f,
                "{measure} {residual:.3e} ≤ tolerance {tolerance:.3e} after {iterations} iterations ({steps}; ᾱ = 1.9/‖W‖, ‖W‖ ≈ {norm_w:.6e}){polish}"
            ),
            StopReason::StartMeetsTolerance {
                measure,
                residual,
                tolerance,
                polish,
            } => write!(
                f,
                "the start projected onto the box meets the tolerance: {measure} {residual:.3e} ≤ tolerance {tolerance:.3e}{polish}"
            ),
            StopReason::LinearObjective { residual } => write!(
                f,
                "W = 0: the linear objective is minimised at the bounds, residual {residual:.3e}"
            ),
            _ => unreachable!("not an MPRGP reason"),
        }
    }

    fn fmt_dual(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StopReason::DualConverged {
                residual,
                tolerance,
                iterations,
                detail,
            } => write!(
                f,
                "natural residual {residual:.3e} ≤ tolerance {tolerance:.1e} after {iterations} {} ({detail})",
                detail.steps()
            ),
            StopReason::DualLimit {
                limit,
                residual,
                tolerance,
                detail,
            } => write!(
                f,
                "iteration limit {limit} reached: natural residual {residual:.3e} > tolerance {tolerance:.1e} ({detail}); {}",
                detail.advice()
            ),
            _ => unreachable!("not a dual reason"),
        }
    }

    fn fmt_projection(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StopReason::IterationLimit {
                limit,
                measure,
                residual,
                tolerance,
                steps,
            } => {
                write!(
                    f,
                    "iteration limit {limit} reached with {measure} {residual:.3e} above tolerance {tolerance:.3e} (not converged"
                )?;
                if let Some(steps) = steps {
                    write!(f, "; {steps}")?;
                }
                f.write_str(")")
            }
            StopReason::Stagnation {
                iteration,
                measure,
                residual,
                tolerance,
            } => write!(
                f,
                "stagnation at iteration {iteration}: no descent direction left at {measure} {residual:.3e} above tolerance {tolerance:.3e} (round-off floor; not converged)"
            ),
            StopReason::LineSearchFailed {
                iteration,
                residual,
            } => write!(
                f,
                "line search failed at iteration {iteration} (natural residual {residual:.3e})"
            ),
            _ => unreachable!("not a projection reason"),
        }
    }

    fn fmt_lemke(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StopReason::PivotLimit { limit, residual } => write!(
                f,
                "pivot limit {limit} reached before z0 left the basis (natural residual {residual:.3e}; not converged)"
            ),
            StopReason::Pivoted {
                pivots,
                residual,
                tolerance,
                polished,
            } => write!(
                f,
                "z0 left the basis after {pivots} pivots; natural residual {residual:.3e} ≤ tolerance {tolerance:.3e}{}",
                if *polished { " after polishing on the active set" } else { "" }
            ),
            StopReason::PivotedAboveTolerance {
                pivots,
                residual,
                tolerance,
            } => write!(
                f,
                "z0 left the basis after {pivots} pivots but the natural residual {residual:.3e} is above tolerance {tolerance:.3e} (round-off on an ill-conditioned W; not converged)"
            ),
            _ => unreachable!("not a Lemke reason"),
        }
    }

    fn fmt_status(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StopReason::StatusesRepeated { iterations } => {
                write!(f, "statuses repeated after {iterations} iterations")
            }
            StopReason::Cycling { iteration } => write!(
                f,
                "cycling: the active set of iteration {iteration} repeats an earlier one even with one status change per iteration (the contact zone is probably meshed too coarsely, course notes §3.3)"
            ),
            StopReason::StatusLimit { limit } => write!(
                f,
                "iteration limit {limit} reached with statuses still changing"
            ),
            _ => unreachable!("not a status reason"),
        }
    }

    fn fmt_penalty(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StopReason::RegularisedSolved {
                active,
                iterations,
                cycle_at,
                penetration,
            } => {
                write!(
                    f,
                    "regularised law solved exactly: the active set ({active} points) repeated after {iterations} iterations"
                )?;
                if let Some(i) = cycle_at {
                    write!(
                        f,
                        " (an active set repeated at iteration {i}: switched to one status change per iteration, least index first)"
                    )?;
                }
                write!(
                    f,
                    "; max penetration {penetration:.3e} (O(1/k), course notes §3.6)"
                )
            }
            StopReason::NewtonCycling {
                iteration,
                tolerance,
            } => write!(
                f,
                "cycling: the active set of iteration {iteration} repeats an earlier one even with one status change per iteration (round-off at the tolerance {tolerance:.1e}?)"
            ),
            StopReason::ActiveSetLimit { limit } => write!(
                f,
                "iteration limit {limit} reached with the active set still changing"
            ),
            StopReason::ByPenalty {
                status,
                penetration,
            } => write!(
                f,
                "{status} (constraints imposed by penalty); max penetration {penetration:.3e} (O(1/k))"
            ),
            _ => unreachable!("not a penalty reason"),
        }
    }
}

impl fmt::Display for ThresholdMapKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ThresholdMapKind::Coulomb => "fixed point on the threshold",
            ThresholdMapKind::NortonHoff => "Norton-Hoff fixed point",
        })
    }
}

impl StopReason {
    fn fmt_friction(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StopReason::FrictionStatusesRepeated { solves } => {
                write!(f, "statuses repeated after {solves} status solves")
            }
            StopReason::FrictionCycling => {
                f.write_str("cycling even with one status change per iteration")
            }
            StopReason::TrescaBoxSolved => f.write_str("solved by MPRGP on the Tresca box"),
            StopReason::BoxFallbacks { before, count } => write!(
                f,
                "{before} ({count} inner Tresca problem(s) solved by MPRGP on the box after the status method cycled)"
            ),
            StopReason::InnerTresca(inner) => write!(f, "inner Tresca problem: {inner}"),
            StopReason::FixedPointReached { map, iterations } => {
                write!(f, "{map} reached after {iterations} iterations")
            }
            StopReason::FixedPointLimit { map, limit } => {
                write!(f, "{map} not reached in {limit} iterations")
            }
            StopReason::FixedPointStalled {
                map,
                best,
                at,
                since,
            } => {
                let why = match map {
                    ThresholdMapKind::NortonHoff => "points whose slip is near zero alternate between stick and slip, where the law is steep: a larger rho, or a load that makes them slip",
                    _ => "normal forces not unique, e.g. a rank-deficient W: try the nonsmooth Gauss–Seidel method, friction = \"nsgs\"",
                };
                write!(
                    f,
                    "{map} stalled: no iterate came closer than {best:.2e} (iteration {at}) in the {since} iterations since; the map does not contract here ({why})"
                )
            }
            StopReason::Tresca(inner) => write!(f, "Tresca: {inner}"),
            _ => unreachable!("not a friction reason"),
        }
    }

    fn fmt_newton(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StopReason::NewtonConverged {
                residual,
                iterations,
            } => write!(
                f,
                "natural residual {residual:.2e} after {iterations} Newton iterations"
            ),
            StopReason::NewtonLimit { limit } => write!(f, "iteration limit {limit} reached"),
            StopReason::NewtonStalled { best, at, since } => write!(
                f,
                "stalled: no iterate came closer than the residual {best:.2e} (iteration {at}) in the {since} iterations since"
            ),
            StopReason::NewtonLineSearchFailed => f.write_str(
                "the Newton line search failed repeatedly (floating bodies: no fallback)",
            ),
            _ => unreachable!("not a Newton reason"),
        }
    }
}
