//! The stable step (model §6): h_crit = 2/ω_max with ω_max² = λ_max(M⁻¹K) estimated by
//! Lanczos (K·x matrix-free, the directional derivative of F_int, plus the interface springs),
//! re-estimated as the stiffness changes; and the choice of the next step h_{n+3/2}.

use super::bound::BoundCache;
use super::lanczos::{lanczos, LanczosOut, LanczosStop};
use super::state::StableStep;
use super::stiffness::{EstimateCache, StiffnessOperator};
use super::Simulation;
use crate::tunables::{
    BASIS_BUDGET, JACOBIAN_RETRIGGER, JACOBIAN_RETRIGGER_MAX, OMEGA_MOVED, OMEGA_STILL,
    SPRING_RETRIGGER, STEP_BAND, UPDATE_MARGIN, UPDATE_MAX_ITER, UPDATE_RESIDUAL,
};
pub(crate) use crate::tunables::{GROWTH_RATIO, JACOBIAN_COMPRESSED};

/// The step for a time-step factor: h = factor × h_crit, never above h_crit (model §6.1, §6.6:
/// central differences are unstable above h_crit = 2/ω_max). A factor above 1 is accepted
/// (scene range (0, 2)) and runs at h = h_crit, the stability limit itself, with no margin for
/// the estimate or for stiffening between estimates (a warning says so).
pub(super) fn capped_step(factor: f64, h_crit: f64) -> f64 {
    factor.min(1.0) * h_crit
}

/// The step controller's state between steps (model §6.5, §6.6).
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub(super) struct StepControl {
    /// h_{n−½}, the interval before the one just taken (set at t₀ to the first h) [s].
    pub h_before: f64,
    /// The step h ramps up to (by at most [`GROWTH_RATIO`] per step) after an estimate found
    /// the body softer [s].
    pub goal: Option<f64>,
    /// Σ W g_N(α) of the glued nodes now (stage 9), at the last estimate and at t₀ [N/m].
    pub springs_now: f64,
    pub springs_at_estimate: f64,
    pub springs_initial: f64,
    /// Glued nodes whose damage is evolving after the last step (stage 9): while there are
    /// any, h does not grow (a step grown while the glue softens enlarges the O(h) error of
    /// the dissipation pairing ΔD, model §5.5).
    pub damage_evolving: usize,
    /// The Jacobian change that triggers an estimate now (0: [`JACOBIAN_RETRIGGER`]).
    pub jacobian_trigger: f64,
    /// The element of [`Simulation::stress_jacobian`] at the last force evaluation.
    pub compressed_element: usize,
    /// The stable-step operator's constants and buffers, kept between estimates. Not in a
    /// checkpoint: its constants depend on the model alone, its buffers are written before they
    /// are read (`solver/checkpoint.rs` keeps the restored simulation's own).
    #[serde(skip)]
    pub estimates: EstimateCache,
    /// The element bound's constants and buffers ([`Simulation::stiffness_bound`]); not in a
    /// checkpoint either.
    #[serde(skip)]
    pub bound: BoundCache,
    /// Whether the next estimate tries the cheap, certified update: false
    /// after the bound failed to certify one (too loose, κ > 4/(1.05 factor)², or the update
    /// too short), true again once it would have certified a converged one.
    pub try_certify: bool,
}

impl Simulation {
    /// Stage 4 (model §4.4): the step h_{n+3/2} about to be taken, the controller's
    /// [`Simulation::next_time_step`] limited by the bulk viscosity's damping
    /// ([`Simulation::damped_step`]).
    pub(super) fn next_step(&mut self) -> f64 {
        let h_next = self.next_time_step();
        self.damped_step(h_next)
    }

    /// Re-estimates h_crit when the stiffness may have changed and returns h_{n+3/2}.
    ///
    /// *When*: the glue's total spring stiffness Σ W g_N(α) moved by [`SPRING_RETRIGGER`] of its
    /// initial value since the last estimate (damage, rupture); under strong compression
    /// ([`Simulation::stress_jacobian`], the smallest J where the stress is evaluated, below
    /// [`JACOBIAN_COMPRESSED`]; with one point the centre's, as the corners' J changes no
    /// stiffness) that J moved by the adaptive threshold ([`JACOBIAN_RETRIGGER`]) since the
    /// last estimate (a violent impact stiffens a neo-Hookean body within a few steps,
    /// and contact is how such compression starts: contact itself adds no stiffness, its
    /// impulses are velocity-level); and at the latest every `h_crit_update_interval` steps,
    /// for stiffening the indicators miss (SVK in tension). Each estimate is warm-started from
    /// the previous Ritz vector and costs a few force evaluations
    /// ([`Simulation::update_stable_step`]).
    ///
    /// *What*: with the target h* = factor × h_crit (never above h_crit, [`capped_step`]):
    /// when stiffening makes h exceed h* by more than [`STEP_BAND`] (or h_crit itself), h
    /// becomes (1 − [`STEP_BAND`]) × h* at once; when softening makes h* exceed h by more than
    /// [`STEP_BAND`], h grows towards h* by at most [`GROWTH_RATIO`] per step, and not while
    /// some element is compressed below [`JACOBIAN_COMPRESSED`] nor while the glue's damage is
    /// evolving ([`StepControl::damage_evolving`]: a node in transition, a delayed α behind its
    /// target, or the tearing under way, some node damaged and some not ruptured). The step is
    /// held through the tearing because the dissipation pairing ΔD (model §5.5) has an O(h)
    /// error: grown while the glue tore, the pull-off's D rose above its fixed-step value;
    /// held, D is the fixed-step value, and h grows once the glue has torn. The dead band
    /// keeps estimate noise from moving h. A change of step is exact in the ledger
    /// ([`Simulation::ledger`], the step-change work of model §5.8).
    pub(super) fn next_time_step(&mut self) -> f64 {
        if self.model.scheme.h_crit_update_interval == 0 {
            return self.state.h;
        }
        let c = &self.state.step_control;
        let trigger = c.jacobian_trigger.max(JACOBIAN_RETRIGGER);
        let compressed = self.state.stress_jacobian < JACOBIAN_COMPRESSED;
        let strained = compressed
            && (self.state.stress_jacobian - self.state.jacobian_at_estimate).abs() > trigger;
        if self.estimate_without_strain() || strained {
            let before = (2.0 / self.state.h_crit).powi(2);
            let est = self.update_stable_step();
            if strained {
                let moved = (est.omega_max_sq / before - 1.0).abs();
                self.state.step_control.jacobian_trigger = if moved > OMEGA_MOVED {
                    0.5 * trigger
                } else if moved < OMEGA_STILL {
                    (2.0 * trigger).min(JACOBIAN_RETRIGGER_MAX)
                } else {
                    trigger
                };
            }
            self.state.jacobian_at_estimate = self.state.stress_jacobian;
            self.state.step_control.springs_at_estimate = self.state.step_control.springs_now;
            self.stats.h_crit_estimates += 1;
            self.stats.h_crit_estimate_iterations += est.iterations as u64;
            self.state.h_crit = est.h_crit;
            self.stats.h_crit_min = self.stats.h_crit_min.min(est.h_crit);
            let factor = self.model.scheme.time_step_factor;
            let target = capped_step(factor, est.h_crit);
            let c = &mut self.state.step_control;
            if self.state.h > ((1.0 + STEP_BAND) * factor * est.h_crit).min(est.h_crit) {
                c.goal = None;
                return capped_step((1.0 - STEP_BAND) * factor, est.h_crit);
            }
            if target > (1.0 + STEP_BAND) * self.state.h {
                c.goal = Some(target);
            } else if let Some(goal) = c.goal {
                c.goal = Some(goal.min(target));
            }
        }
        match self.state.step_control.goal {
            Some(_) if compressed || self.state.step_control.damage_evolving > 0 => self.state.h,
            Some(goal) if goal > self.state.h => (GROWTH_RATIO * self.state.h).min(goal),
            _ => {
                self.state.step_control.goal = None;
                self.state.h
            }
        }
    }

    /// With bulk viscosity (model §4.12, §6.6): `h_next` capped at
    /// min(factor, 1) × h_crit × (√(1 + ξ²) − ξ), ξ the largest damping ratio of the last force
    /// evaluation, the stable step of central differences on a damped mode; when the cap bites,
    /// the controller's goal is the undamped target, so h grows back (by at most
    /// [`GROWTH_RATIO`] per step) once ξ falls. Without bulk viscosity, `h_next` itself.
    pub(super) fn damped_step(&mut self, h_next: f64) -> f64 {
        let Some(bv) = self.state.bulk_viscosity.as_ref() else {
            return h_next;
        };
        let target = capped_step(self.model.scheme.time_step_factor, self.state.h_crit);
        let cap = target * super::bulk_viscosity::damped_step_factor(bv.xi_max);
        if h_next <= cap {
            return h_next;
        }
        self.state.step_control.goal = Some(target);
        cap
    }

    /// Whether [`Self::next_time_step`] of this step re-estimates h_crit whatever the Jacobian:
    /// at the scheduled steps, and when the glue's springs softened while h may grow.
    pub(super) fn estimate_without_strain(&self) -> bool {
        let every = self.model.scheme.h_crit_update_interval as u64;
        if every == 0 {
            return false;
        }
        let c = &self.state.step_control;
        // Softening only ever lowers ω_max: it is worth an estimate only while the glue may
        // hold h below what the bulk alone allows (h_crit_bulk, measured at t₀ when a glued
        // node's spring is near the system's ω_max).
        let may_grow = self.state.h_crit_bulk.is_some_and(|hb| {
            capped_step(self.model.scheme.time_step_factor, hb) > (1.0 + STEP_BAND) * self.state.h
        });
        let softened = may_grow
            && (c.springs_now - c.springs_at_estimate).abs() > SPRING_RETRIGGER * c.springs_initial;
        self.state.step_count.is_multiple_of(every) || softened
    }

    /// The stable step now by a warm-started Lanczos estimate: from the previous Ritz vector
    /// (plus, under strong compression, a random vector on the most compressed element,
    /// [`StiffnessOperator::add_local_start`]: there the stiffest mode jumps from element to
    /// element with the compression wave), at most [`UPDATE_MAX_ITER`] iterations, stopped once
    /// the Ritz residual is below [`UPDATE_RESIDUAL`] θ; ω² = θ + max(‖r‖, [`UPDATE_MARGIN`] θ);
    /// then certified by the element bound, or converged.
    ///
    /// *Why a few iterations need more than their residual.* θ is a lower bound of ω_max². The
    /// Ritz pair's residual ‖r‖ bounds the distance from θ to *some* eigenvalue; it bounds
    /// λ_max − θ when that eigenvalue is the largest, i.e. when no other eigenvalue lies
    /// between θ and λ_max — which a top cluster narrower than ‖r‖ can break (θ converges
    /// towards the cluster's lower members first). Measured against converged estimates
    /// (`physics/tests/step.rs`, where the glue tears), θ + ‖r‖ alone fell short of the
    /// converged θ_c by a small fraction of θ_c; under strong compression (smallest Jacobian
    /// below [`JACOBIAN_COMPRESSED`]) a few iterations stopped on a lower mode with a small
    /// residual, far shorter in ω² in the 100 m/s impact (docs: performance log). So no margin
    /// derived from the Lanczos run itself holds. The floor [`UPDATE_MARGIN`] θ (a top cluster
    /// of relative width 3e-2) keeps the shortfall s small where the glue tears, at a cost of
    /// h_crit about 1.5 % below the converged value; what makes the step safe is the
    /// certificate.
    ///
    /// *The certificate.* Every update is checked against the element bound
    /// ω_b² ≥ ω_max² ([`Simulation::stiffness_bound`], proven in `solver/bound.rs`): after this
    /// estimate the step is at most h_a = min((1 + [`STEP_BAND`]) × factor, 1) × h_crit(update)
    /// ([`Simulation::next_time_step`] keeps h below that or resets it under it), and
    ///
    ///   h_a ≤ 2/ω_b ≤ 2/ω_max = h_crit,true                                          (C)
    ///
    /// makes the step stable now whatever the update's error. The bound overestimates ω_max²
    /// by κ = ω_b²/ω_max² (measured against converged estimates, `physics/tests/step.rs`,
    /// along the SVK pull-offs at 7³ and 10³, in the neo-Hookean 100 m/s impact, where its
    /// modulus grows as 1/λ_min(C), and with one point; docs: performance log). With the update
    /// short by a ratio s ≥ 1 in ω², h_a² ω_b² = min(1.05 factor, 1)² · 4 κ s, so (C) holds
    /// when κ s ≤ 1/(1.05 factor)²: 3.6 at the default factor 0.5, which the pull-offs meet at
    /// every checked update and the violent impact at most of them; never near factor 1.
    /// Where (C) fails the estimate is converged (to `h_crit_tolerance`, from the update's own
    /// Ritz vector), and the next estimate goes straight to the converged one until the bound
    /// would have certified a converged estimate ([`StepControl::try_certify`]). So every step
    /// rests on the proof (C) or on a converged
    /// estimate, never on a measured margin. Between estimates the triggers of
    /// [`Simulation::next_time_step`] follow the stiffening, as before.
    pub fn update_stable_step(&mut self) -> StableStep {
        let compressed = self.state.stress_jacobian < JACOBIAN_COMPRESSED;
        let element = self.state.step_control.compressed_element;
        let cheap = self.state.step_control.try_certify;
        let mut iterations = 0;
        if cheap {
            let stop = LanczosStop {
                max_iter: UPDATE_MAX_ITER,
                tol: 0.0,
                residual: UPDATE_RESIDUAL,
                check_every: 1,
            };
            let out = self.run_estimate(true, true, stop, |op, warm| {
                op.start_vector(Some(warm));
                if compressed {
                    op.add_local_start(element);
                }
            });
            let update = LanczosOut {
                resid: out.resid.max(UPDATE_MARGIN * out.theta),
                ..out
            }
            .stable_step();
            if self.certified(&update) {
                self.stats.h_crit_certified += 1;
                return update;
            }
            iterations = update.iterations;
        }
        let stop = LanczosStop {
            max_iter: 300,
            tol: self.model.scheme.h_crit_tolerance,
            residual: 0.0,
            check_every: 5,
        };
        let out = self.run_estimate(true, true, stop, |op, warm| {
            op.start_vector(Some(warm));
            if compressed {
                op.add_local_start(element);
            }
        });
        let converged = self.proven(StableStep {
            iterations: iterations + out.alphas.len(),
            ..out.stable_step()
        });
        if !cheap {
            // Would the bound have certified this estimate? Then the next one tries the cheap
            // update again (the bound's looseness κ moves with the compression).
            self.certified(&converged);
        }
        converged
    }

    /// Certificate (C) of [`Simulation::update_stable_step`] for the estimate `est`: the
    /// largest step it allows, h_a = min((1 + [`STEP_BAND`]) × factor, 1) × h_crit(est), is
    /// at most 2/ω_b, the element bound's stable step ([`Simulation::stiffness_bound`]).
    /// Records the outcome for the next compressed estimate
    /// ([`StepControl::try_certify`]).
    fn certified(&mut self, est: &StableStep) -> bool {
        let bound = self.stiffness_bound();
        let factor = self.model.scheme.time_step_factor;
        let h_allowed = ((1.0 + STEP_BAND) * factor).min(1.0) * est.h_crit;
        let ok = h_allowed * h_allowed * bound <= 4.0;
        self.state.step_control.try_certify = ok;
        ok
    }

    /// One Lanczos estimate at the current state: the operator with or without the interface
    /// springs (`springs`), F_int(U) the step's own (`forces_current`) or assembled; `start`
    /// sets the start vector (given the previous Ritz vector); `stop.max_iter` is capped at
    /// the number of degrees of freedom. Leaves the Ritz vector of the run in
    /// `self.state.ritz_vector`, formed from the kept basis (within [`BASIS_BUDGET`]) or by a second
    /// pass.
    fn run_estimate(
        &mut self,
        springs: bool,
        forces_current: bool,
        mut stop: LanczosStop,
        start: impl FnOnce(&mut StiffnessOperator, &[f64]),
    ) -> LanczosOut {
        let mut cache = std::mem::take(&mut self.state.step_control.estimates);
        let mut ritz = std::mem::take(&mut self.state.ritz_vector);
        let mut op = StiffnessOperator::new(self, springs, forces_current, &mut cache);
        start(&mut op, &ritz);
        let start = std::mem::take(&mut op.cache.start);
        let mut work = std::mem::take(&mut op.cache.work);
        let n = start.len();
        stop.max_iter = stop.max_iter.min(n);
        work.basis_limit = stop.max_iter.min(BASIS_BUDGET / n.max(1));
        let team = self.work.team.as_ref();
        let mut apply = |q: &[f64], y: &mut [f64]| op.apply(q, y);
        let out = lanczos(&mut apply, &start, &stop, None, team, &mut work);
        work.ritz_vector(&mut apply, &start, &out, team, &mut ritz);
        (cache.start, cache.work) = (start, work);
        self.state.step_control.estimates = cache;
        self.state.ritz_vector = ritz;
        out
    }

    /// A converged estimate from a cold start ([`Simulation::estimate_stable_step`]) that
    /// leaves the warm start of the run's next update as it was: the reference the update
    /// estimates are checked against.
    pub fn converged_stable_step(&mut self) -> StableStep {
        let ritz = self.state.ritz_vector.clone();
        let est = self.estimate_stable_step(None);
        self.state.ritz_vector = ritz;
        est
    }

    /// ω_max² of M⁻¹K at the current state by Lanczos on M^{-½}KM^{-½} (model §6.1, §6.2), K·x
    /// matrix-free as the directional derivative of F_int (forward difference, relative step
    /// 1e-6 of the smallest edge) plus the interface springs W g_N(α) of glued nodes;
    /// prescribed components are removed. Lanczos Ritz values approach λ_max from below, so
    /// the estimate is θ + ‖r‖ with ‖r‖ = β_j|s_j| the Ritz residual: an eigenvalue lies within
    /// ‖r‖ of θ, which bounds λ_max once θ has converged to the top of the spectrum.
    pub fn estimate_stable_step(&mut self, warm: Option<Vec<f64>>) -> StableStep {
        self.stable_step_estimate(warm, true)
    }

    /// [`Simulation::estimate_stable_step`], with the interface springs in K or without them
    /// (`springs = false`: the bulk alone).
    pub(super) fn stable_step_estimate(
        &mut self,
        warm: Option<Vec<f64>>,
        springs: bool,
    ) -> StableStep {
        let stop = LanczosStop {
            max_iter: 300,
            tol: self.model.scheme.h_crit_tolerance,
            residual: 0.0,
            check_every: 5,
        };
        let out = self.run_estimate(springs, false, stop, |op, _| {
            op.start_vector(warm.as_deref())
        });
        if springs {
            self.proven(out.stable_step())
        } else {
            out.stable_step()
        }
    }

    /// An estimate meant to be converged, as the step may rest on it: unchanged when its
    /// Lanczos run converged; else counted ([`RunStats::h_crit_unconverged`]) and raised to the
    /// proven element bound ω_b² ≥ ω_max² ([`Simulation::stiffness_bound`], model §6.4) when
    /// that is finite and the larger, so an unconverged Ritz value never sets a step above
    /// 2/ω_b.
    ///
    /// [`RunStats::h_crit_unconverged`]: super::RunStats::h_crit_unconverged
    fn proven(&mut self, est: StableStep) -> StableStep {
        if est.converged {
            return est;
        }
        self.stats.h_crit_unconverged += 1;
        let bound = self.stiffness_bound();
        // +∞ where the material has no pointwise bound (the rubbers, model §1.10): no proof to
        // fall back on, the estimate stands (counted and warned about).
        if bound.is_finite() && bound > est.omega_max_sq {
            StableStep {
                omega_max_sq: bound,
                h_crit: 2.0 / bound.sqrt(),
                ..est
            }
        } else {
            est
        }
    }
}
