//! A concave corner of one triangulated mould (model §7.5): the mould is the solid
//! {x < 0} ∪ {z < 0} (a floor z = 0 and a wall x = 0 meeting along the y axis), one surface of
//! triangles; a block sits in the corner with its `x-` face on the wall and its `z-` face on the
//! floor, so its edge nodes on the y axis touch both faces of the one mould.
//!
//! A node inside both faces has the corner line as its closest feature, whose pseudo-normal is
//! (1, 0, 1)/√2: that one constraint lets the node slide along (−1, 0, 1) into the wall (or
//! along (1, 0, −1) into the floor) and keeps none of the faces. Model §7.5 gives such a node one
//! constraint per face it is behind, solved together (model §3.7), and a node on two face sets
//! of the one mould one constraint per distinct face, whose friction is shared by both entries
//! (their μ weighted by their areas), not taken by the first entry alone.

use crate::common::bare_box;
use decohesion_physics::material::{Material, MaterialModel};
use decohesion_physics::model::{ContactFaces, Mould, PrescribedDisplacement, Shape};
use decohesion_physics::mould::SurfaceMesh;
use decohesion_physics::piecewise::PiecewiseLinear;
use decohesion_physics::solver::Simulation;
use std::sync::Arc;

/// The mould {x < 0} ∪ {z < 0} as one open surface over y ∈ [−l, l]: the floor x ∈ [0, l] and
/// the wall z ∈ [0, l], `n` cells a side, two triangles a cell, outward (floor +z, wall +x),
/// sharing the corner line's vertices. 4n² triangles (n = 4: 64, above the size queried
/// without the lists of nearby triangles, so the lists' path is the one exercised).
fn l_mould(l: f64, n: u32) -> Mould {
    let step = |i: u32| i as f64 / n as f64;
    let mut v = Vec::new();
    // Floor P(i, j) = (l i/n, −l + 2l j/n, 0), then the wall Q(k, j), k ≥ 1 (k = 0 is P(0, j)).
    for i in 0..=n {
        for j in 0..=n {
            v.push([l * step(i), l * (2.0 * step(j) - 1.0), 0.0]);
        }
    }
    for k in 1..=n {
        for j in 0..=n {
            v.push([0.0, l * (2.0 * step(j) - 1.0), l * step(k)]);
        }
    }
    let p = |i: u32, j: u32| i * (n + 1) + j;
    let q = |k: u32, j: u32| {
        if k == 0 {
            p(0, j)
        } else {
            (n + k) * (n + 1) + j
        }
    };
    let mut t = Vec::new();
    for a in 0..n {
        for j in 0..n {
            let (fa, fb, fc, fd) = (p(a, j), p(a + 1, j), p(a + 1, j + 1), p(a, j + 1));
            t.extend([[fa, fb, fc], [fa, fc, fd]]);
            let (wa, wb, wc, wd) = (q(a, j), q(a, j + 1), q(a + 1, j + 1), q(a + 1, j));
            t.extend([[wa, wb, wc], [wa, wc, wd]]);
        }
    }
    let s = SurfaceMesh::new("l_mould", None, 1.0, v, t, &|k| format!("triangle {k}")).unwrap();
    Mould {
        name: "corner".into(),
        shape: Shape::Surface(Arc::new(s).into()),
        ..Default::default()
    }
}

/// A 20 mm block of soft rubber in the corner, its `x-` face (μ_x) and `z-` face (μ_z) in
/// contact with the one mould.
fn block_in_corner(mu_x: f64, mu_z: f64, end_time: f64) -> decohesion_physics::model::Model {
    let s = 0.02;
    let mut model = bare_box(
        [s; 3],
        [2, 2, 2],
        Material::new(MaterialModel::NeoHookean, 1.0e6, 0.3, 1100.0),
        end_time,
    );
    model.moulds = vec![l_mould(0.1, 4)];
    for (faces, mu) in [("x-", mu_x), ("z-", mu_z)] {
        model.contacts.push(ContactFaces {
            faces: faces.into(),
            plane: 0,
            mu,
        });
    }
    model
}

/// Squeezed into the corner (its `x+` face driven 4 mm towards the wall, its `z+` face 2 mm
/// towards the floor, over 20 ms), frictionless: the edge nodes are pressed into both faces.
///
/// Velocity-level contact (model §3.1, §4.7) has no position correction: a node in front of a
/// face at tₙ₊₁ is not constrained by it and can enter it over the next step by its travel
/// h|V|; a node behind a face that is one of its constraints leaves with n·V ≥ 0, so its depth
/// does not grow. So no node is ever deeper in a face than the largest one-step travel of the
/// run, h_max |V|_max, plus the snap of a gap to 0 within the round-off of positions (far below
/// the 1e-12 m allowed for it). And at every step, a node behind both faces leaves with no
/// approach into either, to the joint solve's tolerance (1e-12 of the velocity scale; 1e-9 of
/// the squeeze speed asserted). Before the rule the edge nodes got the corner's pseudo-normal
/// alone, and left the corner along (−1, 0, 1) or (1, 0, −1), into one of the faces.
#[test]
fn a_block_squeezed_into_a_concave_corner_enters_neither_face() {
    let t_end = 0.02;
    let mut model = block_in_corner(0.0, 0.0, t_end);
    let ramp = |u: f64| PiecewiseLinear {
        points: vec![(0.0, [0.0]), (t_end, [u])],
    };
    model.displacements = vec![
        PrescribedDisplacement {
            faces: "x+".into(),
            component: 0,
            history: ramp(-0.004),
        },
        PrescribedDisplacement {
            faces: "z+".into(),
            component: 2,
            history: ramp(-0.002),
        },
    ];
    let mut sim = Simulation::new(model).unwrap();
    let nodes: Vec<usize> = {
        let mut n: Vec<usize> = sim
            .state
            .contact_nodes
            .iter()
            .map(|c| c.node as usize)
            .collect();
        n.dedup();
        n
    };
    let speed = 0.2; // the x+ face's, m/s
    let (mut travel, mut deepest, mut both, mut at) = (0.0f64, 0.0f64, 0usize, (0.0, 0));
    let mut v_max = 0.0f64;
    // The fastest approach into a face of a node behind both: (−n·V, t, node, V).
    let mut worst = (0.0f64, 0.0, 0, [0.0; 3]);
    while !sim.finished() {
        sim.step().expect("stable run");
        for &i in &nodes {
            let (x0, u, v) = (
                sim.model.mesh.nodes[i],
                sim.state.u.get(i),
                sim.state.v.get(i),
            );
            let x: [f64; 3] = std::array::from_fn(|c| x0[c] + u[c]);
            let depth = (-x[0]).max(-x[2]);
            if depth > deepest {
                (deepest, at) = (depth, (sim.state.time, i));
            }
            v_max = v_max.max(v.iter().map(|c| c * c).sum::<f64>().sqrt());
            if x[0] < -1e-12 && x[2] < -1e-12 {
                both += 1;
                let approach = (-v[0]).max(-v[2]);
                if approach > worst.0 {
                    worst = (approach, sim.state.time, i, v);
                }
            }
        }
        travel = travel.max(sim.state.h * v_max);
    }
    eprintln!("deepest {deepest:e} m (t, node {at:?}); travel bound {travel:e} m; {both} node-steps behind both faces; fastest approach into a face behind both {worst:?}");
    assert!(
        both > 20,
        "the edge nodes were behind both faces {both} times"
    );
    assert!(
        worst.0 <= 1e-9 * speed,
        "a node behind both faces leaves into one (−n·V, t, node, V): {worst:?}"
    );
    assert!(
        deepest <= travel * (1.0 + 1e-9) + 1e-12,
        "a node {deepest:e} m inside the mould, beyond one step's travel {travel:e} m (t, node {at:?})"
    );
}

/// Two face sets of the block (`x-` frictionless, `z-` with μ = 0.6) in contact with the one
/// mould share the edge nodes, and so share each constraint there: one constraint per distinct
/// face, with μ̄ = Σ Wᵢμᵢ / Σ Wᵢ over the entries (the node's reaction spread over its entries'
/// areas W, each with its own μ), its normal impulse split in proportion to Wᵢ and its friction
/// in proportion to Wᵢμᵢ (each share in its own cone). The block slides along the corner line,
/// pressed into both faces: at an edge node behind both faces, pushed by both, and still
/// sliding along the corner line after the step (so slipping), the friction it feels is
/// μ̄ (λ_wall + λ_floor), to the joint solve's tolerance (1e-6 relative asserted); the
/// frictionless entry carries none of it at any step; both entries carry the same normal
/// impulse per area (but for the other face's friction along a normal, zero at a converged
/// slip along the corner line). Before, the two identical constraints went to the joint solve
/// as two, the first (`x-`, μ = 0) took the whole impulse and the node slid without friction.
#[test]
fn two_face_sets_on_one_mould_share_the_friction_of_one_constraint_per_face() {
    let (mu_x, mu_z) = (0.0, 0.6);
    let mut model = block_in_corner(mu_x, mu_z, 0.01);
    model.gravity = [-30.0, 0.0, -30.0];
    model.initial_velocity = [0.0, 0.5, 0.0];
    let mut sim = Simulation::new(model).unwrap();
    let mut by_node: std::collections::BTreeMap<u32, Vec<usize>> = Default::default();
    for (j, cn) in sim.state.contact_nodes.iter().enumerate() {
        by_node.entry(cn.node).or_default().push(j);
    }
    let shared: Vec<(usize, usize, usize)> = (by_node.iter())
        .filter(|(_, js)| js.len() == 2)
        .map(|(&n, js)| {
            let (a, b) = (js[0], js[1]);
            // (node, the x- entry, the z- entry)
            if sim.state.contact_nodes[a].mu == mu_x {
                (n as usize, a, b)
            } else {
                (n as usize, b, a)
            }
        })
        .collect();
    assert_eq!(shared.len(), 3, "the edge nodes of a 2×2×2 block");
    let (mut checked, mut worst) = (0usize, 0.0f64);
    while !sim.finished() {
        sim.step().expect("stable run");
        for &(i, jx, jz) in &shared {
            let (x0, u, v) = (
                sim.model.mesh.nodes[i],
                sim.state.u.get(i),
                sim.state.v.get(i),
            );
            let x: [f64; 3] = std::array::from_fn(|c| x0[c] + u[c]);
            let (ex, ez) = (&sim.state.contact_nodes[jx], &sim.state.contact_nodes[jz]);
            let (px, pz) = (
                ex.contact_impulse.map(|c| c * ex.area),
                ez.contact_impulse.map(|c| c * ez.area),
            );
            let p: [f64; 3] = std::array::from_fn(|c| px[c] + pz[c]);
            assert_eq!(
                px[1], 0.0,
                "the frictionless entry carries friction: {px:?}"
            );
            // Behind both faces, sliding along the corner line only (both faces closed:
            // no velocity along their normals) with both faces pushing.
            let along = v[0].abs().max(v[2].abs()) <= 1e-9 * v[1];
            if x[0] < -1e-12 && x[2] < -1e-12 && v[1] > 1e-6 && along && p[0] > 0.0 && p[2] > 0.0 {
                // The normal components (the faces' normals are x and z) per area.
                let normal = |e: &[f64; 3]| [e[0], e[2]];
                let (a, b) = (normal(&ex.contact_impulse), normal(&ez.contact_impulse));
                // Equal but for the other face's friction along this normal, zero at a converged
                // slip to the joint solve's tolerance (1e-12 of the scale; 1e-9 asserted).
                let scale = a.iter().chain(&b).fold(0.0f64, |m, c| m.max(c.abs()));
                for c in 0..2 {
                    assert!(
                        (a[c] - b[c]).abs() <= 1e-9 * scale,
                        "normal impulse per area {a:?} vs {b:?}"
                    );
                }
                let (w_x, w_z) = (ex.area, ez.area);
                let mu_bar = (w_x * mu_x + w_z * mu_z) / (w_x + w_z);
                let felt = -p[1] / (p[0] + p[2]);
                worst = worst.max((felt / mu_bar - 1.0).abs());
                checked += 1;
            }
        }
    }
    eprintln!("{checked} sliding node-steps behind both faces; worst |μ_felt/μ̄ − 1| = {worst:e}");
    assert!(
        checked > 10,
        "{checked} sliding node-steps behind both faces"
    );
    assert!(worst <= 1e-6, "the friction felt is {worst:e} off μ̄");
}
