"""A sweep on a Dask cluster: each run of the grid is a task on a worker process, and the
results are the serial loop's, bit for bit (a run does not depend on where or beside what it
runs).

    pip install ./python "dask[distributed]"
    python examples/python/cluster_sweep.py                                # a local cluster
    python examples/python/cluster_sweep.py --scheduler tcp://HOST:8786    # a real one

The scene goes to the workers as its text (``Scene.from_toml``), so they need the ``decohesion``
package but not the repository; a scene that names a mesh or STL file needs that file at the
same path on every worker. The local cluster listens on 127.0.0.1 only and has no dashboard.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import decohesion

REPO = Path(__file__).resolve().parents[2]

#: Summary keys that measure the machine, not the physics: left out of the comparison.
MACHINE = ("wall_seconds", "step_wall_seconds", "element_steps_per_second",
           "ns_per_element_step", "stage_seconds", "threads")


def run_one(text: str, file: str, overrides: dict[str, Any]) -> dict[str, Any]:
    """One run of the grid on one thread: its summary (``decohesion run --summary``)."""
    scene = decohesion.Scene.from_toml(text, file=file, overrides=overrides)
    sim = decohesion.Simulation(scene, threads=1)
    sim.run(progress=False)
    return sim.summary()


def grid(key: str, values: list[float]) -> list[dict[str, Any]]:
    return [{key: v} for v in values]


def sweep(client, scene: Path, key: str, values: list[float]) -> list[dict[str, Any]]:
    """The grid as Dask tasks, one per value, gathered in the order of ``values``."""
    text = scene.read_text()
    futures = client.map(run_one, [text] * len(values), [str(scene)] * len(values),
                         grid(key, values), pure=False)
    return client.gather(futures)


def serial(scene: Path, key: str, values: list[float]) -> list[dict[str, Any]]:
    text = scene.read_text()
    return [run_one(text, str(scene), o) for o in grid(key, values)]


def physics(summary: dict[str, Any]) -> dict[str, Any]:
    """The summary without what measures the machine."""
    return {k: v for k, v in summary.items() if k not in MACHINE}


def local_client(workers: int):
    """A client of a cluster of `workers` local processes, one thread each, on 127.0.0.1."""
    from dask.distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                           host="127.0.0.1", dashboard_address="127.0.0.1:0")
    return Client(cluster)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scene", type=Path, default=REPO / "scenes" / "pull_off.toml")
    p.add_argument("--key", default="interface.law.u_r")
    p.add_argument("--values", default="0.003,0.004,0.006,0.008",
                   help="comma-separated values of --key")
    p.add_argument("--scheduler", help="address of a running Dask scheduler (default: a local "
                   "cluster of --workers processes)")
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--check", action="store_true",
                   help="also run the grid serially here and compare, bit for bit")
    a = p.parse_args()
    values = [float(v) for v in a.values.split(",")]
    if a.scheduler:
        from dask.distributed import Client

        client = Client(a.scheduler)
    else:
        client = local_client(a.workers)
    with client:
        rows = sweep(client, a.scene, a.key, values)
    print(f"{a.key:>24} {'status':>10} {'peak reaction [N]':>18} {'damage D [J]':>14} "
          f"{'full rupture [s]':>17}")
    for v, s in zip(values, rows):
        peak = s["peak_reactions"][0]["force"] if s["peak_reactions"] else float("nan")
        print(f"{v:>24g} {s['status']:>10} {peak:>18.6e} {s['energies']['damage_dissipated']:>14.6e} "
              f"{s['time_full_rupture'] or float('nan'):>17.6f}")
    if a.check:
        same = [physics(x) == physics(y) for x, y in zip(rows, serial(a.scene, a.key, values))]
        print("serial runs: " + ("the same, bit for bit" if all(same) else f"DIFFERENT {same}"))
        return 0 if all(same) else 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
