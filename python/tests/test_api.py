"""Arrays (shapes, dtypes, copies), properties, check(), overrides, and the GIL released while
stepping."""

from __future__ import annotations

import threading

import numpy as np
import pytest

import decohesion
from conftest import scene


def test_arrays_have_their_documented_shapes_and_dtypes(pull_off):
    sim = decohesion.Simulation(pull_off)
    sim.step(200)  # the glue is loaded, some nodes damaged
    nodes, m = 8**3, 8 * 8  # 7×7×7 cells; the glued bottom face has 8×8 nodes
    expected = {
        "reference_coordinates": ((nodes, 3), np.float64),
        "displacement": ((nodes, 3), np.float64),
        "velocity": ((nodes, 3), np.float64),
        "mass": ((nodes,), np.float64),
        "elements": ((7**3, 8), np.int64),
        "interface_nodes": ((m,), np.int64),
        "alpha": ((m,), np.float64),
        "gap": ((m,), np.float64),
        "jump": ((m, 3), np.float64),
        "cohesive_traction": ((m, 3), np.float64),
        "interface_state": ((m,), np.int8),
        "interface_contact": ((m,), np.int8),
        "contact_nodes": ((0,), np.int64),
        "contact_gap": ((0,), np.float64),
        "contact_status": ((0,), np.int8),
        "reactions": ((1,), np.float64),
        "imposed_displacements": ((1,), np.float64),
    }
    for name, (shape, dtype) in expected.items():
        a = getattr(sim, name)
        assert isinstance(a, np.ndarray), name
        assert a.shape == shape and a.dtype == dtype, (name, a.shape, a.dtype)
        assert a.flags.writeable and a.flags.c_contiguous, name
    # Consistency between the arrays: the interface nodes lie on the glued face z = 0, the
    # masses add up to ρV (1 m³ of 1100 kg/m³), the states are the law's classes of α.
    X = sim.reference_coordinates
    assert np.all(X[sim.interface_nodes, 2] == 0.0)
    assert sim.mass.sum() == pytest.approx(1100.0, rel=1e-12)
    law = pull_off.check()["interfaces"][0]
    expected_state = np.where(sim.alpha <= law["alpha_e"], 0, np.where(sim.alpha >= law["u_r"], 2, 1))
    assert np.array_equal(sim.interface_state, expected_state)
    counts = sim.state_counts
    assert [counts[k] for k in ("elastic", "transition", "ruptured")] == [
        int(np.sum(sim.interface_state == s)) for s in (0, 1, 2)
    ]
    # The imposed displacement of the top: 1 m/s ramp, U = t (pull_off.toml).
    assert sim.prescribed == ["z+_z"]
    assert sim.imposed_displacements[0] == pytest.approx(sim.t, rel=1e-12)


def test_writing_into_a_returned_array_changes_nothing(pull_off):
    touched, clean = decohesion.Simulation(pull_off), decohesion.Simulation(pull_off)
    touched.step(50)
    clean.step(50)
    for name in ("displacement", "velocity", "alpha", "gap", "jump", "reference_coordinates",
                 "mass", "interface_nodes", "interface_state", "elements", "reactions"):
        a = getattr(touched, name)
        before = a.copy()
        a[...] = 7  # a copy: nothing of the solver is shared
        assert np.array_equal(getattr(touched, name), before), name
    touched.step(50)
    clean.step(50)
    assert np.array_equal(touched.displacement, clean.displacement)
    assert np.array_equal(touched.alpha, clean.alpha)
    assert touched.energies == clean.energies


def test_properties_and_energies(pull_off):
    sim = decohesion.Simulation(pull_off)
    assert sim.t == 0.0 and sim.step_count == 0 and not sim.finished
    check = pull_off.check()
    assert sim.h_crit == check["h_crit"] and sim.h == check["time_step"]
    assert sim.h == pytest.approx(0.5 * sim.h_crit, rel=1e-15)  # time_step_factor = 0.5
    sim.step()
    assert sim.step_count == 1 and sim.t > 0
    e = sim.energies
    assert set(e) >= {"kinetic", "strain", "interface_stored", "damage_dissipated",
                      "external_work", "residual", "relative_residual"}
    work = e["gravity_work"] + e["traction_work"] + e["reaction_work"] + e["plane_work"]
    assert e["external_work"] == pytest.approx(work, rel=1e-12, abs=1e-300)
    sim.step(0)
    assert sim.step_count == 1
    with pytest.raises(ValueError, match="n must be ≥ 0"):
        sim.step(-1)
    assert "pull_off" in repr(sim) and "pull_off" in repr(pull_off)
    assert sim.scene.name == "pull_off" and pull_off.end_time == 0.33


def rust_e(x: float, digits: int) -> str:
    """`x` as Rust's `{:.Ne}` writes it (`6.32159e-4`, not Python's `6.32159e-04`)."""
    mantissa, exponent = f"{x:.{digits}e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def test_check_is_the_command_lines(pull_off, cli):
    """The numbers of `decohesion check` (printed to 5–6 digits) are check()'s."""
    import subprocess

    c = pull_off.check()
    text = subprocess.run([str(cli), "check", str(scene("pull_off"))], capture_output=True,
                          text=True, check=True).stdout
    assert f"h_crit (Lanczos, §6)         {rust_e(c['h_crit'], 5)} s" in text
    assert f"{c['wave_speed']:.4f} m/s" in text
    assert f"expected steps               {c['expected_steps']} to" in text
    itf = c["interfaces"][0]
    assert f"G_c = {rust_e(itf['fracture_energy'], 5)} J/m²" in text
    assert f"peak traction              {rust_e(itf['peak_traction'], 5)} Pa" in text
    assert c["nodes"] == 512 and c["elements"] == 343 and c["warnings"] == []
    # G_c of the plateau–linear law from its knots, independently (model §2.7):
    # ½g₀α_e² + ∫_{α_e}^{u_r} g₀(u_r−δ)/(u_r−α_e)·δ dδ.
    g0, ae, ur = itf["g_n0"], itf["alpha_e"], itf["u_r"]
    gc = 0.5 * g0 * ae**2 + g0 / (ur - ae) * (ur * (ur**2 - ae**2) / 2 - (ur**3 - ae**3) / 3)
    assert itf["fracture_energy"] == pytest.approx(gc, rel=1e-12)


def test_from_toml_and_override_values(tmp_path):
    text = scene("pull_off").read_text()
    s = decohesion.Scene.from_toml(text, file="my_pull.toml", overrides={
        "mesh.cells": (3, 3, np.int64(3)),  # a tuple, a numpy integer
        "interface.law.u_r": np.float64(0.005),
        "material.model": "neo_hookean",
        "name": "custom",
    })
    assert s.name == "custom" and s.file == "my_pull.toml"
    c = s.check()
    assert c["elements"] == 27 and c["material"]["model"] == "neo_hookean"
    assert c["interfaces"][0]["u_r"] == 0.005
    assert "u_r = 0.005" in s.resolved
    with pytest.raises(TypeError, match="overrides must be a dict"):
        decohesion.Scene.from_toml(text, overrides=["mesh.cells=[3,3,3]"])
    with pytest.raises(TypeError, match="override `end_time`: object is not a scene value"):
        decohesion.Scene.from_toml(text, overrides={"end_time": object()})


def test_the_gil_is_released_while_stepping(pull_off):
    """While one thread steps, another runs Python: with the GIL held for the whole call, the
    main thread could not count at all until the stepping thread had finished. 4000 steps of
    the 7³ cube are about 1.4·10⁶ element-steps, far longer than 1000 turns of the loop."""
    sim = decohesion.Simulation(
        decohesion.Scene.load(scene("pull_off"), overrides={"end_time": 100.0})
    )
    worker = threading.Thread(target=sim.step, args=(4000,))
    count = 0
    worker.start()
    while worker.is_alive():
        count += 1
    worker.join()
    assert sim.step_count == 4000
    assert count > 1000, f"main thread counted {count} while the other stepped"


def test_progress_without_tqdm_prints_a_plain_line(pull_off, capsys, monkeypatch):
    import builtins

    real_import = builtins.__import__

    def no_tqdm(name, *args, **kwargs):
        if name.startswith("tqdm"):
            raise ImportError(name)
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_tqdm)
    sim = decohesion.Simulation(pull_off)
    sim.run(until=0.05, progress=True)
    err = capsys.readouterr().err
    assert "pull_off: t = 0 s → 0.05 s" in err
    assert sim.t >= 0.05 and sim.t - sim.h < 0.05  # the first step at or past `until`


def test_progress_with_tqdm_is_a_bar(pull_off, capsys):
    pytest.importorskip("tqdm")  # installed by .ci/run
    sim = decohesion.Simulation(pull_off)
    sim.run(until=0.05, progress=True)
    err = capsys.readouterr().err
    assert "pull_off (~159 steps): 100%|" in err
    assert f"step {sim.step_count}, ruptured 0/64]" in err
