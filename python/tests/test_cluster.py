"""`examples/python/cluster_sweep.py`: a sweep mapped over a Dask cluster of local worker
processes gives the serial loop's summaries bit for bit."""

from __future__ import annotations

import importlib.util
import os
import shutil
import subprocess

from conftest import REPO, _required, physics, scene


def example():
    path = REPO / "examples" / "python" / "cluster_sweep.py"
    spec = importlib.util.spec_from_file_location("cluster_sweep", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_a_sweep_on_a_local_cluster_equals_the_serial_runs():
    try:
        import dask.distributed  # noqa: F401
    except ImportError:
        _required("dask.distributed", 'pip install "dask[distributed]"')
    ex = example()
    values = [0.003, 0.004, 0.006]
    with ex.local_client(2) as client:
        # Two worker processes, not threads of this one.
        assert len(client.scheduler_info()["workers"]) == 2
        rows = ex.sweep(client, scene("pull_off"), "interface.law.u_r", values)
    here = ex.serial(scene("pull_off"), "interface.law.u_r", values)
    assert [r["status"] for r in rows] == ["completed"] * 3
    for got, want in zip(rows, here):
        assert physics(got) == physics(want)
    # The values did reach the runs: a larger u_r dissipates more.
    damage = [r["energies"]["damage_dissipated"] for r in rows]
    assert damage == sorted(damage) and damage[0] < damage[-1]


def test_the_local_cluster_listens_on_127_0_0_1_only():
    """Every socket the cluster's processes listen on (this one's scheduler, the nannies, the
    workers; read with `ss`) is bound to 127.0.0.1."""
    try:
        import dask.distributed  # noqa: F401
    except ImportError:
        _required("dask.distributed", 'pip install "dask[distributed]"')
    ss = shutil.which("ss")
    if ss is None:
        _required("ss (iproute2)", "apt-get install iproute2")
    ex = example()
    with ex.local_client(2) as client:
        assert client.scheduler.address.startswith("tcp://127.0.0.1:")
        pids = {os.getpid()}
        pids |= set(client.run(os.getpid).values()) | set(client.run(os.getppid).values())
        out = subprocess.run([ss, "-Hltnp"], capture_output=True, text=True, check=True).stdout
    listening = [line.split() for line in out.splitlines()
                 if any(f"pid={p}," in line for p in pids)]
    assert listening, out
    for fields in listening:
        assert fields[3].startswith("127.0.0.1:"), fields
