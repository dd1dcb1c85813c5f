"""`decohesion.fit`: the command line's `fit` from Python — a curve made by the model is fitted
back, and bad arguments are refused with what is admissible."""

from __future__ import annotations

import numpy as np
import pytest

import decohesion
from conftest import scene


def pull_off_curve(tmp_path, u_r: float):
    """The pull-off's reaction against the imposed displacement at 12 points from 4 to 150 mm
    (its `history`), written as CSV in mm and N."""
    sim = decohesion.Simulation(
        decohesion.Scene.load(scene("pull_off"), overrides={"interface.law.u_r": u_r})
    )
    sim.run(progress=False)
    h = sim.history
    u = np.linspace(0.004, 0.15, 12)
    f = np.interp(u, h["u_z_plus_z [m]"], h["F_z_plus_z [N]"])
    path = tmp_path / "curve.csv"
    lines = ["u [mm], F [N]"] + [f"{float(a) * 1e3!r}, {float(b)!r}" for a, b in zip(u, f)]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_fit_recovers_u_r_and_writes_the_outputs(tmp_path):
    # The curve of u_r = 4 mm, from a start of 6 mm (50 % off). Without noise, the only
    # difference between data and model is np.interp against the fit's own interpolation of the
    # same rows (both linear in the same segments): the fitted u_r is within the simplex's
    # resolution, 1 %.
    data = pull_off_curve(tmp_path, 4e-3)
    out = tmp_path / "out"
    r = decohesion.fit(
        scene("pull_off"), data, "u_z_plus_z", "F_z_plus_z [N]",
        free={"interface.law.u_r": (2.5e-3, 1e-2)},
        overrides={"interface.law.u_r": 6e-3},
        max_evals=60, threads=1, out=out,
    )
    (p,) = r["parameters"]
    assert p["start"] == 6e-3 and p["start_from"] == "scene"
    assert abs(p["value"] / 4e-3 - 1) < 0.01, p
    assert r["fitted"]["rms_relative"] < 1e-3
    assert r["initial"]["rms_relative"] > 0.05
    assert r["y"]["unit"] == "N" and r["x"]["unit"] == "mm"
    assert len(r["curves"]["fitted"]) == 12
    for name in ["fit.json", "fit.csv", "evaluations.csv", "fit.svg", "pull_off_fitted.toml"]:
        assert (out / name).stat().st_size > 0, name
    fitted = decohesion.Scene.load(out / "pull_off_fitted.toml")
    assert f"u_r = {p['value']!r}" in fitted.text


@pytest.mark.parametrize(
    "kwargs, error, text",
    [
        ({"free": [("interface.law.u_r", 1e-3, 1e-2)]}, TypeError, "free must be a dict"),
        ({"free": {"interface.law.u_r": 1e-3}}, TypeError, "a pair of numbers (lo, hi), got float"),
        ({"free": {"interface.law.u_r": (1e-2, 1e-3)}}, ValueError, "reversed or equal"),
        ({"free": {"interface.law.nope": (1e-3, 1e-2)}}, ValueError, "refuses the lower bound"),
        ({"max_evals": 0}, ValueError, "max_evals must be ≥ 1 (got 0)"),
        ({"x": "u_top"}, ValueError, "--x u_top: no such column"),
    ],
)
def test_bad_arguments_are_refused(tmp_path, kwargs, error, text):
    data = pull_off_curve(tmp_path, 4e-3)
    args = {
        "x": "u_z_plus_z", "y": "F_z_plus_z",
        "free": {"interface.law.u_r": (2.5e-3, 1e-2)},
    }
    args.update(kwargs)
    with pytest.raises(error) as e:
        decohesion.fit(scene("pull_off"), data, **args)
    assert text in str(e.value)


def test_a_bad_curve_names_its_file_and_line(tmp_path):
    data = tmp_path / "bad.csv"
    data.write_text("u [mm], F [N]\n0, 0\n1, 1\n1, 2\n2, 3\n3, 4\n")
    with pytest.raises(ValueError) as e:
        decohesion.fit(scene("pull_off"), data, "u_z_plus_z", "F_z_plus_z",
                       free={"interface.law.u_r": (2.5e-3, 1e-2)})
    assert "bad.csv, line 4" in str(e.value) and "must increase strictly" in str(e.value)


def test_ctrl_c_returns_the_best_so_far(tmp_path):
    # A fit that would make 10⁵ runs of a 10³ pull-off, interrupted (as Ctrl-C does) once runs
    # have ended: the fit stops after the run in progress and returns its best run, with
    # stop = "cancelled", no σ (the uncertainty's runs are not made) and a warning that names
    # the interrupt.
    import _thread
    import signal
    import threading

    data = pull_off_curve(tmp_path, 4e-3)
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(1.5, _thread.interrupt_main)
    try:
        timer.start()
        with pytest.warns(UserWarning, match="fit interrupted") as warned:
            r = decohesion.fit(
                scene("pull_off"), data, "u_z_plus_z", "F_z_plus_z",
                free={"interface.law.u_r": (2.5e-3, 1e-2)},
                overrides={"mesh.cells": [10, 10, 10]},
                max_evals=100_000, tolerance=0.0, threads=1,
            )
    finally:
        timer.join()
        signal.signal(signal.SIGINT, previous)
    assert r["stop"] == "cancelled"
    assert 1 <= r["evaluations"] < 100_000
    assert "KeyboardInterrupt" in str(warned[0].message)
    (p,) = r["parameters"]
    assert p["sigma"] is None
    assert 2.5e-3 <= p["value"] <= 1e-2
    assert r["fitted"]["rms_relative"] <= r["initial"]["rms_relative"]
