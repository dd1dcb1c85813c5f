//! What the closest-point cache of triangulated moulds saves (docs: performance log): a
//! 100 × 100 mm, 1 mm thick rubber sheet (100 × 100 × 1 hex8) on a mould
//! surface of 2 × 71² = 10 082 triangles (sine ribs every 10 mm, `examples/shared/sine_ribs.rs`,
//! written to a temporary STL), its 10 201 bottom nodes a contact face set on it (μ = 0.3),
//! the sheet starting at rest on the ribs' crests under gravity: every step projects each of
//! its bottom nodes onto the mould. With AMPLITUDE = 0 the mould is a triangulated plane and
//! the whole face lies on it.
//!
//! ```sh
//! cargo run --release -p decohesion-physics --example mould_cache -- [STEPS] [REPEATS] [AMPLITUDE]
//! # defaults 300 5 10: AMPLITUDE in tenths of a millimetre (the ribs' height)
//! ```
//!
//! Prints, per contact-node-step: the closest-point query alone, cold (the full BVH query),
//! bounded (the BVH asked only for points closer than the node's last triangle,
//! `project_cached`) and warm (from the node's list of nearby triangles, `project_near`, what
//! the step uses), timed on the nodes' positions at the last step with the caches of the step
//! before; what the lists did over the last warm run (triangle projections, rebuilds and ties
//! per query, list lengths); the whole step with the lists on and off (medians of REPEATS runs
//! of STEPS steps); and the queries' share of the step. Wall-clock: on a shared machine
//! say so ("loaded") next to the figures.

#[allow(dead_code)]
#[path = "../../examples/shared/sine_ribs.rs"]
mod sine_ribs;

use decohesion_physics::mould::surface::{NearLists, NO_FEATURE};
use decohesion_physics::mould::{Shape, SurfaceMesh};
use decohesion_physics::scene::load_scene;
use decohesion_physics::solver::Simulation;
use decohesion_physics::timing::median;
use std::time::Instant;

/// A simulation of the scene in `dir`, cold or warm.
fn simulation(dir: &std::path::Path, cold: bool) -> Simulation {
    let scene = load_scene(&dir.join("mould_cache.toml"), &[]).expect("the bench scene");
    let mut sim = Simulation::new(scene.model).expect("the bench simulation");
    sim.set_mould_queries_cold(cold);
    sim
}

/// Seconds per step over `steps` steps, and the share of stages 1–2 (positions, the moulds'
/// poses and every node's closest point) in the step by the solver's stage clock.
fn time_steps(sim: &mut Simulation, steps: usize) -> (f64, f64) {
    let t0 = Instant::now();
    for _ in 0..steps {
        sim.step().expect("a step");
    }
    let st = &sim.stats;
    let share = st.stage_times.positions / st.steps_wall.as_secs_f64();
    (t0.elapsed().as_secs_f64() / steps as f64, share)
}

/// The contact nodes' positions now.
fn positions(sim: &Simulation) -> Vec<[f64; 3]> {
    (sim.state.contact_nodes.iter())
        .map(|c| {
            let i = c.node as usize;
            std::array::from_fn(|k| sim.model.mesh.nodes[i][k] + sim.state.u.get(i)[k])
        })
        .collect()
}

/// Nanoseconds per query over `x`: cold, bounded from the last triangle `primed`, and from
/// the lists `near` (with `primed`).
fn time_queries(
    s: &SurfaceMesh,
    x: &[[f64; 3]],
    primed: &[u32],
    near: &NearLists,
    repeats: usize,
) -> (f64, f64, f64) {
    let (mut cold, mut warm, mut listed) = (Vec::new(), Vec::new(), Vec::new());
    let mut sink = 0.0;
    for _ in 0..repeats {
        let (mut f, mut lists) = (primed.to_vec(), near.clone());
        let t0 = Instant::now();
        for (j, (&y, f)) in x.iter().zip(&mut f).enumerate() {
            sink += s.project_near(y, f, &mut lists, j).point[2];
        }
        listed.push(t0.elapsed().as_secs_f64());
        let t0 = Instant::now();
        for &y in x {
            sink += s.project(y).point[2];
        }
        cold.push(t0.elapsed().as_secs_f64());
        let mut f = primed.to_vec();
        let t0 = Instant::now();
        for (&y, f) in x.iter().zip(&mut f) {
            sink += s.project_cached(y, f).point[2];
        }
        warm.push(t0.elapsed().as_secs_f64());
    }
    assert!(sink.is_finite());
    let per = 1e9 / x.len() as f64;
    (
        median(&mut cold) * per,
        median(&mut warm) * per,
        median(&mut listed) * per,
    )
}

fn main() {
    let mut args = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("a count"));
    let steps: usize = args.next().unwrap_or(300);
    let repeats: usize = args.next().unwrap_or(5);
    let amplitude: f64 = args.next().map_or(1e-3, |a: usize| a as f64 * 1e-4);
    let dir = std::env::temp_dir().join(format!("mould_cache_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (v, t) = sine_ribs::sine_ribs(71, -0.005, 0.11, amplitude, 0.01);
    std::fs::write(dir.join("ribs.stl"), sine_ribs::to_stl(&v, &t)).unwrap();
    let scene = sine_ribs::Sheet {
        name: "mould_cache",
        file: "ribs.stl",
        velocity: None,
        gravity: true,
        origin: [0.0, 0.0, amplitude],
        size: [0.1, 0.1, 0.001],
        cells: [100, 100, 1],
    }
    .toml();
    std::fs::write(dir.join("mould_cache.toml"), scene).unwrap();

    let (mut warm_step, mut cold_step) = (Vec::new(), Vec::new());
    let (mut warm_share, mut cold_share) = (Vec::new(), Vec::new());
    let mut sim = simulation(&dir, false);
    for _ in 0..repeats {
        let mut cold = simulation(&dir, true);
        let (t, f) = time_steps(&mut cold, steps);
        cold_step.push(t);
        cold_share.push(f);
        sim = simulation(&dir, false);
        let (t, f) = time_steps(&mut sim, steps);
        warm_step.push(t);
        warm_share.push(f);
    }
    let Shape::Surface(s) = sim.model.moulds[0].shape.clone() else {
        panic!("the mould is a surface")
    };
    let nodes = sim.state.contact_nodes.len();
    let in_contact = (sim.state.contact_nodes.iter())
        .filter(|c| c.gap <= 0.0)
        .count();
    // The cache as the step leaves it before the last step: primed at the positions one step
    // earlier, then timed at the last positions.
    let before = positions(&sim);
    sim.step().unwrap();
    let now = positions(&sim);
    let mut primed = vec![NO_FEATURE; nodes];
    let mut near = NearLists::new(nodes);
    for (j, (y, f)) in before.iter().zip(&mut primed).enumerate() {
        s.project_near(*y, f, &mut near, j);
    }
    near.stats = Default::default();
    let (q_cold, q_bounded, q_warm) = time_queries(&s, &now, &primed, &near, repeats.max(5));
    let st = sim.mould_near_stats()[1];
    let per_query = |n: u64| n as f64 / st.queries.max(1) as f64;
    let (ws, cs) = (median(&mut warm_step), median(&mut cold_step));
    println!(
        "ribs {:.1} mm high: {} triangles, {nodes} contact nodes ({in_contact} touching after {steps} steps), {} hex8",
        amplitude * 1e3,
        s.mesh.num_triangles(),
        sim.model.mesh.elements.len()
    );
    println!(
        "query alone: cold {q_cold:.0} ns, bounded from the last triangle {q_bounded:.0} ns, from the lists {q_warm:.0} ns per contact-node-step"
    );
    println!(
        "lists over the last warm run ({} queries): {:.3} triangle projections, {:.4} rebuilds, {:.4} ties per query; {:.1} triangles per list, {:.1} candidates per rebuild",
        st.queries,
        per_query(st.projections),
        per_query(st.rebuilds),
        per_query(st.ties),
        st.listed as f64 / st.rebuilds.max(1) as f64,
        st.candidates as f64 / st.rebuilds.max(1) as f64
    );
    println!(
        "whole step: cold {:.2} ms, warm {:.2} ms ({:.0} and {:.0} ns per contact-node-step)",
        cs * 1e3,
        ws * 1e3,
        cs * 1e9 / nodes as f64,
        ws * 1e9 / nodes as f64
    );
    println!(
        "queries' share of the step: cold {:.0} %, warm {:.0} % (the queries alone × nodes / step)",
        100.0 * q_cold * nodes as f64 * 1e-9 / cs,
        100.0 * q_warm * nodes as f64 * 1e-9 / ws
    );
    println!(
        "stages 1–2 (positions, poses, closest points) by the stage clock: cold {:.0} %, warm {:.0} %",
        100.0 * median(&mut cold_share),
        100.0 * median(&mut warm_share)
    );
    std::fs::remove_dir_all(&dir).ok();
}
