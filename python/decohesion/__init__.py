"""decohesion: explicit non-smooth dynamics (CD-Lagrange) of a soft hex8 solid glued to rigid
moulds by the RCCM cohesive law — damageable adhesion, unilateral contact, friction growing with
damage — driven from Python.

>>> import decohesion
>>> scene = decohesion.Scene.load("scenes/pull_off.toml", overrides={"interface.law.u_r": 0.006})
>>> sim = decohesion.Simulation(scene)
>>> sim.step(100)                      # 100 CD-Lagrange steps, the GIL released
>>> sim.alpha                          # damage α of every interface node [m], numpy (m,)
>>> sim.run(save="out/pull_off.rrd")   # to the end time, recorded like `decohesion run --save`
>>> sim.summary()["time_full_rupture"]
>>> sim.history["F_z_plus_z [N]"]      # the reaction at every step [N], as `run --series`
>>> decohesion.fit("scenes/pull_off.toml", "curve.csv", "u_z_plus_z", "F_z_plus_z",
...                free={"interface.law.u_r": (2.5e-3, 1e-2)})["parameters"]

Units are SI (m, s, kg, N, Pa, J). The classes are written in Rust (``decohesion._native``);
their documentation with every array's shape, dtype and unit is in ``_native.pyi``.
"""

from typing import Any

from ._native import Scene, Simulation, SolverError, __version__, fit

__all__ = ["Scene", "Simulation", "SolverError", "__version__", "fit", "history_frame"]


def history_frame(sim: Simulation) -> Any:
    """``sim.history`` as a pandas DataFrame (one row per step, the ``--series`` columns) when
    pandas can be imported, else the dict of numpy arrays itself."""
    history = sim.history
    try:
        import pandas
    except ImportError:
        return history
    return pandas.DataFrame(history)
