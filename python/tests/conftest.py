"""Shared fixtures: the repository's scenes, the command-line binary (for parity with the
command line) and the Rerun CLI (for `rerun rrd verify`)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import decohesion

REPO = Path(__file__).resolve().parents[2]
SCENES = REPO / "scenes"


def scene(name: str) -> Path:
    """The path of a scene of the repository (``"pull_off"``, ``"extreme/brittle"``)."""
    return SCENES / f"{name}.toml"


def _required(what: str, how: str) -> None:
    """Fails under CI (``CI`` set), where every test must run; skips elsewhere."""
    if os.environ.get("CI"):
        pytest.fail(f"{what} not found: {how}")
    pytest.skip(f"{what} not found: {how}")


@pytest.fixture(scope="session")
def cli() -> Path:
    """The `decohesion` command built by cargo: $DECOHESION_BIN, else
    $CARGO_TARGET_DIR/release/decohesion, else target/release/decohesion."""
    candidates = [os.environ.get("DECOHESION_BIN")]
    if os.environ.get("CARGO_TARGET_DIR"):
        candidates.append(str(Path(os.environ["CARGO_TARGET_DIR"]) / "release" / "decohesion"))
    candidates.append(str(REPO / "target" / "release" / "decohesion"))
    for c in candidates:
        if c and Path(c).is_file():
            return Path(c)
    _required("the decohesion command", "cargo build --release, or set DECOHESION_BIN")


@pytest.fixture(scope="session")
def rerun() -> str:
    """The Rerun CLI: $DECOHESION_RERUN, else `rerun` beside this Python, else on PATH."""
    beside = Path(sys.executable).parent / "rerun"
    for c in (os.environ.get("DECOHESION_RERUN"), str(beside), shutil.which("rerun")):
        if c and Path(c).is_file():
            return c
    _required("the Rerun CLI", "pip install rerun-sdk==0.36.3, or set DECOHESION_RERUN")


def cli_summary(cli: Path, path: Path, tmp_path: Path, overrides=()) -> tuple[dict, int]:
    """`decohesion run PATH --summary` → (the JSON summary, the exit code)."""
    out = tmp_path / f"{path.stem}_cli.json"
    args = [str(cli), "run", str(path), "--quiet", "--summary", str(out)]
    for spec in overrides:
        args += ["--set", spec]
    done = subprocess.run(args, capture_output=True, text=True, cwd=REPO)
    return json.loads(out.read_text()), done.returncode


#: Summary fields that measure the machine (wall times, rates) or name output files: every other
#: field is physics, computed by the same code in the same order, and must be equal bit for bit.
NOT_PHYSICS = {
    "wall_seconds",
    "step_wall_seconds",
    "element_steps_per_second",
    "ns_per_element_step",
    "stage_seconds",
    "recording",
    "paraview",
}


def physics(summary: dict) -> dict:
    return {k: v for k, v in summary.items() if k not in NOT_PHYSICS}


@pytest.fixture
def pull_off() -> decohesion.Scene:
    return decohesion.Scene.load(scene("pull_off"))
