"""Type stubs and documentation of the Rust extension ``decohesion._native``.

Units are SI: metres, seconds, kilograms, newtons, pascals, joules. Arrays are new numpy arrays
at every access (copies: writing into one changes nothing in the simulation). Node arrays are
indexed like ``reference_coordinates``; interface arrays (``alpha``, ``gap``, …) follow
``interface_nodes``; contact arrays follow ``contact_nodes``.
"""

import os
from typing import Any, Mapping, Optional, Union

import numpy as np
import numpy.typing as npt

#: The package's version, the crate's (``python/Cargo.toml``).
__version__: str

#: A scene value for ``overrides``: what a TOML value can be.
OverrideValue = Union[bool, int, float, str, list, tuple, dict]

class SolverError(RuntimeError):
    """The simulation could not go on: the energy grew (``kind == "unstable"``, typically a time
    step above the stability limit) or an element inverted (``kind == "inverted"``). The message
    is the command line's, with what to change. The simulation keeps the state where it stopped;
    stepping it again raises the same error."""

    step: int
    """Step n at which the run stopped."""
    t: float
    """Time tₙ [s]."""
    h: float
    """Time step h [s]."""
    h_crit: float
    """Estimated stable step h_crit [s]."""
    kind: str
    """``"unstable"`` or ``"inverted"``."""
    element: Optional[int]
    """The inverted element (``kind == "inverted"``), else None."""

class Scene:
    """A scene: the model of ``decohesion run SCENE``, validated. Every key, its unit, default
    and admissible range: the scene reference, ``docs/src/reference/scenes.md``
    (``decohesion reference scenes``).

    A scene that cannot be loaded raises ``ValueError`` with the command line's message, which
    names the file, the key, the value and what is admissible (a file that cannot be read:
    ``FileNotFoundError`` / ``OSError``)."""

    @staticmethod
    def load(
        path: Union[str, os.PathLike[str]],
        overrides: Optional[Mapping[str, OverrideValue]] = None,
    ) -> Scene:
        """Reads the scene file at ``path``. ``overrides`` maps key paths to values, as
        ``decohesion run --set key=value`` does: ``{"interface.law.u_r": 0.006,
        "mesh.cells": [14, 14, 14], "plane.0.normal": [0, 0, 1], "material.model":
        "neo_hookean"}``; a numeric segment indexes an array, an array of one table is entered
        without an index. The overridden scene goes through the same validation as a file."""
    @staticmethod
    def from_toml(
        text: str,
        file: str = "scene.toml",
        overrides: Optional[Mapping[str, OverrideValue]] = None,
    ) -> Scene:
        """A scene from its TOML text. ``file`` names it in messages; its stem is the scene's
        name unless the text sets ``name``, and its folder is where a relative ``mesh.file`` is
        read from (the current directory by default)."""
    def check(self) -> dict[str, Any]:
        """What ``decohesion check`` prints, as a dict: ``file``, ``name``, ``description``,
        ``nodes``, ``elements``, ``smallest_edge`` [m], ``material`` (``model``, ``young`` [Pa],
        ``poisson``, ``density`` [kg/m³], ``lambda`` and ``mu`` [Pa] — a rubber's small-strain
        limit — and ``rubber``: None, or a dict of the rubber's family constants ``iso``,
        ``bulk`` K [Pa] and ``volumetric``), ``wave_speed`` c_d [m/s],
        ``h_crit`` [s] (Lanczos estimate, model §6.2), ``h_crit_element`` = L_e/c_d [s],
        ``h_crit_bulk`` [s] or None (the bulk alone, when the glue may set the step),
        ``time_step`` h [s], ``time_step_factor``, ``end_time`` [s], ``expected_steps``,
        ``interfaces`` (one dict per interface: ``faces``, ``family``, ``label``, ``g_n0``
        [Pa/m], ``alpha_e`` and ``u_r`` [m], ``mu_inf``, ``initial_damage`` [m],
        ``peak_traction`` [Pa] at ``peak_opening`` [m], ``fracture_energy`` G_c [J/m²],
        ``area`` [m²], ``energy_to_break`` [J]), ``state_bytes_per_element`` and
        ``warnings`` (list of str: the regime of the model, as ``check`` and ``run`` print
        them). Sets the simulation up (a Lanczos estimate): a set-up error is a
        ``ValueError``."""
    @property
    def name(self) -> str:
        """The scene's name (the file's stem unless the scene sets ``name``)."""
    @property
    def description(self) -> str:
        """The scene's ``description`` (empty if it has none)."""
    @property
    def file(self) -> str:
        """The file name used in messages."""
    @property
    def text(self) -> str:
        """The scene text as read."""
    @property
    def resolved(self) -> str:
        """The TOML document after the overrides: what the model was built from."""
    @property
    def end_time(self) -> float:
        """End time of a run [s]."""

class Simulation:
    """The CD-Lagrange simulation of a scene (model §4): positions Uₙ at integer times tₙ,
    velocities V_{n+½} at half times, the RCCM interface, contact and friction solved node by
    node, the energy ledger (model §5), the stable step re-estimated as the run goes (model §6).

    ``threads``: threads of the element loop (default: every core, above 2048 elements).
    Results do not depend on it. Stepping releases the GIL; Ctrl-C (``KeyboardInterrupt``)
    stops after the current step and leaves a consistent state that can be stepped on. While
    one thread steps a simulation, using that same simulation from another thread raises
    ``RuntimeError`` (it is borrowed); other simulations and other Python code run freely."""

    def __init__(self, scene: Scene, threads: Optional[int] = None) -> None:
        """Sets the simulation of ``scene`` up at t = 0 (the stable step estimated). A set-up
        error is a ``ValueError``; ``threads`` < 1 too."""
    def step(self, n: int = 1) -> None:
        """Takes ``n`` steps, also past the end time. Raises ``SolverError`` on a blow-up and
        ``KeyboardInterrupt`` on Ctrl-C (after the current step)."""
    def run(
        self,
        until: Optional[float] = None,
        progress: bool = True,
        save: Union[str, os.PathLike[str], None] = None,
        vtk: Union[str, os.PathLike[str], None] = None,
        every: Optional[int] = None,
        fps: Optional[float] = None,
        colour: str = "displacement",
        series: Union[str, os.PathLike[str], None] = None,
    ) -> None:
        """Steps until tₙ reaches ``until`` [s] (default: the scene's end time; the last step is
        the first at or past it), through the command line's run driver:

        - ``progress``: a progress bar (tqdm if installed, else a plain line on stderr);
        - ``save``: a Rerun recording to this ``.rrd`` file, the same as ``decohesion run
          --save`` (entities, layout, cadence): ``rerun FILE`` opens it;
        - ``vtk``: ParaView files in this folder (``.vtu`` per frame and ``NAME.pvd``), as
          ``--vtk``;
        - ``every`` (steps) or ``fps`` (frames per simulated second): the frame cadence of
          both; by default 200 frames over the end time, plus the first and the last step;
        - ``colour``: ``"displacement"``, ``"von_mises"`` or ``"jacobian"`` (the recording's
          surface colour);
        - ``series``: the run's scalars to this CSV file, as ``--series`` (a row per step, or at
          ``every``/``fps`` when given); ``history`` has them whatever this is.

        The recording and the ParaView index are finished whatever the outcome: on
        ``SolverError``, on Ctrl-C (``KeyboardInterrupt`` is raised after they are written) and
        on an output's error (``OSError``)."""
    def save(self, path: Union[str, os.PathLike[str]]) -> None:
        """Writes the state at tₙ to the checkpoint file ``path``, atomically (a temporary file,
        fsync, rename): the fields, the damage, the moulds, the step control, the ledger and
        the statistics, each number to the bit. ``restore`` continues from it. Raises
        ``ValueError`` after a ``SolverError`` (that state is not saved) and ``OSError`` when
        the file cannot be written."""
    def restore(self, path: Union[str, os.PathLike[str]]) -> None:
        """Continues from the checkpoint file ``path`` written by ``save`` of a simulation of
        the same scene: stepping on gives the same bits as the simulation that saved it.
        ``history`` restarts at the restored step. Raises ``ValueError`` for a file that is not
        a checkpoint, is corrupt (its checksums), or was written for another scene (its
        overrides, mesh or moulds), leaving the simulation as it was; ``OSError`` (e.g.
        ``FileNotFoundError``) when it cannot be read."""
    def summary(self) -> dict[str, Any]:
        """The command line's ``--summary`` JSON for the simulation now, as a dict: ``scene``,
        ``status`` (``"completed"`` once the end time is reached, ``"in_progress"`` before,
        ``"failed"`` after a ``SolverError``, ``"cancelled"`` after a ``KeyboardInterrupt``),
        ``error``, ``nodes``, ``elements``, ``interface_nodes``, ``threads``, ``steps``,
        ``time_step`` [s], ``h_crit_initial``, ``h_crit_min`` [s], ``time_step_factor``,
        ``simulated_time`` [s], ``wall_seconds`` (set-up and every ``step``/``run``),
        ``step_wall_seconds``, ``element_steps_per_second``, ``ns_per_element_step``,
        ``peak_reactions`` (``faces``, ``component``, ``force`` [N],
        ``imposed_displacement`` [m], ``time`` [s]), ``time_first_damage``,
        ``time_full_rupture`` [s] or None, ``final_counts``, ``energies`` (as
        ``energies``), ``max_relative_residual``, ``stage_seconds``, ``recording`` and
        ``paraview`` (what the last ``run`` wrote, or None), ``series`` (when the last ``run``
        wrote one), ``warnings``."""
    @property
    def history(self) -> dict[str, npt.NDArray[Any]]:
        """The scalars of every step taken since the simulation was made, step 0 included, by
        ``step`` and ``run`` alike (a failed step's state too): the columns of ``decohesion run
        --series`` keyed by their CSV names with units, each a (rows,) array, float64 (int64
        for ``step [-]`` and the ``n_… [-]`` counts), equal to the CSV's values bit for bit:

        - ``t [s]``, ``step [-]``, ``h [s]`` (the step about to be taken);
        - per prescribed condition ``<faces>_<axis>`` (``z+`` written ``z_plus``): ``u_… [m]``,
          the imposed displacement, and ``F_… [N]``, its reaction;
        - per mould: ``F_mould_<name>_x [N]`` (``_y``, ``_z``), the force the body exerted on
          it over the last step, and ``M_mould_<name>_x [N m]`` …, its moment about the mould's
          pivot;
        - the ledger's terms [J] (the keys of ``energies``, plus ``step_change_work``) and
          ``relative_residual [-]``; with several moulds ``friction_mould_<name> [J]``;
        - ``n_elastic``, ``n_transition``, ``n_ruptured``, ``n_unformed`` interface nodes by
          state and ``n_open``, ``n_stick``, ``n_slip`` nodes by contact status [-].

        A row takes about 8 bytes per column per step; ``decohesion.history_frame(sim)`` gives
        a pandas DataFrame."""
    @property
    def t(self) -> float:
        """Time tₙ [s]."""
    @property
    def h(self) -> float:
        """The step about to be taken, h_{n+½} = tₙ₊₁ − tₙ [s]."""
    @property
    def h_crit(self) -> float:
        """The latest stable-step estimate 2/ω_max [s]."""
    @property
    def step_count(self) -> int:
        """Steps taken, n."""
    @property
    def end_time(self) -> float:
        """The scene's end time [s]."""
    @property
    def finished(self) -> bool:
        """True once tₙ has reached the end time."""
    @property
    def scene(self) -> Scene:
        """The scene simulated."""
    @property
    def threads(self) -> int:
        """Threads that run the step's loops."""
    @property
    def reference_coordinates(self) -> npt.NDArray[np.float64]:
        """Reference coordinates X, shape (nodes, 3), float64 [m]."""
    @property
    def elements(self) -> npt.NDArray[np.int64]:
        """Hex8 connectivity (node indices), shape (elements, 8), int64."""
    @property
    def mass(self) -> npt.NDArray[np.float64]:
        """Lumped nodal masses, shape (nodes,), float64 [kg]."""
    @property
    def displacement(self) -> npt.NDArray[np.float64]:
        """Displacements Uₙ, shape (nodes, 3), float64 [m]."""
    @property
    def velocity(self) -> npt.NDArray[np.float64]:
        """Velocities V_{n+½} (Uₙ₊₁ = Uₙ + h V_{n+½}), shape (nodes, 3), float64 [m/s]."""
    @property
    def interface_nodes(self) -> npt.NDArray[np.int64]:
        """Node index of each interface (glued) node, shape (m,), int64."""
    @property
    def alpha(self) -> npt.NDArray[np.float64]:
        """Damage αₙ of the interface nodes, shape (m,), float64 [m]: the largest damage measure
        reached (PHYSICS.md §3, eq. 12), at most u_r for the g_N(α) families, approached with
        a lag under ``[interface.delay]``; for ``rccm`` the equivalent opening u₀/√β, which
        goes on past u_r; 0 on nodes whose glue has not formed (state 3)."""
    @property
    def gap(self) -> npt.NDArray[np.float64]:
        """Normal gap gₙ of the interface nodes (> 0 open), shape (m,), float64 [m]."""
    @property
    def jump(self) -> npt.NDArray[np.float64]:
        """Displacement jump [u]ₙ of the interface nodes, shape (m, 3), float64 [m]."""
    @property
    def cohesive_traction(self) -> npt.NDArray[np.float64]:
        """Cohesive traction R_d = g_N(α)[u] (acting on the solid as −R_d), shape (m, 3),
        float64 [Pa]."""
    @property
    def interface_state(self) -> npt.NDArray[np.int8]:
        """State of the interface nodes, shape (m,), int8: 0 elastic (α ≤ α_e), 1 transition
        (α_e < α < u_r), 2 ruptured (α ≥ u_r) — the glue's states of paper fig. 6 — and 3
        unformed: a node of glue that forms on contact (a ``[[contact]]`` entry with a
        ``[contact.law]``) that has not touched the mould yet (contact with Coulomb ``mu``, no
        glue)."""
    @property
    def interface_contact(self) -> npt.NDArray[np.int8]:
        """Contact status of the interface nodes in the last step, shape (m,), int8: 0 open,
        1 stick, 2 slip."""
    @property
    def contact_nodes(self) -> npt.NDArray[np.int64]:
        """Node index of each contact-only node (no glue), shape (k,), int64."""
    @property
    def contact_gap(self) -> npt.NDArray[np.float64]:
        """Normal gap of the contact-only nodes, shape (k,), float64 [m]."""
    @property
    def contact_status(self) -> npt.NDArray[np.int8]:
        """Contact status of the contact-only nodes, shape (k,), int8: 0 open, 1 stick,
        2 slip."""
    @property
    def prescribed(self) -> list[str]:
        """Names ``<faces>_<axis>`` of the prescribed-displacement conditions."""
    @property
    def reactions(self) -> npt.NDArray[np.float64]:
        """Reaction force of each prescribed condition along its axis now, shape (p,),
        float64 [N]."""
    @property
    def imposed_displacements(self) -> npt.NDArray[np.float64]:
        """Imposed displacement of each prescribed condition at tₙ, shape (p,), float64
        [m]."""
    @property
    def energies(self) -> dict[str, float]:
        """The energy ledger now (model §5.1) [J]: ``kinetic``, ``strain``, ``hourglass``,
        ``interface_stored``, ``damage_dissipated``, ``contact_normal_dissipated``,
        ``friction_dissipated``, ``external_work`` (= ``gravity_work`` + ``traction_work`` +
        ``reaction_work`` + ``plane_work``), ``internal_work``, ``residual`` (the balance
        residual) and ``relative_residual`` [-]."""
    @property
    def state_counts(self) -> dict[str, int]:
        """Interface nodes per state now: ``elastic``, ``transition``, ``ruptured``, and
        ``unformed`` (state 3 of ``interface_state``) only when some glue that forms on contact
        has nodes not formed yet."""

def fit(
    scene: Union[str, os.PathLike[str]],
    data: Union[str, os.PathLike[str]],
    x: str,
    y: str,
    free: Mapping[str, tuple[float, float]],
    overrides: Optional[Mapping[str, OverrideValue]] = None,
    x_unit: Optional[str] = None,
    y_unit: Optional[str] = None,
    max_evals: int = 600,
    sample: Optional[int] = None,
    tolerance: float = 1e-10,
    threads: Optional[int] = None,
    out: Optional[Union[str, os.PathLike[str]]] = None,
) -> dict[str, Any]:
    """``decohesion fit``: the values of the ``free`` keys (``{"interface.law.u_r": (2.5e-3,
    1e-2)}``, each with its bounds) that make the run of ``scene`` reproduce the measured curve
    ``data`` (CSV: a header ``u [mm], F [N]``, then x strictly increasing and y), comparing the
    series columns ``x`` and ``y`` (names of ``Simulation.history`` / ``run --series``, with or
    without the unit, e.g. ``"u_z_plus_z"`` and ``"F_z_plus_z"``) at the measured x. Each key
    starts from the scene's value (after ``overrides``), else the middle of its bounds;
    ``x_unit`` and ``y_unit`` give the measured units when the header has none.

    A Halton sample of ``sample`` points of the bounds' box (default: 20 per free key), then
    Nelder–Mead from the best of them and the start, at most ``max_evals`` runs in all, until
    the misfits of the simplex agree within ``tolerance``; the sample, the first simplex and the
    uncertainty's runs go side by side on ``threads`` threads (default: the cores), the GIL
    released. Returns the report of
    ``fit.json``: ``parameters`` (each ``key``, ``start``, ``value``, ``sigma``, ``at_bound``),
    ``correlation``, ``initial`` and ``fitted`` (misfit ``cost``, ``rms_relative``, ``rms`` in the
    measured unit), ``stop`` (``"converged"``; ``"stalled"``: no run improved on the best in the last 20 (n + 1);
    ``"max_evals"``; ``"cancelled"``), the run counts
    and ``curves`` (``x``, ``measured``, ``initial``, ``fitted`` in the measured units). With
    ``out``, the command's files are written there too (``fit.json``, ``fit.csv``,
    ``evaluations.csv``, ``fit.svg``, the fitted scene file).

    Bad input (the curve, a key, bounds, a column) raises ``ValueError`` naming the file and line
    or the key and what is admissible. Ctrl-C stops after the run in progress: the best so far
    is returned with ``stop == "cancelled"`` and a warning."""
