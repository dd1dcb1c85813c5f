#!/usr/bin/env python3
"""The synthetic measured curves of data/ (data/README.md says what each is), made by the model
itself with known law values, so that a fit can be checked against them.

    python3 scripts/synthetic_curves.py [--bin target/release/decohesion]

Each curve: `decohesion run SCENE --set … --series` (every step's scalars), read at evenly spaced
imposed displacements by linear interpolation (or, for the benchmark curves, as the mean of the
steps within half a spacing of each point: the force rings at each node's rupture, and a load
cell's filter would average that out), Gaussian noise of a stated share of the peak added (numpy's
PCG64 generator with a fixed seed, so a rerun writes the same file), written in the units each
curve states with a header comment saying how it was made. Needs numpy.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]

# name: (scene, overrides, x column, y column, x from, x to, points, noise share, seed,
#        (x label, x scale from m), (y label, y scale from N), averaged over a spacing)
MM_KN = (("u [mm]", 1e3), ("F [kN]", 1e-3))
MM_N = (("u [mm]", 1e3), ("F [N]", 1.0))
# The 45° peel's end path (lesson 3's): up at 1 m/s, sideways at 0.28 m/s.
PEEL_45 = (
    'displacement=[{faces="x-",component="z",table=[[0.0,0.0],[0.14,0.14]]},'
    '{faces="x-",component="x",table=[[0.0,0.0],[0.14,0.0392]]}]'
)
CURVES = {
    "pull_off_noisy": (
        "scenes/pull_off.toml", [], "u_z_plus_z [m]", "F_z_plus_z [N]",
        0.004, 0.16, 40, 0.02, 1, *MM_KN, False,
    ),
    # The benchmarks of issue 42, without noise (physics/tests/dcb.rs and
    # physics/tests/teaching_scenes.rs check the same runs against their analytic references).
    "dcb": (
        "data/dcb.toml", [], "u_x_minus_z [m]", "F_x_minus_z [N]",
        0.0, 0.00138, 70, 0.0, 0, *MM_N, True,
    ),
    "peel_90": (
        "scenes/peel.toml", [], "u_x_minus_z [m]", "F_x_minus_z [N]",
        0.0, 0.14, 71, 0.0, 0, *MM_N, True,
    ),
    "peel_45": (
        "scenes/peel.toml", [PEEL_45], "u_x_minus_z [m]", "F_x_minus_z [N]",
        0.0, 0.14, 71, 0.0, 0, *MM_N, True,
    ),
}


def read_series(path: Path) -> dict[str, np.ndarray]:
    lines = path.read_text().splitlines()
    names = lines[0].split(",")
    values = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    return {n: values[:, k] for k, n in enumerate(names)}


def main() -> int:
    default_bin = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target")) / "release" / "decohesion"
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bin", type=Path, default=default_bin)
    args = parser.parse_args()
    out_dir = REPO / "data"
    for name, (scene, sets, xc, yc, x0, x1, n, noise, seed, xu, yu, avg) in CURVES.items():
        with tempfile.TemporaryDirectory() as tmp:
            series = Path(tmp) / "series.csv"
            cmd = [str(args.bin), "run", scene, "--quiet", "--series", str(series)]
            for s in sets:
                cmd += ["--set", s]
            subprocess.run(cmd, cwd=REPO, check=True)
            h = read_series(series)
        x = np.linspace(x0, x1, n)
        y = np.interp(x, h[xc], h[yc])
        if avg:
            half = 0.5 * (x1 - x0) / (n - 1)
            for k, xk in enumerate(x):
                near = np.abs(h[xc] - xk) <= half
                if near.any():
                    y[k] = h[yc][near].mean()
        rng = np.random.default_rng(seed)
        y_noisy = y + noise * np.abs(y).max() * rng.standard_normal(n) if noise > 0 else y
        text = [
            f"# {name}: `decohesion run {scene}"
            + "".join(f" --set '{s}'" for s in sets)
            + f"`, {yc} read at {n} values of {xc} from {x0} to {x1}"
            + (" (each the mean of the steps within half a spacing)," if avg else ","),
            f"# Gaussian noise of σ = {noise:g} × the peak added (numpy PCG64, seed {seed});"
            if noise > 0
            else "# no noise added;",
            "# made by scripts/synthetic_curves.py.",
            f"{xu[0]}, {yu[0]}",
        ]
        text += [f"{a * xu[1]:.6g}, {b * yu[1]:.6g}" for a, b in zip(x, y_noisy)]
        (out_dir / f"{name}.csv").write_text("\n".join(text) + "\n")
        print(f"wrote data/{name}.csv ({n} points)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
