"""Errors reach Python as the command line reports them: every class of scene error as
ValueError with the command line's message (which names the key), a blow-up as SolverError
with its step, time, step size and stable step."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

import decohesion
from conftest import REPO, scene

PULL_OFF = scene("pull_off")


def cli_error(cli: Path, path: Path, specs: list[str]) -> str:
    """The message of `decohesion check PATH --set …`, which must fail."""
    args = [str(cli), "check", str(path)]
    for s in specs:
        args += ["--set", s]
    done = subprocess.run(args, capture_output=True, text=True, cwd=REPO)
    assert done.returncode == 1, done.stdout
    assert done.stderr.startswith("error: ")
    return done.stderr[len("error: "):].rstrip("\n")


# (what, Python overrides, the same as --set, the key the message must name)
OVERRIDE_CASES = [
    ("inadmissible value", {"interface.law.u_r": 0.001}, ["interface.law.u_r=0.001"],
     "interface[0].law.u_r"),
    ("not finite", {"material.young": float("nan")}, ["material.young=nan"], "material.young"),
    ("unknown key", {"material.youngs": 5e6}, ["material.youngs=5e6"], "material.youngs"),
    ("wrong type", {"material.young": "soft"}, ['material.young="soft"'], "material.young"),
    ("override out of range", {"plane.7.normal": [0, 0, 1]}, ["plane.7.normal=[0, 0, 1]"],
     "plane.7.normal"),
    ("unknown law family", {"interface.law.family": "glue"}, ['interface.law.family="glue"'],
     "interface[0].law.family"),
    ("unknown face set", {"interface.faces": "w+"}, ['interface.faces="w+"'], "interface[0].faces"),
]


@pytest.mark.parametrize("what,overrides,specs,key", OVERRIDE_CASES, ids=[c[0] for c in OVERRIDE_CASES])
def test_scene_errors_are_value_errors_with_the_command_lines_message(what, overrides, specs, key,
                                                                      cli):
    with pytest.raises(ValueError) as raised:
        decohesion.Scene.load(PULL_OFF, overrides=overrides)
    message = str(raised.value)
    assert key in message
    assert message == cli_error(cli, PULL_OFF, specs)


def edited(tmp_path: Path, drop: str = None, replace: tuple = None) -> Path:
    """pull_off.toml without the lines starting with `drop`, or with one text replaced."""
    lines = PULL_OFF.read_text().splitlines(keepends=True)
    if drop:
        lines = [ln for ln in lines if not ln.startswith(drop)]
    text = "".join(lines)
    if replace:
        assert replace[0] in text
        text = text.replace(*replace)
    path = tmp_path / "edited.toml"
    path.write_text(text)
    return path


#: The line of `young` in pull_off.toml, where the syntax error is made.
YOUNG_LINE = 1 + PULL_OFF.read_text().splitlines().index(
    next(ln for ln in PULL_OFF.read_text().splitlines() if ln.startswith("young = 5.0e6"))
)

# (what, edit, the key (or place) the message must name)
FILE_CASES = [
    ("TOML syntax", dict(replace=("young = 5.0e6", "young = 5.0e6e")), f"line {YOUNG_LINE}, column 14"),
    ("missing required key", dict(drop="end_time"), "end_time"),
    ("missing box-mesh key", dict(drop="cells"), "mesh.cells"),
    ("missing law parameter", dict(drop="u_r"), "interface[0].law.u_r"),
    ("plane named nowhere", dict(replace=('plane = "mould"', 'plane = "floor"')), "interface[0].plane"),
]


@pytest.mark.parametrize("what,edit,key", FILE_CASES, ids=[c[0] for c in FILE_CASES])
def test_file_errors_from_load_and_from_toml(what, edit, key, tmp_path, cli):
    path = edited(tmp_path, **edit)
    with pytest.raises(ValueError) as raised:
        decohesion.Scene.load(path)
    message = str(raised.value)
    assert key in message
    assert message == cli_error(cli, path, [])
    with pytest.raises(ValueError) as from_text:
        decohesion.Scene.from_toml(path.read_text(), file=str(path))
    assert str(from_text.value) == message


def test_a_file_that_cannot_be_read(tmp_path, cli):
    missing = tmp_path / "nowhere.toml"
    with pytest.raises(FileNotFoundError) as raised:
        decohesion.Scene.load(missing)
    assert str(raised.value) == cli_error(cli, missing, [])
    with pytest.raises(IsADirectoryError):
        decohesion.Scene.load(tmp_path)


def test_a_failed_run_raises_solver_error_with_its_fields(cli, tmp_path):
    """The top slammed down at 100 m/s: an element inverts within a few steps (h is capped at
    h_crit, so a time-step factor above 1 no longer blows a run up)."""
    slam = "[[0.0, 0.0], [0.01, -1.0]]"
    overrides = {"displacement.0.table": [[0.0, 0.0], [0.01, -1.0]], "end_time": 0.05}
    sim = decohesion.Simulation(decohesion.Scene.load(PULL_OFF, overrides=overrides))
    with pytest.raises(decohesion.SolverError) as raised:
        sim.run(progress=False)
    e = raised.value
    assert isinstance(e, RuntimeError) and e.kind == "inverted"
    assert isinstance(e.element, int) and 0 <= e.element < 343
    assert 0 < e.step < 150 and e.step == sim.step_count
    assert e.t == sim.t and e.t < sim.end_time
    assert e.h > 0 and e.h_crit > 0
    assert f"element {e.element} inverted" in str(e)
    summary = sim.summary()
    assert summary["status"] == "failed" and summary["error"] == str(e)
    assert summary["steps"] == e.step
    # The command line stops at the same step with the same message.
    out = tmp_path / "cli.json"
    done = subprocess.run([str(cli), "run", str(PULL_OFF), "--quiet", "--set",
                           f"displacement.0.table={slam}", "--set", "end_time=0.05",
                           "--summary", str(out)],
                          capture_output=True, text=True)
    assert done.returncode == 1
    assert f"error: {e}" in done.stderr
    # The failed simulation refuses to go on, with the same error.
    with pytest.raises(decohesion.SolverError) as again:
        sim.step()
    assert again.value.step == e.step and str(again.value) == str(e)
    assert sim.step_count == e.step


def test_bad_run_arguments_are_value_errors(pull_off, tmp_path):
    sim = decohesion.Simulation(pull_off)
    with pytest.raises(ValueError, match="not both"):
        sim.run(every=2, fps=10.0)
    with pytest.raises(ValueError, match="every must be ≥ 1"):
        sim.run(every=0)
    with pytest.raises(ValueError, match="fps must be a finite number > 0"):
        sim.run(fps=-1.0)
    with pytest.raises(ValueError, match="unknown colour field `red`"):
        sim.run(save=tmp_path / "x.rrd", colour="red")
    with pytest.raises(ValueError, match="until must be a finite time"):
        sim.run(until=float("inf"))
    with pytest.raises(ValueError, match="threads must be ≥ 1"):
        decohesion.Simulation(pull_off, threads=0)
    assert sim.step_count == 0


@pytest.mark.parametrize("flag", ["save", "vtk"])
def test_an_output_that_cannot_be_opened_is_an_os_error_with_the_command_lines_message(
        flag, pull_off, tmp_path, cli):
    blocker = tmp_path / "a_file"
    blocker.write_text("not a folder")
    target = blocker / ("run.rrd" if flag == "save" else "vtk")
    sim = decohesion.Simulation(pull_off)
    with pytest.raises(OSError) as raised:
        sim.run(progress=False, **{flag: target})
    assert sim.step_count == 0, "refused before the first step"
    done = subprocess.run([str(cli), "run", str(PULL_OFF), "--quiet", f"--{flag}", str(target)],
                          capture_output=True, text=True)
    assert done.returncode == 1
    assert done.stderr == f"error: {raised.value}\n"
    assert str(target) in str(raised.value)


# (what, the call, the exception, text its message must contain: the argument and what it takes)
BAD_ARGUMENTS = [
    ("overrides not a dict", lambda s: decohesion.Scene.load(PULL_OFF, overrides=3), TypeError,
     "overrides must be a dict"),
    ("override key not a str", lambda s: decohesion.Scene.load(PULL_OFF, overrides={1: 2}),
     TypeError, "override keys are key paths"),
    ("override value not a scene value",
     lambda s: decohesion.Scene.load(PULL_OFF, overrides={"material.young": object()}), TypeError,
     "override `material.young`: object is not a scene value"),
    ("threads negative", lambda s: decohesion.Simulation(s, threads=-3), ValueError,
     "threads must be ≥ 1"),
    ("negative step count", lambda s: decohesion.Simulation(s).step(-1), ValueError,
     "n must be ≥ 0 steps"),
    ("until NaN", lambda s: decohesion.Simulation(s).run(until=float("nan")), ValueError,
     "until must be a finite time"),
    ("every negative", lambda s: decohesion.Simulation(s).run(every=-2), ValueError,
     "every must be ≥ 1"),
    ("fps NaN", lambda s: decohesion.Simulation(s).run(fps=float("nan")), ValueError,
     "fps must be a finite number > 0"),
]


@pytest.mark.parametrize("what,call,error,text", BAD_ARGUMENTS, ids=[c[0] for c in BAD_ARGUMENTS])
def test_bad_arguments_are_refused_naming_the_argument(what, call, error, text, pull_off):
    with pytest.raises(error) as e:
        call(pull_off)
    assert text in str(e.value)


# (what, the call with an argument of the wrong type, the argument's name)
WRONG_TYPES = [
    ("step count a string", lambda s: decohesion.Simulation(s).step("10"), "n"),
    ("until a string", lambda s: decohesion.Simulation(s).run(until="0.1"), "until"),
    ("threads a float", lambda s: decohesion.Simulation(s, threads=1.5), "threads"),
    ("path a number", lambda s: decohesion.Scene.load(3), "path"),
    ("save path a number", lambda s: decohesion.Simulation(s).save(5), "path"),
    ("every a string", lambda s: decohesion.Simulation(s).run(every="2"), "every"),
]


@pytest.mark.parametrize("what,call,name", WRONG_TYPES, ids=[c[0] for c in WRONG_TYPES])
def test_a_wrong_type_is_a_type_error_that_names_the_argument(what, call, name, pull_off):
    """PyO3 names the argument in the exception's notes (PEP 678), which a traceback prints
    under the message: "while processing 'n'"."""
    with pytest.raises(TypeError) as e:
        call(pull_off)
    assert f"while processing '{name}'" in getattr(e.value, "__notes__", [])
