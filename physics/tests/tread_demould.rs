//! Issue 13's flagship, `scenes/tread_demould.toml`: the grooved tread block glued on every
//! moulded face to the ribbed mould that formed it, the mould drawn away upwards. Every glued
//! node tears, no node is left inside the mould beyond one step's travel of the mould, the rib
//! walls rub (friction dissipated on the mould, reported for it), the ledger closes, and the
//! glue dissipates its fracture energy over the glued area once.

mod common;
use common::*;
use decohesion_physics::scene::{load_scene, parse_scene};
use decohesion_physics::solver::Simulation;

/// Glued areas [m²] from the mesh's dimensions (examples/shared/tread_geometry.rs): rib tops
/// (16 + 12 + 16) × 30 mm, groove floors 2 × 4 × 30 mm and walls 4 × √(2² + 8²) × 30 mm.
fn glued_area() -> f64 {
    let wall = (2.0f64 * 2.0 + 8.0 * 8.0).sqrt();
    ((16.0 + 12.0 + 16.0) * 30.0 + 2.0 * 30.0 * (4.0 + 2.0 * wall)) * 1e-6
}

#[test]
fn tread_demoulds() {
    let scene = load_scene(&scene_file("tread_demould.toml"), &[]).unwrap();
    let mut sim = Simulation::new(scene.model).unwrap();
    assert!(sim.start_offsets.is_empty(), "{:?}", sim.start_offsets);
    let ribbed = sim.model.planes.iter().position(|p| p.name == "ribbed");
    let k = ribbed.expect("the scene's mould is `ribbed`");
    // The mould's largest speed (1 m/s after its ramp), from its velocity history.
    let v_max = (sim.model.planes[k].velocity.as_ref().unwrap().points.iter())
        .map(|p| p.1.iter().map(|c| c * c).sum::<f64>().sqrt())
        .fold(0.0, f64::max);
    assert_eq!(v_max, 1.0);
    // Contact is a velocity-level condition (Signorini on V_{n+3/2}, PHYSICS.md §4 stage 7)
    // without position correction: x_{n+1} = x_n + h V_{n+½} moves a node with the velocity of
    // the step before, which no constraint has seen while the node was still off the mould. So
    // a node can end a step inside by one step's travel towards the mould,
    // h |V_{n+½} − v_mould| ≤ h (|V_{n+½}| + |v_mould|). The block is stretched by the glue and
    // springs back when it tears: its vibration brings nodes back against the rising mould, so
    // the node's own speed counts, not only the mould's 1 m/s (measured: 3.0 |v_mould| h).
    // Once inside, its approach velocity is removed and the depth should not grow. Measured:
    // 1.6 × h (|V_{n+½}| + |v_mould|), 12 µm, at a groove-wall node 2 mm below the rib top
    // (X = (16.5, 14, 18) mm) at 1.95 ms, just after the last glue let go: the excess over one
    // step is not explained yet (README, Not yet), so the bound, 2 steps' travel, is that
    // measurement with a margin, not a derived value: it catches a node driven through the
    // mould (a missing or wrong-signed constraint gives depths of many steps).
    let mut v_prev: Vec<[f64; 3]> = sim.v.clone();
    let (mut worst, mut at) = (0.0f64, (0.0, [0.0; 3]));
    sim.run(|s| {
        for itf in &s.interface_nodes {
            let i = itf.node as usize;
            let speed = v_prev[i].iter().map(|c| c * c).sum::<f64>().sqrt();
            let r = -itf.gap / (s.h * (speed + v_max));
            if r > worst {
                (worst, at) = (r, (s.time, s.model.mesh.nodes[i]));
            }
        }
        v_prev.copy_from_slice(&s.v);
        true
    })
    .unwrap();
    eprintln!("deepest: {worst} × h (|V| + |v_mould|) (t, X: {at:?})");
    assert!(
        worst <= 2.0,
        "a node {worst} × h (|V| + |v_mould|) inside the mould (t, X: {at:?})"
    );
    let n = sim.interface_nodes.len();
    assert_eq!(n, 816, "glued entries on the top and groove faces");
    assert_eq!(sim.state_counts().ruptured, n, "every glued node torn");
    let t = sim.stats.time_full_rupture.expect("every glued node tears");
    assert!(t < 0.5 * sim.model.end_time, "full rupture at {t} s");
    // The ribs have cleared the grooves: the mould has risen by more than the groove depth
    // (8 mm) plus the block's stretch before the glue let go, and every node is off it.
    let rise = sim.model.planes[k].displacement(sim.time)[2];
    assert!(rise > 0.012, "the mould rose {rise} m");
    for itf in &sim.interface_nodes {
        assert!(itf.gap > 0.0, "node {} still on the mould", itf.node);
    }
    // Friction on the rib walls: dissipated on the mould and reported for it.
    let frictions = sim.mould_frictions();
    assert_eq!(frictions.len(), 1);
    assert_eq!(frictions[0].0, "ribbed");
    let e = sim.energies();
    assert!(
        frictions[0].1 > 0.0,
        "friction on the mould {}",
        frictions[0].1
    );
    assert_eq!(frictions[0].1, e.friction_dissipated);
    // PHYSICS.md §5: the ledger closes to O(h²), ~1e-5..1e-4 of the largest energy in the
    // scene tests; 1e-3 as they use (pull_off, tread, extreme) would still catch a missing
    // term (the friction here is 1 % of the energies, the normal contact 0.3 %).
    assert!(
        sim.ledger.max_relative_residual < 1e-3,
        "residual {}",
        sim.ledger.max_relative_residual
    );
    // Every glued node tears once: the damage dissipation is G_c × the glued area up to the
    // discrete rupture steps (O(h)), within the pull-off test's bounds [0.99, 1.08].
    let gc_area = sim.model.interfaces[0].law.fracture_energy() * glued_area();
    assert_eq!(
        sim.model.interfaces[1].law.fracture_energy(),
        sim.model.interfaces[0].law.fracture_energy()
    );
    let d = e.damage_dissipated;
    assert!(
        d >= 0.99 * gc_area && d <= 1.08 * gc_area,
        "damage dissipation {d} J vs G_c·A {gc_area} J"
    );
}

/// With a second mould (a far plane nothing touches), the friction is split by mould: all of
/// it on the ribbed mould (equal to the total to round-off: the same terms summed in another
/// order, the impulse read back per unit area), none on the plane.
#[test]
fn friction_is_split_by_mould() {
    let file = scene_file("tread_demould.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    let text = format!(
        "{text}\n[[mould]]\nname = \"far\"\nshape = \"half_space\"\n\
         point = [0.0, 0.0, -1.0]\nnormal = [0.0, 0.0, 1.0]\n"
    );
    // The tearing (full rupture at ≈ 1.9 ms) is where the walls rub.
    let over = ["end_time=0.0025".to_string()];
    let scene = parse_scene(&text, &file.display().to_string(), &over).unwrap();
    let mut sim = Simulation::new(scene.model).unwrap();
    sim.run(|_| true).unwrap();
    let f = sim.mould_frictions();
    let total = sim.energies().friction_dissipated;
    assert_eq!(
        f.iter().map(|p| p.0.as_str()).collect::<Vec<_>>(),
        ["ribbed", "far"]
    );
    assert!(total > 0.0);
    assert_eq!(f[1].1, 0.0);
    assert!(
        ((f[0].1 - total) / total).abs() < 1e-9,
        "ribbed {} J, total {total} J",
        f[0].1
    );
}
