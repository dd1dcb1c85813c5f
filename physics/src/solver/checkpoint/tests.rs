use super::*;

/// The shipped scene `name` with the overrides `set`.
fn model(name: &str, set: &[&str]) -> std::sync::Arc<Model> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../scenes/{name}"));
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    // Loaded from its path: a scene's mesh file is found beside it.
    crate::scene::load_scene(&path, &set).unwrap().model
}

/// The bits of the fields a step writes: U, V, F_int, every interface node's α, α_next, jump
/// and impulse, every contact node's impulse, the ledger, t, n, h.
fn bits(sim: &Simulation) -> Vec<u64> {
    let mut out: Vec<u64> = [sim.state.time, sim.state.h, sim.state.h_crit]
        .iter()
        .map(|x| x.to_bits())
        .collect();
    out.push(sim.state.step_count);
    for p in [&sim.state.u, &sim.state.v, &sim.state.f_int] {
        out.extend((0..p.len()).flat_map(|i| p.get(i)).map(f64::to_bits));
    }
    for n in &sim.state.interface_nodes {
        let xs = [n.alpha, n.alpha_next, n.alpha_static, n.gap, n.stiffness];
        out.extend(
            xs.iter()
                .chain(&n.jump)
                .chain(&n.contact_impulse)
                .map(|x| x.to_bits()),
        );
    }
    for n in &sim.state.contact_nodes {
        out.extend(n.contact_impulse.iter().map(|x| x.to_bits()));
    }
    let l = &sim.state.ledger;
    let xs = [l.kinetic, l.strain, l.interface_stored, l.damage_dissipated];
    out.extend(xs.iter().map(|x| x.to_bits()));
    out.push(l.relative_residual().to_bits());
    out
}

/// A run restored from a checkpoint at step k goes on bit for bit as the run that did not
/// stop (model §4.13), on scenes that carry the state across steps in every way: glue that
/// damages and a variable step (pull-off), friction and contact (sliding), a turning mould
/// (roller peel), delayed damage and RCCM (rate effect, rccm shear), bulk viscosity, and
/// tetrahedra (the Gmsh rubber strip) with bulk viscosity and mass scaling.
#[test]
fn a_restored_run_goes_on_bit_for_bit() {
    let cases: [(&str, &[&str]); 6] = [
        ("pull_off.toml", &["mesh.cells=[3,3,2]"]),
        ("sliding.toml", &[]),
        ("roller_peel.toml", &[]),
        ("rccm_shear.toml", &[]),
        (
            "pull_off.toml",
            &["mesh.cells=[3,3,2]", "bulk_viscosity.linear=0.06"],
        ),
        (
            "rubber_peel.toml",
            &[
                "bulk_viscosity.linear=0.06",
                "mass_scaling.target_step=5e-7",
            ],
        ),
    ];
    for (name, set) in cases {
        let m = model(name, set);
        let mut whole = Simulation::new(m.clone()).unwrap();
        let total = 60;
        for _ in 0..total / 2 {
            whole.step().unwrap();
        }
        let bytes = whole.checkpoint();
        for _ in total / 2..total {
            whole.step().unwrap();
        }
        let mut resumed = Simulation::new(m).unwrap();
        let header = resumed.restore(&bytes, "test").unwrap();
        assert_eq!(header.step, total as u64 / 2, "{name}");
        for _ in total / 2..total {
            resumed.step().unwrap();
        }
        assert_eq!(bits(&whole), bits(&resumed), "{name} {set:?}");
    }
}

/// A checkpoint that is cut short, has a flipped bit, has no magic line, or was written by
/// another model is refused with what is wrong, and leaves the simulation as it was.
#[test]
fn bad_checkpoints_are_refused_and_leave_the_simulation_alone() {
    let m = model("pull_off.toml", &["mesh.cells=[2,2,2]"]);
    let mut sim = Simulation::new(m.clone()).unwrap();
    for _ in 0..5 {
        sim.step().unwrap();
    }
    let good = sim.checkpoint();
    let mut fresh = Simulation::new(m).unwrap();
    let before = bits(&fresh);
    let mut flipped = good.clone();
    let k = flipped.len() - 10;
    flipped[k] ^= 0x10;
    let mut header_flipped = good.clone();
    header_flipped[MAGIC.len() + 9] ^= 1;
    let cases: [(Vec<u8>, &str); 5] = [
        (good[..good.len() - 3].to_vec(), "truncated"),
        (flipped, "state's checksum differs"),
        (header_flipped, "header's checksum differs"),
        (
            b"[scene]\nname = 'x'\n".to_vec(),
            "is not a decohesion checkpoint",
        ),
        (good[..MAGIC.len() + 4].to_vec(), "truncated"),
    ];
    for (bytes, expect) in cases {
        let err = fresh.restore(&bytes, "ck.bin").unwrap_err().to_string();
        assert!(
            err.contains("ck.bin") && err.contains(expect),
            "{expect}: {err}"
        );
        assert_eq!(bits(&fresh), before);
    }
    let other = model(
        "pull_off.toml",
        &["mesh.cells=[2,2,2]", "interface.law.u_r=0.02"],
    );
    let mut other = Simulation::new(other).unwrap();
    let err = other.restore(&good, "ck.bin").unwrap_err().to_string();
    assert!(
        err.contains("another model") && err.contains("--set"),
        "{err}"
    );
    fresh.restore(&good, "ck.bin").unwrap();
    assert_eq!(bits(&fresh), bits(&sim));
}

/// A file written atomically reads back whole, replaces the old one, and leaves no temporary
/// file beside it; a folder that does not exist is an error naming the path.
#[test]
fn files_are_written_atomically() {
    let dir = std::env::temp_dir().join(format!("decohesion-ckpt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("state.ckpt");
    write_atomically(&path, b"first").unwrap();
    write_atomically(&path, b"second, longer").unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), b"second, longer");
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("state.ckpt")]);
    let missing = dir.join("no/such/state.ckpt");
    let err = write_atomically(&missing, b"x").unwrap_err().to_string();
    assert!(err.contains("no/such"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}
