//! Several constraints on one node solved together (model §3.7): a node in a cavity corner, a V,
//! or on two moulds gets one local problem over its active constraints
//! ([`contact_impulses`]), not constraint after constraint.
//!
//! Frictionless with one surface velocity (here at rest), V is the Euclidean projection of
//! V_free on the polyhedral cone {v : nᵢ·v ≥ 0}: checked against that projection computed
//! independently by enumerating the cone's faces (the nearest feasible face projection). The
//! solver stops when an update moves V by less than ε s (ε = [`JOINT_TOLERANCE`] = 1e-12,
//! s = |V_free|); in a 60° V a sweep contracts the error by cos²120° = 1/4, so what is left is
//! below ε s/3: the tolerance 1e-12 s.

use crate::common::{bare_box, mould};
use decohesion_physics::interface::contact::ContactStatus;
use decohesion_physics::interface::contact::{
    contact_impulses, Constraint, JointSolve, JOINT_TOLERANCE,
};
use decohesion_physics::material::{Material, MaterialModel};
use decohesion_physics::mesh::{dot, norm};
use decohesion_physics::model::{ContactFaces, Mould};
use decohesion_physics::solver::Simulation;
use proptest::prelude::*;

const M: f64 = 0.37;

fn unit(x: [f64; 3]) -> [f64; 3] {
    let l = norm(x);
    x.map(|c| c / l)
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Solves the node's constraints (surfaces at rest) from `v`: (V, impulses, statuses, solve).
fn solve(
    v: [f64; 3],
    normals: &[[f64; 3]],
    mu: f64,
    free: [bool; 3],
) -> ([f64; 3], Vec<[f64; 3]>, Vec<ContactStatus>, JointSolve) {
    let cs: Vec<Constraint> = (normals.iter())
        .map(|&n| Constraint {
            normal: n,
            v_surface: [0.0; 3],
            mu,
        })
        .collect();
    let (mut out, mut p) = (v, vec![[0.0; 3]; cs.len()]);
    let mut st = vec![ContactStatus::Open; cs.len()];
    let s = contact_impulses(&mut out, &cs, M, free, &mut p, &mut st);
    (out, p, st, s)
}

/// The projection of `v` on the cone {x : x·n₁ ≥ 0, x·n₂ ≥ 0} (n₁ ∦ n₂), by enumeration of
/// its faces: the interior (v itself), each half-plane's boundary plane, and the edge line
/// along n₁ × n₂; the projection is the nearest of the feasible candidates.
fn projection(v: [f64; 3], n1: [f64; 3], n2: [f64; 3]) -> [f64; 3] {
    let on_plane = |n: [f64; 3]| {
        let s = dot(v, n);
        [v[0] - s * n[0], v[1] - s * n[1], v[2] - s * n[2]]
    };
    let e = unit(cross(n1, n2));
    let on_edge = e.map(|c| dot(v, e) * c);
    let feasible = |x: &[f64; 3]| dot(*x, n1) >= -1e-15 && dot(*x, n2) >= -1e-15;
    let dist = |x: &[f64; 3]| norm([x[0] - v[0], x[1] - v[1], x[2] - v[2]]);
    [v, on_plane(n1), on_plane(n2), on_edge]
        .into_iter()
        .filter(feasible)
        .min_by(|a, b| dist(a).total_cmp(&dist(b)))
        .unwrap()
}

fn assert_close(a: [f64; 3], b: [f64; 3], tol: f64) {
    let d = norm([a[0] - b[0], a[1] - b[1], a[2] - b[2]]);
    assert!(d <= tol, "{a:?} vs {b:?}: {d:e} > {tol:e}");
}

/// A 90° corner (floor and wall) and a 60° V (two planes whose normals make 120°), a node
/// driven diagonally into each: V is the analytic projection, no approach is left into either
/// surface. In the V the one-surface-after-the-other pass would leave the node approaching the
/// floor at −0.433 of its speed: the wall's impulse has a component into the floor.
#[test]
fn a_node_driven_into_a_corner_and_a_v_gets_the_projection() {
    let floor = [0.0, 0.0, 1.0];
    let wall = [1.0, 0.0, 0.0];
    let (s60, c60) = (60f64.to_radians().sin(), 60f64.to_radians().cos());
    let (v1, v2) = ([-s60, 0.0, c60], [s60, 0.0, c60]);
    let overhang = [s60, 0.0, -c60];
    for (normals, v) in [
        ([floor, wall], [-1.0, 0.5, -2.0]),
        ([v1, v2], [-1.0, 0.3, -1.0]),
        ([v1, v2], [0.2, -0.7, -1.5]),
        ([floor, overhang], [-1.0, 0.0, -1.0]),
        ([floor, overhang], [-0.3, 0.4, -1.0]),
    ] {
        let (out, p, _, s) = solve(v, &normals, 0.0, [true; 3]);
        assert!(s.converged, "{s:?}");
        let exact = projection(v, normals[0], normals[1]);
        assert_close(out, exact, 1e-12 * norm(v));
        for (n, p) in normals.iter().zip(&p) {
            assert!(dot(out, *n) >= -1e-12 * norm(v), "approach left: {out:?}");
            // Frictionless: each impulse is along its normal, pushing.
            assert_close(*p, n.map(|c| dot(*p, *n) * c), 1e-15 * M * norm(v));
            assert!(dot(*p, *n) >= 0.0);
        }
    }
    // Into the edge of the V and of the overhang, with no velocity along it: the node stops.
    let (out, ..) = solve([-1.0, 0.0, -1.0], &[floor, overhang], 0.0, [true; 3]);
    assert_close(out, [0.0; 3], 1e-12);
}

/// The impulse of constraint `n` is in its Coulomb cone: λ = p·n ≥ 0 and |p − λn| ≤ μλ.
fn in_cone(p: [f64; 3], n: [f64; 3], mu: f64) -> bool {
    let lambda = dot(p, n);
    let t = [
        p[0] - lambda * n[0],
        p[1] - lambda * n[1],
        p[2] - lambda * n[2],
    ];
    lambda >= -1e-15 && norm(t) <= mu * lambda * (1.0 + 1e-12) + 1e-15
}

/// With friction, in the corner and the V: no approach left, the impulses in their cones, the
/// friction dissipating (−V·r_T ≥ 0 on every constraint at the end velocity, so the contact
/// step does no work on the node: ½m|V|² ≤ ½m|V_free|²); friction converged in most cases
/// (the rest took the frictionless projection, which keeps all three).
#[test]
fn with_friction_the_impulses_stay_in_their_cones_and_dissipate() {
    let (mut cases, mut with_friction) = (0, 0);
    let (s60, c60) = (60f64.to_radians().sin(), 60f64.to_radians().cos());
    for normals in [
        [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]],
        [[-s60, 0.0, c60], [s60, 0.0, c60]],
    ] {
        for mu in [0.1, 0.3, 1.0] {
            for v in [[-1.0, 2.0, -1.0], [0.3, 0.8, -1.0], [-2.0, -0.1, -0.5]] {
                let (out, p, st, s) = solve(v, &normals, mu, [true; 3]);
                assert!(s.converged, "{s:?}");
                cases += 1;
                with_friction += usize::from(
                    !s.friction_dropped
                        && p.iter().any(|p| {
                            p.iter()
                                .zip(&normals[0])
                                .any(|(a, b)| *a != 0.0 && *b == 0.0)
                        }),
                );
                for ((n, p), st) in normals.iter().zip(&p).zip(&st) {
                    assert!(dot(out, *n) >= -2e-12 * norm(v), "approach: {out:?}");
                    assert!(in_cone(*p, *n, mu), "{p:?} out of its cone, μ = {mu}");
                    let pt: [f64; 3] = std::array::from_fn(|c| p[c] - dot(*p, *n) * n[c]);
                    assert!(-dot(out, pt) >= -1e-12 * M * dot(v, v), "{st:?}");
                }
                assert!(dot(out, out) <= dot(v, v) * (1.0 + 1e-12));
            }
        }
    }
    assert!(
        2 * with_friction > cases,
        "{with_friction} of {cases} with friction"
    );
}

/// A node with x prescribed (a symmetry edge) in the corner of the floor and a wall whose
/// normal (0.6, 0.8, 0) leans across the prescribed axis, driven into both with v_x = −1 held:
/// its free components still get both constraints, the floor's (v_z = 0) and the wall's on
/// y (0.6 v_x + 0.8 v_y ≥ 0: v_y = 0.75), and v_x stays −1.
#[test]
fn a_partly_prescribed_node_in_a_corner_gets_both_constraints_on_its_free_components() {
    let normals = [[0.0, 0.0, 1.0], [0.6, 0.8, 0.0]];
    let free = [false, true, true];
    let (out, p, ..) = solve([-1.0, 0.2, -1.0], &normals, 0.0, free);
    assert_close(out, [-1.0, 0.75, 0.0], 1e-14);
    assert!(
        p.iter().all(|p| p[0] == 0.0),
        "an impulse on the prescribed axis"
    );
    // With friction the floor's friction acts on y only (x is held), within its cone.
    let (out, p, ..) = solve([-1.0, 0.2, -1.0], &normals, 0.3, free);
    assert!(dot(out, normals[0]) >= -1e-12 && dot(out, normals[1]) >= -1e-12);
    assert!(p.iter().all(|p| p[0] == 0.0));
}

/// Four surfaces whose admissible cone is {0} (the relative velocity must vanish), three of
/// them almost through one line (cond G = 1.7e6 for their active set): found by the proptest
/// below in a debug build, where the exact projection's first λ left the fourth surface
/// approached at 1.9e-11 s and no active set passed, so the sweeps ran to their cap. The
/// refined λ must give the exact answer, V = v_surface, to the round-off of forming ΔV from
/// impulses of ~800 m·s (ε Σ|λ|/m ≈ 1e-12 s).
#[test]
fn an_ill_conditioned_active_set_still_gives_the_exact_projection() {
    let raw = [
        [-0.6676862573850261, 0.6500144455847704, 0.537891497783138],
        [0.7325664510423866, 0.11271478147290309, -0.6637368727082611],
        [
            0.007537511981399864,
            -0.9272324727356182,
            0.07861542958418648,
        ],
        [0.0, 0.0, -0.4434505665349474],
    ];
    let vs = [0.0, 0.5351738147890193, 0.0];
    let cs: Vec<Constraint> = (raw.iter())
        .map(|&n| Constraint {
            normal: unit(n),
            v_surface: vs,
            mu: 0.0,
        })
        .collect();
    let v0 = [0.0, 0.0, -1.6398750073771164];
    let (mut v, mut p) = (v0, vec![[0.0; 3]; cs.len()]);
    let mut st = vec![ContactStatus::Open; cs.len()];
    let solve = contact_impulses(&mut v, &cs, M, [true; 3], &mut p, &mut st);
    let s = norm([v0[0] - vs[0], v0[1] - vs[1], v0[2] - vs[2]]);
    assert!(solve.converged && solve.sweeps == 0, "{solve:?}");
    assert_close(v, vs, 4e-12 * s);
    for c in &cs {
        let rel = [v[0] - vs[0], v[1] - vs[1], v[2] - vs[2]];
        assert!(dot(rel, c.normal) >= -(cs.len() as f64) * JOINT_TOLERANCE * s);
    }
}

proptest! {
    /// Random 2–4 normals within 150° of each other (no narrow slot, where the sweeps
    /// contract slowly), a surface velocity shared by all (so the admissible set is not
    /// empty), random V_free and μ: no approach left beyond k ε s, every impulse in its cone,
    /// and the relative kinetic energy not increased by the contact step.
    #[test]
    fn joint_solve_properties(
        raw in prop::collection::vec(prop::array::uniform3(-1.0f64..1.0), 2..=4),
        v in prop::array::uniform3(-3.0f64..3.0),
        vs in prop::array::uniform3(-1.0f64..1.0),
        mu in 0.0f64..1.5,
    ) {
        prop_assume!(raw.iter().all(|n| norm(*n) > 0.2));
        let normals: Vec<[f64; 3]> = raw.iter().map(|&n| unit(n)).collect();
        for (i, a) in normals.iter().enumerate() {
            for b in &normals[..i] {
                prop_assume!(dot(*a, *b) > -150f64.to_radians().cos().abs());
            }
        }
        let cs: Vec<Constraint> = normals.iter()
            .map(|&n| Constraint { normal: n, v_surface: vs, mu })
            .collect();
        let (mut out, mut p) = (v, vec![[0.0; 3]; cs.len()]);
        let mut st = vec![ContactStatus::Open; cs.len()];
        let solve = contact_impulses(&mut out, &cs, M, [true; 3], &mut p, &mut st);
        let rel = |x: [f64; 3]| [x[0] - vs[0], x[1] - vs[1], x[2] - vs[2]];
        let s = norm(rel(v));
        let k = cs.len() as f64;
        for (n, p) in normals.iter().zip(&p) {
            prop_assert!(in_cone(*p, *n, mu), "{:?} out of its cone", p);
            if solve.converged {
                prop_assert!(dot(rel(out), *n) >= -k * JOINT_TOLERANCE * s - 1e-15);
            } else {
                prop_assert!(dot(rel(out), *n) >= -1e-6 * s, "{:?}", solve);
            }
        }
        let (e0, e1) = (dot(rel(v), rel(v)), dot(rel(out), rel(out)));
        prop_assert!(e1 <= e0 * (1.0 + 1e-9) + 1e-300, "{} > {}", e1, e0);
    }
}

/// A sheared block whose `x-` face lies on a wall leaning 30° over it (normal
/// (sin 60°, 0, −cos 60°)), its `z-` face on the floor: the edge nodes sit in a 60° corner,
/// and the block is thrown into it diagonally, (−1, 0, −1) m/s, μ = 0.3. Every step, every
/// node with both constraints active leaves with no approach into either (the
/// one-after-the-other pass left −0.43 m/s into the floor); no node ends inside either mould
/// beyond one step's travel; the ledger closes to 1e-3.
#[test]
fn a_block_thrown_into_a_sixty_degree_corner_between_two_moulds() {
    let (s60, c60) = (60f64.to_radians().sin(), 60f64.to_radians().cos());
    let overhang = [s60, 0.0, -c60];
    let mut model = bare_box(
        [0.05, 0.05, 0.05],
        [3, 3, 3],
        Material::new(MaterialModel::NeoHookean, 5.0e6, 0.3, 1100.0),
        5.0e-3,
    );
    for x in &mut model.mesh.nodes {
        x[0] += x[2] * c60 / s60;
    }
    model.moulds = vec![
        Mould {
            name: "floor".into(),
            ..mould()
        },
        Mould {
            name: "wall".into(),
            normal: overhang,
            ..mould()
        },
    ];
    for (faces, plane) in [("z-", 0), ("x-", 1)] {
        model.contacts.push(ContactFaces {
            faces: faces.into(),
            plane,
            mu: 0.3,
        });
    }
    model.initial_velocity = [-1.0, 0.0, -1.0];
    let mut sim = Simulation::new(model).unwrap();
    let normals = [[0.0, 0.0, 1.0], overhang];
    let mut corner_steps = 0;
    while !sim.finished() {
        sim.step().expect("stable run");
        let mut active: std::collections::BTreeMap<u32, usize> = Default::default();
        for cn in sim.state.contact_nodes.iter().filter(|c| c.gap <= 0.0) {
            *active.entry(cn.node).or_default() += 1;
        }
        for (&node, _) in active.iter().filter(|(_, &k)| k == 2) {
            corner_steps += 1;
            let v = sim.state.v.get(node as usize);
            for n in normals {
                assert!(dot(v, n) >= -1e-9, "node {node} approaches: v = {v:?}");
            }
        }
    }
    assert!(
        corner_steps > 20,
        "the corner nodes were in contact {corner_steps} times"
    );
    assert_eq!(sim.stats.joint_contact.capped, 0);
    // Velocity-level contact: a node enters a surface by at most one step's travel before its
    // gap turns ≤ 0 (|V| ≤ √2 m/s here, the throw's speed, with margin for the rebound).
    let travel = sim.state.h * 2.0;
    for (i, x) in sim.model.mesh.nodes.iter().enumerate() {
        let y: [f64; 3] = std::array::from_fn(|c| x[c] + sim.state.u.get(i)[c]);
        for n in normals {
            assert!(dot(y, n) >= -travel, "node {i} inside: {y:?}");
        }
    }
    let residual = sim.state.ledger.max_relative_residual;
    assert!(residual < 1e-3, "ledger residual {residual:e}");
}
