"""Simulation.save and restore: a restored simulation steps on bit for bit (model §4.13), and a
file that is not a checkpoint of this scene is refused, leaving the simulation as it was."""

from __future__ import annotations

import numpy as np
import pytest

import decohesion
from conftest import scene


def _small(**values):
    """The pull-off scene on a 3×3×2 mesh, with `values` as overrides."""
    return decohesion.Scene.load(scene("pull_off"), {"mesh.cells": [3, 3, 2], **values})


def _fields(sim):
    return [sim.displacement, sim.velocity, sim.alpha, sim.jump, sim.reactions]


def test_a_restored_simulation_steps_on_bit_for_bit(tmp_path):
    scene = _small()
    whole = decohesion.Simulation(scene)
    whole.step(40)
    path = tmp_path / "state.ckpt"
    whole.save(path)
    whole.step(40)
    resumed = decohesion.Simulation(scene)
    resumed.restore(str(path))
    assert resumed.step_count == 40
    assert len(resumed.history["step [-]"]) == 1
    resumed.step(40)
    assert resumed.t == whole.t
    for a, b in zip(_fields(whole), _fields(resumed)):
        assert np.array_equal(a, b)
    assert resumed.energies == whole.energies


def test_bad_checkpoints_are_refused(tmp_path):
    sim = decohesion.Simulation(_small())
    sim.step(5)
    good = tmp_path / "good.ckpt"
    sim.save(good)
    before = sim.displacement
    not_one = tmp_path / "scene.toml"
    not_one.write_text("[scene]\n")
    with pytest.raises(ValueError, match="not a decohesion checkpoint"):
        sim.restore(not_one)
    cut = tmp_path / "cut.ckpt"
    cut.write_bytes(good.read_bytes()[:-7])
    with pytest.raises(ValueError, match="corrupt"):
        sim.restore(cut)
    with pytest.raises(FileNotFoundError, match="missing.ckpt"):
        sim.restore(tmp_path / "missing.ckpt")
    other = decohesion.Simulation(_small(**{"interface.law.u_r": 0.02}))
    with pytest.raises(ValueError, match="another model"):
        other.restore(good)
    assert np.array_equal(sim.displacement, before)
    with pytest.raises(OSError, match="no_such_folder"):
        sim.save(tmp_path / "no_such_folder" / "x.ckpt")
