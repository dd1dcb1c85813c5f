//! The moulds in the ParaView output (model §7): each mould a part of the `.pvd`
//! with its own files, a fixed one written once, a moving one at every frame, placed by the
//! step's pose. Read back with vtkio and quick-xml, readers independent of the writer.

use crate::common::cli::{decohesion_ok, scratch};
use crate::common::paraview::{read_pvd, read_pvd_parts, read_vtu};
use crate::common::turning;
use vtkio::model::CellType;

#[test]
fn each_mould_is_a_part_placed_by_its_pose() {
    let dir = scratch("vtk", "moulds");
    let scene = turning::scene(&dir);
    let vtk = dir.join("vtk");
    let mut args = vec!["run", scene.to_str().unwrap(), "--quiet"];
    for o in &turning::OVERRIDES {
        args.extend(["--set", o]);
    }
    args.extend(["--vtk", vtk.to_str().unwrap()]);
    decohesion_ok(&args);
    let pvd = vtk.join("indent.pvd");
    let entries = read_pvd_parts(&pvd);
    let frames = read_pvd(&pvd);
    assert!(frames.len() > 5, "{} frames", frames.len());
    // Parts: the body, then base, ball, paddle in the scene's order, one entry each per frame.
    for (part, name) in [(1, "base"), (2, "ball"), (3, "paddle")] {
        let mine: Vec<_> = entries.iter().filter(|e| e.part == part).collect();
        assert_eq!(mine.len(), frames.len(), "{name}");
        assert!(mine.iter().all(|e| e.name == name));
        let times: Vec<f64> = mine.iter().map(|e| e.time).collect();
        assert_eq!(times, frames.iter().map(|f| f.0).collect::<Vec<_>>());
        let mut files: Vec<&str> = mine.iter().map(|e| e.file.as_str()).collect();
        files.dedup();
        // The fixed base: one file; the moving ball and paddle: one per frame.
        let want = if name == "base" { 1 } else { frames.len() };
        assert_eq!(files.len(), want, "{name}: {files:?}");
    }
    // The base plane z = 0 drawn as a square covering the pad's footprint [0, 0.04]².
    let base = read_vtu(&vtk.join(&entries.iter().find(|e| e.part == 1).unwrap().file));
    assert!(base.types.iter().all(|t| *t == CellType::Triangle));
    let (xs, ys): (Vec<f64>, Vec<f64>) = base.points.chunks(3).map(|p| (p[0], p[1])).unzip();
    assert!(base.points.chunks(3).all(|p| p[2] == 0.0));
    let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    let max = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    for v in [&xs, &ys] {
        assert!(min(v) < 0.0 && max(v) > 0.04, "{v:?}");
    }
    // The paddle at t = 0 and at the last frame: x = R(t)(x₀ − c₀) + c₀ + v t. The step
    // composes R(t) from exact per-step rotations: round-off of a few ulps per step.
    let paddle: Vec<_> = entries.iter().filter(|e| e.part == 3).collect();
    let first = read_vtu(&vtk.join(&paddle[0].file));
    assert_eq!(paddle[0].time, 0.0);
    assert_eq!(first.types.len(), 12, "a box: 12 triangles");
    let last = paddle.last().unwrap();
    let grid = read_vtu(&vtk.join(&last.file));
    assert!(last.time > 0.04, "t = {}", last.time);
    let mut moved = 0.0f64;
    for (x0, x) in first.points.chunks(3).zip(grid.points.chunks(3)) {
        let want = turning::place(last.time, [x0[0], x0[1], x0[2]]);
        for i in 0..3 {
            assert!((x[i] - want[i]).abs() < 1e-12, "{x:?} vs {want:?}");
        }
        moved = moved.max((x[0] - x0[0]).abs());
    }
    assert!(moved > 1e-3, "the paddle moved {moved} m");
    // Its normals turned with it: n = R(t) n₀.
    let n0 = &first.point["normal"];
    let r = turning::rotation(turning::OMEGA.map(|w| w * last.time));
    for (a, b) in n0.chunks(3).zip(grid.point["normal"].chunks(3)) {
        for i in 0..3 {
            let want: f64 = (0..3).map(|j| r[i][j] * a[j]).sum();
            assert!((b[i] - want).abs() < 1e-12);
        }
    }
}
