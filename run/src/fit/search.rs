//! The search of a fit ([`super::fit`]): the objective over z ∈ [0, 1]ⁿ with every run kept, runs
//! side by side, the Halton sample, Nelder–Mead descents (argmin) and the linearised
//! uncertainty. The module docs of [`super`] state what each does and why.

use super::problem::{Evaluation, Problem, FAILED_COST};
use super::{Prepared, Record, Stop, Watch};
use anyhow::{bail, Result};
use argmin::core::{CostFunction, Executor, State, TerminationReason};
use argmin::solver::neldermead::NelderMead;
use std::cell::RefCell;
use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, Ordering};

/// The optimiser's objective over z, with every run kept.
pub(super) struct Objective<'a> {
    pub(super) prep: &'a Prepared,
    pub(super) cancel: &'a AtomicBool,
    pub(super) threads: usize,
    pub(super) max_evals: usize,
    pub(super) state: RefCell<Runs<'a>>,
}

/// The runs so far, by the bits of their z.
pub(super) struct Runs<'a> {
    pub(super) cache: HashMap<Vec<u64>, Evaluation>,
    pub(super) records: Vec<Record>,
    pub(super) best: Option<usize>,
    pub(super) watch: &'a mut dyn Watch,
    /// Why the objective stopped the optimiser (max evals, stalled, cancelled).
    pub(super) stopped: Option<Stop>,
    /// Runs since the best misfit last improved.
    pub(super) since_best: usize,
}

/// Runs without improvement of the best misfit after which the fit stops as [`Stop::Stalled`]:
/// 20 (n + 1) for n free keys, enough for twenty contractions or shrinks of the simplex.
pub fn stall_runs(n: usize) -> usize {
    20 * (n + 1)
}

pub(super) fn bits(z: &[f64]) -> Vec<u64> {
    z.iter().map(|v| v.to_bits()).collect()
}

impl Runs<'_> {
    pub(super) fn add(&mut self, z: &[f64], values: Vec<f64>, e: Evaluation) {
        let (status, cost, error) = match &e {
            Evaluation::Done { cost, .. } => ("completed", Some(*cost), None),
            Evaluation::Failed(m) => ("failed", None, Some(m.clone())),
            Evaluation::Cancelled => ("cancelled", None, None),
        };
        let record = Record {
            index: self.records.len() + 1,
            values,
            z: z.to_vec(),
            cost,
            status,
            error,
        };
        if let Some(c) = cost {
            let better = self
                .best
                .is_none_or(|b| c < self.records[b].cost.unwrap_or(f64::INFINITY));
            if better {
                self.best = Some(self.records.len());
                self.since_best = 0;
            } else {
                self.since_best += 1;
            }
        } else {
            self.since_best += 1;
        }
        self.records.push(record);
        let last = self.records.last().expect("just pushed");
        self.watch
            .evaluated(last, self.best.map(|b| &self.records[b]));
        if !matches!(e, Evaluation::Cancelled) {
            self.cache.insert(bits(z), e);
        }
    }
}

impl Objective<'_> {
    pub(super) fn values(&self, z: &[f64]) -> Vec<f64> {
        self.prep
            .problem
            .free
            .iter()
            .zip(z)
            .map(|(f, z)| f.value(*z))
            .collect()
    }

    /// Runs the points `zs` side by side (those not run before) and records them.
    pub(super) fn run_many(&self, zs: &[Vec<f64>]) {
        let todo: Vec<&Vec<f64>> = {
            let st = self.state.borrow();
            zs.iter()
                .filter(|z| !st.cache.contains_key(&bits(z)))
                .collect()
        };
        let values: Vec<Vec<f64>> = todo.iter().map(|z| self.values(z)).collect();
        let results = run_side_by_side(&self.prep.problem, &values, self.threads, self.cancel);
        let mut st = self.state.borrow_mut();
        for ((z, values), e) in todo.into_iter().zip(values).zip(results) {
            st.add(z, values, e);
        }
    }
}

/// Runs the parameter vectors `values` on `threads` threads: as many side by side as there are
/// threads (each on its share), the results in the order given.
pub(super) fn run_side_by_side(
    problem: &Problem,
    values: &[Vec<f64>],
    threads: usize,
    cancel: &AtomicBool,
) -> Vec<Evaluation> {
    let jobs = threads.clamp(1, values.len().max(1));
    let per = (threads / jobs).max(1);
    let next = std::sync::atomic::AtomicUsize::new(0);
    let out: std::sync::Mutex<Vec<Option<Evaluation>>> =
        std::sync::Mutex::new(vec![None; values.len()]);
    std::thread::scope(|s| {
        for _ in 0..jobs {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::SeqCst);
                let Some(p) = values.get(i) else { return };
                let e = if cancel.load(Ordering::SeqCst) {
                    Evaluation::Cancelled
                } else {
                    problem.evaluate(p, per, cancel)
                };
                out.lock().expect("no panic holds the results")[i] = Some(e);
            });
        }
    });
    out.into_inner()
        .expect("no panic holds the results")
        .into_iter()
        .map(|e| e.unwrap_or(Evaluation::Cancelled))
        .collect()
}

/// The objective as argmin's problem (argmin takes its problem by value; the runs stay with
/// the [`Objective`] whatever the optimiser's outcome).
pub(super) struct ByRef<'o, 'a>(&'o Objective<'a>);

impl CostFunction for ByRef<'_, '_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, z: &Vec<f64>) -> Result<f64, argmin::core::Error> {
        self.0.cost(z)
    }
}

impl Objective<'_> {
    /// The misfit at z: from the runs made, else a new run (none outside the bounds; an error,
    /// which stops the optimiser, once `max_evals` runs were made or on Ctrl-C).
    fn cost(&self, z: &[f64]) -> Result<f64, argmin::core::Error> {
        let outside: f64 = z.iter().map(|v| (-v).max(v - 1.0).max(0.0)).sum();
        if outside > 0.0 {
            return Ok(FAILED_COST * (1.0 + outside));
        }
        if let Some(e) = self.state.borrow().cache.get(&bits(z)) {
            return Ok(e.cost());
        }
        {
            let mut st = self.state.borrow_mut();
            if self.cancel.load(Ordering::SeqCst) {
                st.stopped = Some(Stop::Cancelled);
            } else if st.records.len() >= self.max_evals {
                st.stopped = Some(Stop::MaxEvals);
            } else if st.since_best >= stall_runs(self.prep.problem.free.len()) {
                st.stopped = Some(Stop::Stalled);
            }
            if st.stopped.is_some() {
                return Err(argmin::core::Error::msg("the fit stops"));
            }
        }
        let values = self.values(z);
        let e = (self.prep.problem).evaluate(&values, self.threads, self.cancel);
        let cost = e.cost();
        let cancelled = matches!(e, Evaluation::Cancelled);
        self.state.borrow_mut().add(z, values, e);
        if cancelled {
            self.state.borrow_mut().stopped = Some(Stop::Cancelled);
            return Err(argmin::core::Error::msg("the fit stops"));
        }
        Ok(cost)
    }
}

/// The first simplex: z₀ and z₀ ± `step` eⱼ (towards the inside of the bounds).
pub(super) fn first_simplex(z0: &[f64], step: f64) -> Vec<Vec<f64>> {
    let mut s = vec![z0.to_vec()];
    for j in 0..z0.len() {
        let mut z = z0.to_vec();
        z[j] += if z0[j] + step <= 1.0 { step } else { -step };
        s.push(z);
    }
    s
}

/// The primes that are the bases of the Halton sequence, one per free key.
pub(super) const HALTON_BASES: [u64; 16] =
    [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53];

/// Point `i` (from 1) of the Halton sequence in [0, 1)^n: coordinate j is the radical inverse of
/// i in base pⱼ (the digits of i mirrored about the radix point). Its first N points cover the cube
/// evenly at every scale, without a random seed.
pub fn halton(i: u64, n: usize) -> Vec<f64> {
    HALTON_BASES[..n]
        .iter()
        .map(|&b| {
            let (mut f, mut r, mut k) = (1.0, 0.0, i);
            while k > 0 {
                f /= b as f64;
                r += f * (k % b) as f64;
                k /= b;
            }
            r
        })
        .collect()
}

/// Default of `--sample` for n free keys: 20 n points.
pub fn default_sample(n: usize) -> usize {
    20 * n
}

pub(super) use crate::tunables::FIT_MAX_RESTARTS as MAX_RESTARTS;

/// One descent of Nelder–Mead from the simplex of `from` and `step`: its first vertices run side
/// by side, then argmin's iterations until the tolerance, a stall, `max_evals` or Ctrl-C.
pub(super) fn nelder_mead(obj: &Objective<'_>, from: &[f64], step: f64, n: usize) -> Result<Stop> {
    let simplex = first_simplex(from, step);
    let left = obj
        .max_evals
        .saturating_sub(obj.state.borrow().records.len());
    let mut simplex_runs = simplex.clone();
    simplex_runs.truncate(1 + left.min(n));
    obj.run_many(&simplex_runs);
    {
        let mut st = obj.state.borrow_mut();
        st.since_best = 0;
        st.stopped = None;
    }
    let complete = simplex
        .iter()
        .all(|z| obj.state.borrow().cache.contains_key(&bits(z)));
    if obj.cancel.load(Ordering::SeqCst) {
        return Ok(Stop::Cancelled);
    }
    if !complete {
        return Ok(Stop::MaxEvals);
    }
    let solver = NelderMead::new(simplex)
        .with_sd_tolerance(obj.prep.args.tolerance)
        .map_err(|e| anyhow::anyhow!("--tolerance: {e}"))?;
    let result = Executor::new(ByRef(obj), solver)
        .configure(|s| s.max_iters(u64::MAX))
        .run();
    Ok(match result {
        Ok(r) => match r.state().get_termination_reason() {
            Some(TerminationReason::SolverConverged) => Stop::Converged,
            _ => Stop::MaxEvals,
        },
        Err(e) => match obj.state.borrow().stopped {
            Some(s) => s,
            None => bail!("the optimiser failed: {e}"),
        },
    })
}

/// σ of each value, the correlation matrix (when every σ exists), the runs made.
pub(super) type Uncertainty = (Vec<Option<f64>>, Option<Vec<Vec<f64>>>, usize);

pub(super) use crate::tunables::FIT_JACOBIAN_STEP as JACOBIAN_STEP;

/// σ of each value and the correlations, from the Jacobian of the relative residuals at the
/// optimum z* by central differences (one-sided at a bound), its runs side by side; and how
/// many runs it made. Cov = s² (JᵀJ)⁻¹ with s² = Σ rᵢ² / (m − n).
pub(super) fn uncertainty(obj: &Objective<'_>, z: &[f64], y: &[f64]) -> Uncertainty {
    let p = &obj.prep.problem;
    let n = z.len();
    let mut points = Vec::new();
    for j in 0..n {
        for sign in [1.0, -1.0] {
            let mut zz = z.to_vec();
            zz[j] = (z[j] + sign * JACOBIAN_STEP).clamp(0.0, 1.0);
            points.push(zz);
        }
    }
    let values: Vec<Vec<f64>> = points.iter().map(|z| obj.values(z)).collect();
    let runs = run_side_by_side(p, &values, obj.threads, obj.cancel);
    let r0 = p.residuals(y);
    let m = r0.len();
    let mut jac = nalgebra::DMatrix::<f64>::zeros(m, n);
    let mut identified = vec![true; n];
    for j in 0..n {
        let (zp, zm) = (&points[2 * j], &points[2 * j + 1]);
        let (ep, em) = (&runs[2 * j], &runs[2 * j + 1]);
        let side = |zz: &Vec<f64>, e: &Evaluation| match e {
            Evaluation::Done { y, .. } if zz[j] != z[j] => {
                Some((obj.values(zz)[j], p.residuals(y)))
            }
            _ => None,
        };
        let here = || (obj.values(z)[j], r0.clone());
        let (a, b) = match (side(zp, ep), side(zm, em)) {
            (Some(a), Some(b)) => (a, b),
            (Some(a), None) => (a, here()),
            (None, Some(b)) => (here(), b),
            (None, None) => {
                identified[j] = false;
                continue;
            }
        };
        let dp = a.0 - b.0;
        for i in 0..m {
            jac[(i, j)] = (a.1[i] - b.1[i]) / dp;
        }
    }
    let extra = runs.len();
    if m <= n {
        return (vec![None; n], None, extra);
    }
    let s2 = r0.iter().map(|r| r * r).sum::<f64>() / (m - n) as f64;
    let jtj = jac.transpose() * &jac;
    let Some(inv) = jtj.clone().try_inverse() else {
        return (vec![None; n], None, extra);
    };
    let cov = inv * s2;
    let sigma: Vec<Option<f64>> = (0..n)
        .map(|j| {
            let v = cov[(j, j)];
            (identified[j] && v.is_finite() && v > 0.0).then(|| v.sqrt())
        })
        .collect();
    let correlation = sigma.iter().all(Option::is_some).then(|| {
        (0..n)
            .map(|i| {
                (0..n)
                    .map(|k| cov[(i, k)] / (cov[(i, i)] * cov[(k, k)]).sqrt())
                    .collect()
            })
            .collect()
    });
    (sigma, correlation, extra)
}
