//! Stage 7 (model §4.7, §3): unilateral contact with Coulomb friction at one node, in closed
//! form (the mass is lumped and the integration nodal, so each node's problem is local).
//!
//! Conventions: n is the surface's unit normal pointing into the solid, a gap g > 0 is open,
//! velocities are relative to the surface's material point, impulses are W R (N·s).

pub use crate::tunables::{JOINT_MAX_CONSTRAINTS, JOINT_MAX_SWEEPS, JOINT_TOLERANCE};
use crate::vec3::{dot, norm};

/// Contact status of a node against a plane, for output and debugging.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum ContactStatus {
    /// Gap > 0, or approaching velocity ≥ 0: no impulse.
    #[default]
    Open,
    /// |r_T| ≤ μ r_N: no sliding.
    Stick,
    /// |r_T| = μ r_N opposing the sliding velocity.
    Slip,
}

/// Stage 7 for one node against one surface (model §3.4, paper eqs. 19–20, 22): if gₙ₊₁ ≤ 0
/// and the relative free velocity approaches (v_N < 0), r_N = −m v_N/W brings v_N to 0; the
/// trial tangential impulse −m v_T/W sticks if |r_T| ≤ μ r_N, else r_T = −μ r_N v_T/|v_T|.
///
/// A node whose velocity components are partly prescribed (`free[c]` false: a symmetry edge, a
/// clamped edge) gets contact and friction on its free components only.
///
/// Let F be the span of the free axes (`free[c]`), P_F its projector, V* the velocity after
/// stage 6 (prescribed components already set), v* = V* − v_plane. The mould pushes with
/// λn + r_T (r_T ⊥ n); the Dirichlet support takes the share on the prescribed components,
/// so what moves the node is the projection on F, p = P_F(λn + r_T), with V = V* + p/m. The
/// friction is taken in F as well, r_T ∈ T_F = F ∩ n^⊥. For u ∈ F, u·n = u·n_F with
/// n_F = P_F n, so T_F = F ∩ n_F^⊥: the normal part λn_F and the tangential part r_T of p are
/// orthogonal and the problem splits as in the free case. With v_N = n·(V − v_plane):
///
/// - normal: v_N = v*_N + λ|n_F|²/m, and 0 ≤ v_N ⊥ λ ≥ 0 (eq. 19 in F) gives
///   λ = max(0, −m v*_N/|n_F|²): the free components bring the approach velocity to 0;
/// - tangential: w = the component of v* in T_F, trial r_T = −m w; it sticks if
///   |r_T| ≤ μλ (λ is the mould's normal reaction, of which the node feels λn_F), else
///   r_T = −μλ w/|w| (eq. 20 in T_F);
/// - |n_F|² ≤ 1e-12 (the normal along prescribed axes only): the free components cannot change
///   the gap, the prescribed motion alone sets it; no impulse.
///
/// With no axis prescribed (F = ℝ³, n_F = n) this is the law above (and the same operations). It is exact Coulomb
/// when the prescribed components do not slide along the mould (a symmetry plane; a clamped
/// edge moved along the normal, e.g. the peel's lifted end); when they do (a node dragged
/// along the mould by its prescribed motion), the friction of that sliding goes to the
/// support's reaction and the free components obey Coulomb on their own instead of sharing
/// one cone with it. The prescribed share of λn + r_T is not added to the reported reaction
/// (only their sum is determined on those components).
///
/// **A held contact stays a candidate while its gap is open** (`held = Some(h)`, h = h_{n+3/2},
/// for an entry closed at the previous step): its constraint is n·(V − v_plane) ≥ −g⁺/h, which
/// at g ≤ 0 is eq. 19's v_N ≥ 0 unchanged and at g > 0 lets the node close the gap over the
/// next step but not pass it (the gap predicted at tₙ₊₂, gₙ₊₁ + h v_N ≥ 0). Why: on a turning
/// or curved mould the velocity-level constraint lets the gap of a sliding contact drift by
/// h²(ω×n)·v_T + h²|v_T|²/2R per step; once it reads g > 0 the eq. 19 rule released the node
/// for one step with its free velocity, which a force pressing it on the mould makes large, and
/// it entered by h|v_N,free|, which nothing takes back (roller_peel: a round-off drift, then
/// several steps' travel inside the roller for the rest of the run, after a small relative
/// change of h; docs: performance log). A first contact (`held = None`) keeps eq. 19 at
/// gₙ₊₁ ≤ 0 alone: predicting it too would spread the stop of an impact over two steps (in
/// the dropped column, the first landing's loss then far outside the test's 1e-3 of
/// ½ m_b v_b²; docs: performance log).
///
/// Updates `v` in place (free components only) and returns the impulse W R_c [N·s] and the
/// status.
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn contact_impulse(
    v: &mut [f64; 3],
    gap: f64,
    n: [f64; 3],
    v_plane: [f64; 3],
    mu: f64,
    m: f64,
    free: [bool; 3],
    held: Option<f64>,
) -> ([f64; 3], ContactStatus) {
    let all_free = free == [true; 3];
    let on_f = |x: [f64; 3]| std::array::from_fn::<f64, 3, _>(|c| if free[c] { x[c] } else { 0.0 });
    let n_f = if all_free { n } else { on_f(n) };
    let nf2 = if all_free { 1.0 } else { dot(n_f, n_f) };
    let Some(reach) = held_reach(gap, held) else {
        return ([0.0; 3], ContactStatus::Open);
    };
    if nf2 <= 1e-12 {
        return ([0.0; 3], ContactStatus::Open);
    }
    let rel = [v[0] - v_plane[0], v[1] - v_plane[1], v[2] - v_plane[2]];
    // The approach beyond what closes a held contact's open gap in one step (else the
    // approach itself).
    let vn = dot(rel, n) + reach;
    if vn >= 0.0 {
        return ([0.0; 3], ContactStatus::Open);
    }
    // Impulses (W R) rather than per-area values: W cancels (model §3.4).
    // λ: the normal reaction; w: the relative velocity in the tangent space (T_F).
    let (lambda, w) = if all_free {
        let rn = dot(rel, n);
        let vt = [rel[0] - rn * n[0], rel[1] - rn * n[1], rel[2] - rn * n[2]];
        (-m * vn, vt)
    } else {
        let rf = on_f(rel);
        let s = dot(rf, n_f) / nf2;
        let w = [rf[0] - s * n_f[0], rf[1] - s * n_f[1], rf[2] - s * n_f[2]];
        (-m * vn / nf2, w)
    };
    let w_norm = norm(w);
    let (pt, status) = if m * w_norm <= mu * lambda {
        (w.map(|c| -m * c), ContactStatus::Stick)
    } else {
        let k = mu * lambda / w_norm;
        (w.map(|c| -k * c), ContactStatus::Slip)
    };
    let p = [
        lambda * n_f[0] + pt[0],
        lambda * n_f[1] + pt[1],
        lambda * n_f[2] + pt[2],
    ];
    for c in 0..3 {
        v[c] += p[c] / m;
    }
    (p, status)
}

/// Whether an entry of gap `gap` is a candidate of stage 7, and how far it may approach its
/// mould over the next step beyond v_N = 0: a held entry (`held = Some(h)`, closed at the
/// previous step, h = h_{n+3/2}) always, with reach g⁺/h (its constraint v_N ≥ −g⁺/h); a first
/// contact (`None`) only at g ≤ 0, with reach 0 (eq. 19); `None` returned: not a candidate.
/// The one definition of the held rule, for the one-surface closed form ([`contact_impulse`])
/// and the joint solve's candidates.
#[inline]
pub fn held_reach(gap: f64, held: Option<f64>) -> Option<f64> {
    match held {
        Some(h) => Some(gap.max(0.0) / h),
        None if gap > 0.0 => None,
        None => Some(0.0),
    }
}

/// One active unilateral constraint of a node (gₙ₊₁ ≤ 0) in a joint solve
/// ([`contact_impulses`]): the surface's unit normal n into the solid, the velocity of the
/// surface's material point where it acts, and its Coulomb coefficient (μ, or μ(αₙ₊₁) of a
/// glued entry).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Constraint {
    pub normal: [f64; 3],
    pub v_surface: [f64; 3],
    pub mu: f64,
}

/// What a joint solve took: the sweeps, whether the impulses converged to
/// [`JOINT_TOLERANCE`] before [`JOINT_MAX_SWEEPS`], and the last sweep's largest impulse change
/// relative to s.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointSolve {
    pub sweeps: u32,
    pub converged: bool,
    pub change: f64,
    /// The largest approach velocity left, maxᵢ −vᵢ,N, relative to s (≤ 0 when none).
    pub approach: f64,
    /// The frictional sweeps hit the cap and the node got the frictionless projection.
    pub friction_dropped: bool,
}

/// Stage 7 for one node against several active surfaces together (model §3.7,
/// generalising the closed form of §3.4): a corner of a cavity, two moulds,
/// a node glued to one mould and touching another.
///
/// **Problem.** Find impulses pᵢ (what the node feels of surface i, on its free components F
/// as in [`contact_impulse`]) with V = V_free + Σᵢ pᵢ/m and, for every i,
/// 0 ≤ vᵢ,N ⊥ λᵢ ≥ 0 with vᵢ = V − v_surface,i, vᵢ,N = nᵢ·vᵢ, pᵢ = λᵢ nᵢ,F + rᵢ,T, and
/// Coulomb on rᵢ,T ∈ T_F,i: |rᵢ,T| ≤ μᵢλᵢ, sticking (wᵢ = 0) or opposing the sliding
/// wᵢ (the part of vᵢ in T_F,i). Frictionless, these are the KKT conditions of
/// min ½m|V − V_free|² over V ∈ V_free + F with nᵢ·(V − v_surface,i) ≥ 0 for every i: V is
/// the mass-weighted projection of the free velocity on the intersection of the half-spaces
/// (Gauss's least constraint, Moreau's velocity-level contact), unique when the set is
/// non-empty (it is convex and closed). It is non-empty with one surface velocity (it holds
/// v_s) and whenever the surfaces do not close onto the node faster than it can follow; two
/// walls closing on a node from both sides leave no admissible V, and the sweeps then stop at
/// the cap with the approach velocity reported.
///
/// **Method.** Frictionless (every μᵢ = 0), the projection exactly, by enumeration of the
/// active sets (model §3.7; [`projection`]). With friction, projected Gauss–Seidel on
/// accumulated impulses (as rapier and Bullet): a sweep
/// visits the constraints in order; for each, its own impulse is taken out of V and the
/// one-surface problem is solved exactly in closed form with the others held
/// ([`contact_impulse`]). Frictionless, this is exact coordinate descent on the dual of the
/// projection problem, monotone in the dual objective and convergent; each sweep shrinks the
/// error by about cos²θ, θ the angle between the normals (one sweep at a 90° corner, ×0.25 per
/// sweep in a 60° V, slow in a narrow slot, nᵢ ≈ −nⱼ). With friction it is the usual PGS for
/// the Coulomb problem, whose fixed points are exactly the conditions above.
///
/// **Tolerance.** The sweeps stop when no update changed the velocity by more than ε s
/// (|Δpᵢ|/m ≤ ε s, ε = [`JOINT_TOLERANCE`], s = maxᵢ |V_free − v_surface,i|); then the last
/// sweep left each vᵢ,N ≥ −(k − 1) ε s (k constraints: only the later constraints' changes act
/// on it) and each impulse in its cone exactly (every update is a cone point). After
/// [`JOINT_MAX_SWEEPS`] with friction unconverged, the node gets the frictionless
/// projection instead (`friction_dropped`: no friction on it for that step, which keeps the
/// three guarantees: no approach, impulses in their cones, no energy gained). PGS with
/// friction can contract slowly or cycle: a node barely slipping on two walls
/// (m|wᵢ| just above μᵢλᵢ), whose friction on one wall pushes along the other's normal, has a
/// sweep factor μᵢλᵢ/(m|wᵢ|) → 1 (the demould scene's cavity corners as the walls slide). If the
/// frictionless sweeps hit the cap too (nearly opposite normals) it stops with `converged`
/// false and the approach velocity left; the caller counts both ([`JointStats`]) and the run
/// warns. At convergence
/// Σᵢ vᵢ·pᵢ ≤ 0 (each term: 0 from the normal complementarity, 0 when sticking, −μλ|wᵢ| when
/// slipping), so with one surface velocity v_s the relative kinetic energy ½m|V − v_s|² is not
/// increased: ½m|V_free − v_s|² = ½m|V − v_s|² − Σ vᵢ·pᵢ + |Σpᵢ|²/2m.
///
/// With one constraint the first sweep is [`contact_impulse`] itself and the second changes
/// nothing; the boundary pass calls this only with two or more.
///
/// Writes V into `v`, pᵢ [N·s] into `impulses[i]` and the status into `status[i]`.
pub fn contact_impulses(
    v: &mut [f64; 3],
    constraints: &[Constraint],
    m: f64,
    free: [bool; 3],
    impulses: &mut [[f64; 3]],
    status: &mut [ContactStatus],
) -> JointSolve {
    let v_free = *v;
    let scale = constraints.iter().fold(0.0f64, |a, c| {
        a.max(norm(std::array::from_fn(|k| v_free[k] - c.v_surface[k])))
    });
    let frictional = constraints.iter().any(|c| c.mu > 0.0);
    let mut out = if frictional {
        sweeps(v, constraints, true, m, free, impulses, status, scale)
    } else {
        JointSolve::default()
    };
    if !out.converged {
        // Frictionless, or friction did not converge: the exact frictionless projection.
        *v = v_free;
        let sweeps_frictional = out.sweeps;
        out = match projection(v_free, constraints, m, free, impulses, status, scale) {
            true => JointSolve {
                converged: true,
                ..JointSolve::default()
            },
            false => sweeps(v, constraints, false, m, free, impulses, status, scale),
        };
        out.sweeps += sweeps_frictional;
        out.friction_dropped = frictional;
    }
    // V = V_free + Σ pᵢ/m exactly as the ledger pairs them.
    *v = std::array::from_fn(|k| v_free[k] + impulses.iter().map(|p| p[k]).sum::<f64>() / m);
    out.approach = constraints.iter().fold(0.0f64, |a, c| {
        let rel: [f64; 3] = std::array::from_fn(|k| v[k] - c.v_surface[k]);
        a.max(-dot(rel, c.normal) / scale.max(f64::MIN_POSITIVE))
    });
    out
}

/// The frictionless problem of [`contact_impulses`] exactly, by enumeration of the active
/// sets (model §3.7): for each set S of at most dim F constraints, the impulses
/// pᵢ = λᵢaᵢ (aᵢ = P_F nᵢ) that bring every nᵢ·(V − v_surface,i), i ∈ S, to 0 solve
/// G λ = −m b with G_ij = aᵢ·aⱼ, bᵢ = nᵢ·(V_free − v_surface,i) (S skipped when G is singular
/// to 1e-12); S is admissible when λ ≥ 0 and every constraint holds (to 1e-12 s). The KKT
/// point is admissible, and any admissible V is a point of the set, so the admissible V
/// nearest to V_free is the projection. Writes the impulses and statuses; false when no set is
/// admissible (round-off on degenerate normals), leaving them to the sweeps.
fn projection(
    v_free: [f64; 3],
    constraints: &[Constraint],
    m: f64,
    free: [bool; 3],
    impulses: &mut [[f64; 3]],
    status: &mut [ContactStatus],
    scale: f64,
) -> bool {
    let k = constraints.len();
    if k > JOINT_MAX_CONSTRAINTS {
        return false;
    }
    let dim = free.iter().filter(|&&f| f).count();
    // Fixed-size work arrays: this runs inside the time step, at every node with several
    // active constraints, and must not allocate.
    let (mut a, mut b) = (
        [[0.0; 3]; JOINT_MAX_CONSTRAINTS],
        [0.0; JOINT_MAX_CONSTRAINTS],
    );
    for (i, c) in constraints.iter().enumerate() {
        a[i] = std::array::from_fn(|j| if free[j] { c.normal[j] } else { 0.0 });
        b[i] = dot(
            c.normal,
            std::array::from_fn(|j| v_free[j] - c.v_surface[j]),
        );
    }
    let tol = 1e-12 * scale;
    let mut best: Option<(f64, u32, [f64; 3])> = None;
    for set in 0u32..(1 << k) {
        let (mut s_all, mut ns) = ([0usize; JOINT_MAX_CONSTRAINTS], 0);
        for i in (0..k).filter(|&i| set & (1 << i) != 0) {
            s_all[ns] = i;
            ns += 1;
        }
        if ns > dim {
            continue;
        }
        let s = &s_all[..ns];
        let mut g = [[0.0; 3]; 3];
        let mut rhs = [0.0; 3];
        for (r, &i) in s.iter().enumerate() {
            rhs[r] = -m * b[i];
            for (c, &j) in s.iter().enumerate() {
                g[r][c] = dot(a[i], a[j]);
            }
        }
        let Some(mut lambda) = solve_small(g, rhs, ns) else {
            continue;
        };
        let dv_of = |lambda: &[f64; 3]| -> [f64; 3] {
            std::array::from_fn(|j| {
                s.iter().zip(lambda).map(|(&i, l)| l * a[i][j]).sum::<f64>() / m
            })
        };
        let gap_rate = |i: usize, dv: [f64; 3]| b[i] + dot(constraints[i].normal, dv);
        let mut dv = dv_of(&lambda);
        if (0..k).any(|i| gap_rate(i, dv) < -tol) {
            // Nearly dependent normals (cond G up to ~1e6: three surfaces almost through one
            // line) leave λ with an error along G's near-null direction that shows as a
            // violation of ~cond(G)·ε·s. Iterative refinement on the quantity that matters,
            // the active rates cᵢ = bᵢ + nᵢ·ΔV(λ) (i ∈ S): G δλ = −m c, λ += δλ, twice,
            // brings them to the round-off of forming ΔV, ~ε Σ|λᵢ|/m. Only a set that failed
            // the check is refined, so a well-conditioned set keeps its bits.
            for _ in 0..2 {
                let mut r = [0.0; 3];
                for (r, &i) in r.iter_mut().zip(s) {
                    *r = -m * gap_rate(i, dv);
                }
                let Some(d) = solve_small(g, r, ns) else {
                    break;
                };
                lambda.iter_mut().zip(d).for_each(|(l, d)| *l += d);
                dv = dv_of(&lambda);
            }
        }
        if lambda[..ns].iter().any(|&l| l < -1e-12 * m * scale) {
            continue;
        }
        let ok = (0..k).all(|i| gap_rate(i, dv) >= -tol);
        let d = norm(dv);
        if ok && best.is_none_or(|(bd, ..)| d < bd) {
            best = Some((d, set, lambda));
        }
    }
    let Some((_, set, lam)) = best else {
        return false;
    };
    let mut next = 0;
    for i in 0..k {
        let l = if set & (1 << i) != 0 {
            next += 1;
            lam[next - 1].max(0.0)
        } else {
            0.0
        };
        impulses[i] = a[i].map(|c| l * c);
        status[i] = if l > 0.0 {
            ContactStatus::Slip
        } else {
            ContactStatus::Open
        };
    }
    true
}

/// Solves the small symmetric system g x = rhs of its first `n` rows and columns (n ≤ 3) by
/// Gaussian elimination with partial pivoting; `None` when a pivot is below 1e-12 of the
/// largest entry (dependent normals). Entries beyond `n` are left 0.
fn solve_small(mut g: [[f64; 3]; 3], mut rhs: [f64; 3], n: usize) -> Option<[f64; 3]> {
    let big = (g[..n].iter())
        .flat_map(|row| &row[..n])
        .fold(0.0f64, |a, x| a.max(x.abs()));
    for c in 0..n {
        let p = (c..n).max_by(|&i, &j| g[i][c].abs().total_cmp(&g[j][c].abs()))?;
        if g[p][c].abs() <= 1e-12 * big {
            return None;
        }
        g.swap(c, p);
        rhs.swap(c, p);
        for r in c + 1..n {
            let f = g[r][c] / g[c][c];
            for j in c..n {
                g[r][j] -= f * g[c][j];
            }
            rhs[r] -= f * rhs[c];
        }
    }
    let mut x = [0.0; 3];
    for c in (0..n).rev() {
        let s: f64 = (c + 1..n).map(|j| g[c][j] * x[j]).sum();
        x[c] = (rhs[c] - s) / g[c][c];
    }
    Some(x)
}

/// The sweeps of [`contact_impulses`] from V = `v` (= V_free), with each constraint's μ
/// (`friction`) or none, until every update moves V by at most [`JOINT_TOLERANCE`]·`scale` or
/// [`JOINT_MAX_SWEEPS`].
#[allow(clippy::too_many_arguments)]
fn sweeps(
    v: &mut [f64; 3],
    constraints: &[Constraint],
    friction: bool,
    m: f64,
    free: [bool; 3],
    impulses: &mut [[f64; 3]],
    status: &mut [ContactStatus],
    scale: f64,
) -> JointSolve {
    let tol = JOINT_TOLERANCE * scale;
    impulses.iter_mut().for_each(|p| *p = [0.0; 3]);
    let mut out = JointSolve {
        sweeps: 0,
        converged: false,
        change: 0.0,
        approach: 0.0,
        friction_dropped: false,
    };
    while out.sweeps < JOINT_MAX_SWEEPS {
        out.sweeps += 1;
        let mut step = 0.0f64;
        for (i, c) in constraints.iter().enumerate() {
            let old = impulses[i];
            let mu = if friction { c.mu } else { 0.0 };
            // V without this constraint's impulse, then its one-surface problem.
            let mut vi: [f64; 3] = std::array::from_fn(|k| v[k] - old[k] / m);
            let (p, s) = contact_impulse(&mut vi, 0.0, c.normal, c.v_surface, mu, m, free, None);
            step = step.max(norm(std::array::from_fn(|k| p[k] - old[k])) / m);
            (impulses[i], status[i], *v) = (p, s, vi);
        }
        out.change = step / scale.max(f64::MIN_POSITIVE);
        if step <= tol {
            out.converged = true;
            break;
        }
    }
    out
}

/// The counts of the joint solves of a step, reduced with the boundary sums: nodes solved
/// together, their sweeps, the solves whose friction did not converge (frictionless instead),
/// the solves that hit [`JOINT_MAX_SWEEPS`] without friction too,
/// and among those the largest last change and approach velocity left, relative to s
/// ([`JointSolve`]).
#[derive(Default, Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct JointStats {
    pub nodes: u64,
    pub sweeps: u64,
    pub capped: u64,
    pub friction_dropped: u64,
    pub worst_change: f64,
    pub worst_approach: f64,
}

impl JointStats {
    /// No joint solve was made.
    pub fn is_empty(&self) -> bool {
        self.nodes == 0
    }

    pub fn merge(mut self, o: JointStats) -> JointStats {
        self.nodes += o.nodes;
        self.sweeps += o.sweeps;
        self.capped += o.capped;
        self.friction_dropped += o.friction_dropped;
        self.worst_change = self.worst_change.max(o.worst_change);
        self.worst_approach = self.worst_approach.max(o.worst_approach);
        self
    }
}

#[cfg(test)]
mod tests;
