"""Ctrl-C (KeyboardInterrupt) stops stepping after the current step and leaves complete
outputs: a Rerun recording that `rerun rrd verify` accepts, a ParaView index of every frame."""

from __future__ import annotations

import _thread
import signal
import subprocess
import threading
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import decohesion
from conftest import scene


def long_pull_off() -> decohesion.Scene:
    """The pull-off made to last ~300 000 steps (about a minute): only an interrupt ends it."""
    return decohesion.Scene.load(scene("pull_off"), overrides={"end_time": 100.0})


@pytest.fixture(autouse=True)
def sigint_handled():
    """Python's own SIGINT handler for the test: a shell starts background jobs with SIGINT
    ignored, and then `_thread.interrupt_main` does nothing (Python docs), so a CI run launched
    with `&` would never see the Ctrl-C these tests simulate."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def interrupt_after(seconds: float) -> threading.Timer:
    """Raises KeyboardInterrupt in the main thread after `seconds`, as Ctrl-C does."""
    timer = threading.Timer(seconds, _thread.interrupt_main)
    timer.start()
    return timer


def test_ctrl_c_during_run_finishes_the_recording_and_the_paraview_index(tmp_path, rerun):
    sim = decohesion.Simulation(long_pull_off())
    rrd, vtk = tmp_path / "interrupted.rrd", tmp_path / "vtk"
    timer = interrupt_after(1.0)
    with pytest.raises(KeyboardInterrupt):
        sim.run(save=rrd, vtk=vtk, every=50, progress=False)
    timer.join()
    steps = sim.step_count
    assert 0 < steps and sim.t < sim.end_time
    summary = sim.summary()
    assert summary["status"] == "cancelled"
    frames = summary["recording"]["frames"]
    # Every 50th step from 0, and the interrupted step itself when it is not one of them.
    assert frames == steps // 50 + 1 + (steps % 50 != 0)
    verify = subprocess.run([rerun, "rrd", "verify", str(rrd)], capture_output=True, text=True)
    assert verify.returncode == 0, verify.stdout + verify.stderr
    # The ParaView index is complete: one dataset per frame, the last at the interrupted time.
    # (the body is part 0; each mould is a series of its own, part 1 + its index)
    datasets = ET.parse(vtk / "pull_off.pvd").getroot().findall("./Collection/DataSet[@part='0']")
    assert len(datasets) == frames == summary["paraview"]["frames"]
    assert float(datasets[-1].get("timestep")) == pytest.approx(sim.t, rel=1e-12)
    # The state is consistent: the simulation goes on from where it stopped.
    sim.step(10)
    assert sim.step_count == steps + 10
    assert sim.summary()["status"] == "in_progress"


def test_ctrl_c_during_step_stops_after_a_whole_step():
    sim = decohesion.Simulation(long_pull_off())
    timer = interrupt_after(0.5)
    with pytest.raises(KeyboardInterrupt):
        sim.step(10**7)
    timer.join()
    stopped = sim.step_count
    assert 0 < stopped < 10**7
    assert sim.summary()["status"] == "cancelled"
    # Bit for bit the state of an uninterrupted simulation after as many steps.
    again = decohesion.Simulation(long_pull_off())
    again.step(stopped)
    assert again.t == sim.t
    assert np.array_equal(again.displacement, sim.displacement)
    assert np.array_equal(again.velocity, sim.velocity)
    assert again.energies == sim.energies
