#!/usr/bin/env python3
"""Checks that the test build, the command's build and the Python extension's build share one
build of every crates.io dependency and workspace crate they have in common (`.ci/run` calls it).

Cargo unifies features per build: a dependency that only one build has (the tests' proptest, the
explorer's egui, the extension's PyO3) can turn on features of crates that every build shares, and
those crates, with everything above them (the Rerun SDK is ~500 crates), are then built once per
feature set. This script asks cargo for the unit graph of each build (`--unit-graph`, read through
RUSTC_BOOTSTRAP=1: a query only, nothing is compiled) and fails, naming the crates, when a unit of
the command's build is not also a unit of the test build, or a unit of the extension's build (other
than PyO3's own) is not a unit of the command's build. The fix is in `run/Cargo.toml`: ask for the
missing features in the run crate's dependencies (the crate the extension builds).
"""

import json
import os
import subprocess
import sys

BUILDS = {
    "test": ["test", "--release", "--no-run"],
    "command": ["build", "--release", "--bin", "decohesion"],
    "python": ["build", "--release", "-p", "decohesion-py"],
}
# Crates that only the extension's build has: its own dependencies.
PYTHON_ONLY = ("pyo3", "pyo3-build-config", "pyo3-ffi", "pyo3-macros", "pyo3-macros-backend",
               "target-lexicon", "decohesion-py")


def unit_graph(args):
    env = dict(os.environ, RUSTC_BOOTSTRAP="1")
    out = subprocess.run(["cargo", "-Z", "unstable-options", *args, "--unit-graph"],
                         env=env, check=True, capture_output=True, text=True).stdout
    return json.loads(out)["units"]


def identities(units):
    """Every registry and workspace unit as (package, target, mode, platform, a digest of what it
    is built from: features and, recursively, its dependencies' digests)."""
    memo = {}

    def digest(i):
        if i not in memo:
            u = units[i]
            memo[i] = hash((u["pkg_id"], u["target"]["name"], tuple(u["features"]), u["platform"],
                            u["mode"], json.dumps(u["profile"], sort_keys=True),
                            tuple(sorted(digest(d["index"]) for d in u["dependencies"]))))
        return memo[i]

    found = {}
    for i, u in enumerate(units):
        if u["pkg_id"].startswith(("registry+", "path+")):
            name = u["pkg_id"].split("#")[-1]
            found.setdefault((name, u["target"]["name"], u["mode"]), set()).add(digest(i))
    return found


def missing(small, large, skip=()):
    return sorted(f"{name} ({target}, {mode})" for (name, target, mode), ds in small.items()
                  if name.split("@")[0] not in skip
                  and not ds <= large.get((name, target, mode), set()))


def main():
    graphs = {name: identities(unit_graph(args)) for name, args in BUILDS.items()}
    problems = []
    for small, large, skip in (("command", "test", ()), ("python", "command", PYTHON_ONLY)):
        extra = missing(graphs[small], graphs[large], skip)
        if extra:
            problems.append(f"the {small} build has {len(extra)} crate builds that the {large} "
                            f"build lacks (other features): " + ", ".join(extra[:20]))
    if problems:
        print("\n".join(problems), file=sys.stderr)
        print("ask for the features in run/Cargo.toml's dependencies (see its comment)",
              file=sys.stderr)
        return 1
    print("one feature set: the command's build is part of the test build, the Python "
          "extension's of the command's (PyO3 and the extension aside), workspace crates included")
    return 0


if __name__ == "__main__":
    sys.exit(main())
