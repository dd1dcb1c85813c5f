//! The ribbed mould of scenes/tread_demould.toml (examples/ribbed_mould.rs): the committed STL
//! is what the generator writes, and the tread block it formed (examples/tread_block.rs, the
//! same shared dimensions) lies on it: every moulded node (rib tops, groove walls and floors) at
//! gap 0 to round-off at t = 0, every other node outside the mould.

#[allow(dead_code)]
#[path = "../examples/ribbed_mould.rs"]
mod generator;

use decohesion::scene::load_scene;
use std::collections::BTreeSet;

#[test]
fn ribbed_mould_file_is_reproducible() {
    let committed = std::fs::read_to_string(generator::PATH).unwrap();
    assert!(
        committed == generator::text(),
        "{} differs from what `cargo run --example ribbed_mould` writes: regenerate it",
        generator::PATH
    );
}

#[test]
fn moulded_nodes_lie_on_the_mould() {
    let scene = load_scene("scenes/tread_demould.toml".as_ref(), &[]).unwrap();
    let m = &scene.model;
    let k = m.moulds.iter().position(|p| p.name == "ribbed").unwrap();
    let mould = &m.moulds[k];
    let mut moulded = BTreeSet::new();
    for set in ["top", "groove"] {
        for q in &m.mesh.face_sets[set] {
            moulded.extend(q.iter().copied());
        }
    }
    // 16 rows across y of 47 nodes along the moulded profile: the 4 rib-top edges are in both
    // face sets, so the scene's two interfaces hold 752 + 4 × 16 = 816 glued entries.
    assert_eq!(moulded.len(), 47 * 16);
    assert!(m.interfaces.iter().all(|i| i.plane == k));
    // Round-off: a node on a groove wall is x + s (x_top − x) in millimetres, then scaled by
    // 1e-3; the projection subtracts coordinates of ~0.06 m. Each step is exact to ½ ulp of
    // 0.06 m (3.5e-18 m); a few tens of them stay below 1e-16 m, 1e-12 of the block's size.
    let mut worst: f64 = 0.0;
    for (i, x) in m.mesh.nodes.iter().enumerate() {
        let g = mould.project0(*x).gap(*x);
        if moulded.contains(&(i as u32)) {
            worst = worst.max(g.abs());
        } else {
            // The sides and the bottom are outside the mould, at least one 2 mm cell below the
            // rib tops or beside a groove wall (the 1.5 mm-wide top of the thinnest cell, times
            // cos 14° of the wall's draft, is the least).
            assert!(g > 1e-3, "node {i} at {x:?}: gap {g} m");
        }
    }
    assert!(worst <= 1e-16, "largest |gap| of a moulded node {worst} m");
}
