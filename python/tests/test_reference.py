"""The Python reference page and the stubs it is generated from: the committed page is what
``scripts/python_reference.py`` generates, and the stubs name exactly the public methods and
properties of the extension's classes (a method added in Rust without its stub fails here)."""

from __future__ import annotations

import ast
import importlib.util
from pathlib import Path

import decohesion

REPO = Path(__file__).resolve().parents[2]


def _script():
    spec = importlib.util.spec_from_file_location(
        "python_reference", REPO / "scripts" / "python_reference.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_python_md_is_current():
    problem = _script().check()
    assert problem is None, problem


def _stub_members() -> dict[str, set[str]]:
    tree = ast.parse((REPO / "python" / "decohesion" / "_native.pyi").read_text("utf-8"))
    return {
        c.name: {
            s.name
            for s in c.body
            if isinstance(s, ast.FunctionDef) and not s.name.startswith("_")
        }
        for c in tree.body
        if isinstance(c, ast.ClassDef)
    }


def test_stubs_name_every_public_member_of_the_classes():
    stubs = _stub_members()
    for name in ("Scene", "Simulation"):
        cls = getattr(decohesion, name)
        public = {m for m in vars(cls) if not m.startswith("_")}
        assert stubs[name] == public, (
            f"{name}: only in the stubs {sorted(stubs[name] - public)}, "
            f"only in the extension {sorted(public - stubs[name])}"
        )
