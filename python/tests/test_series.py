"""`Simulation.history`: the scalars of every step, the columns of `decohesion run
--series`, equal to the command line's CSV bit for bit."""

from __future__ import annotations

import subprocess

import numpy as np

import decohesion
from conftest import REPO, scene


def read_csv(path) -> dict[str, np.ndarray]:
    """The CSV as a dict of float64 columns (Python's float() reads the shortest round-trip
    decimal Rust writes back to the same float)."""
    lines = path.read_text().splitlines()
    names = lines[0].split(",")
    rows = [[float(v) for v in line.split(",")] for line in lines[1:]]
    assert all(len(r) == len(names) for r in rows)
    values = np.array(rows, dtype=np.float64)
    return {name: values[:, k] for k, name in enumerate(names)}


def test_pull_off_history_equals_the_command_line_series(cli, tmp_path):
    path = scene("pull_off")
    csv = tmp_path / "pull_off.csv"
    done = subprocess.run(
        [str(cli), "run", str(path), "--quiet", "--series", str(csv)],
        capture_output=True, text=True, cwd=REPO,
    )
    assert done.returncode == 0, done.stderr
    expected = read_csv(csv)

    sim = decohesion.Simulation(decohesion.Scene.load(path))
    sim.run(progress=False)
    got = sim.history
    assert list(got) == list(expected)
    for name, column in expected.items():
        # Bit for bit: the same float64 values (int64 columns hold whole numbers exactly).
        assert np.array_equal(got[name].astype(np.float64), column), name
        assert got[name].dtype == (np.int64 if name == "step [-]" or name.startswith("n_")
                                   else np.float64), name
    assert got["step [-]"][-1] == sim.step_count and got["t [s]"][-1] == sim.t
    for axis in "xyz":
        assert f"F_mould_mould_{axis} [N]" in got and f"M_mould_mould_{axis} [N m]" in got
    peak = sim.summary()["peak_reactions"][0]
    at = np.flatnonzero(got["t [s]"] == peak["time"])
    assert len(at) == 1 and got["F_z_plus_z [N]"][at[0]] == peak["force"]


def test_steps_and_runs_add_rows_once_per_step(pull_off):
    sim = decohesion.Simulation(pull_off)
    assert list(sim.history["step [-]"]) == [0]
    sim.step(5)
    sim.run(until=sim.t + 3 * sim.h, progress=False)
    steps = sim.history["step [-]"]
    assert list(steps) == list(range(sim.step_count + 1))
    frame = decohesion.history_frame(sim)
    assert len(frame["t [s]"]) == sim.step_count + 1


def test_run_series_writes_the_history_s_rows(pull_off, tmp_path):
    sim = decohesion.Simulation(pull_off)
    csv = tmp_path / "short.csv"
    sim.run(until=0.01, progress=False, series=csv)
    written = read_csv(csv)
    got = sim.history
    for name, column in written.items():
        assert np.array_equal(got[name].astype(np.float64), column), name
    assert sim.summary()["series"]["rows"] == len(written["t [s]"])
