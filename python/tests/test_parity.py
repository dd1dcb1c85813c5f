"""The Python API computes what the command line computes, bit for bit: the summary after
`run()` against `decohesion run --summary`, and stepping in pieces against one run."""

from __future__ import annotations

import numpy as np
import pytest

import decohesion
from conftest import cli_summary, physics, scene

# A glued pull (plateau–linear law), shear with friction under pressure, a mould of five moving
# planes (contact-only faces), and a run that stops on its stability diagnostic.
SCENES = ["pull_off", "shear", "demould", "extreme/stiff_glue_h105"]


@pytest.mark.parametrize("name", SCENES)
def test_summary_equals_the_command_lines(name, cli, tmp_path):
    path = scene(name)
    expected, code = cli_summary(cli, path, tmp_path)
    sim = decohesion.Simulation(decohesion.Scene.load(path))
    try:
        sim.run(progress=False)
    except decohesion.SolverError:
        assert code == 1 and expected["status"] == "failed"
    else:
        assert code == 0
    got = sim.summary()
    assert set(got) == set(expected)
    assert physics(got) == physics(expected)
    assert got["steps"] > 0


def test_overrides_equal_the_command_lines_set(cli, tmp_path):
    overrides = {"interface.law.u_r": 0.006, "mesh.cells": [5, 5, 5], "scheme.time_step_factor": 0.4}
    expected, code = cli_summary(
        cli, scene("pull_off"), tmp_path, ["interface.law.u_r=0.006", "mesh.cells=[5,5,5]",
                                           "scheme.time_step_factor=0.4"]
    )
    assert code == 0
    sim = decohesion.Simulation(decohesion.Scene.load(scene("pull_off"), overrides=overrides))
    sim.run(progress=False)
    assert physics(sim.summary()) == physics(expected)


def state(sim: decohesion.Simulation) -> dict:
    return {
        "U": sim.displacement,
        "V": sim.velocity,
        "alpha": sim.alpha,
        "gap": sim.gap,
        "jump": sim.jump,
        "state": sim.interface_state,
        "contact": sim.interface_contact,
        "reactions": sim.reactions,
    }


def test_six_times_step_100_equals_run_to_the_same_time(pull_off):
    # 600 steps: past the rupture (≈ 343 steps), where h starts to grow, and before the end
    # (825 steps with the variable step).
    pieces = decohesion.Simulation(pull_off)
    for _ in range(6):
        pieces.step(100)
    assert pieces.step_count == 600
    whole = decohesion.Simulation(pull_off)
    whole.run(until=pieces.t, progress=False)
    assert whole.step_count == 600
    assert whole.t == pieces.t and whole.h == pieces.h and whole.h_crit == pieces.h_crit
    a, b = state(pieces), state(whole)
    for k in a:
        assert np.array_equal(a[k], b[k]), k
    assert pieces.energies == whole.energies
    assert physics(pieces.summary()) == physics(whole.summary())
    assert pieces.summary()["status"] == "in_progress"


def test_run_to_the_end_after_steps_equals_one_run(pull_off):
    """run() resumes where step() left off: same end state as one run()."""
    resumed = decohesion.Simulation(pull_off)
    resumed.step(123)
    resumed.run(progress=False)
    once = decohesion.Simulation(pull_off)
    once.run(progress=False)
    assert resumed.summary()["status"] == "completed"
    assert physics(resumed.summary()) == physics(once.summary())
    assert np.array_equal(resumed.displacement, once.displacement)
