"""A parameter study in Python: the pull-off test (paper §5) for several values of one law
parameter, by default the rupture opening u_r of the plateau–linear law.

For each value the scene is loaded with an override, stepped with ``run(until=…)`` to 200
instants, and the interface state read as numpy arrays at each. The figure shows the paper's
figure 6 for the reference value — α(t) of every interface node, and the elastic / transition /
ruptured counts over time — then, for every value, the reaction against the imposed
displacement and the energy the glue dissipated against G_c·A (what the law says it takes to
break the whole interface).

    pip install ./python matplotlib
    python examples/python/study.py                      # → screenshots/python_study.png
    python examples/python/study.py --param interface.law.alpha_e --values 0.001,0.0015,0.002
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import decohesion  # noqa: E402

REPO = Path(__file__).resolve().parents[2]


def simulate(scene: decohesion.Scene, samples: int) -> dict:
    """Runs `scene` to its end time, sampling the interface and the reaction `samples` times."""
    sim = decohesion.Simulation(scene)
    rows = []
    for t in np.linspace(0.0, sim.end_time, samples + 1)[1:]:
        sim.run(until=t, progress=False)
        counts = sim.state_counts
        rows.append((sim.t, sim.alpha, [counts[k] for k in ("elastic", "transition", "ruptured")],
                     sim.reactions[0], sim.imposed_displacements[0]))
    t, alpha, counts, reaction, imposed = (np.array(c) for c in zip(*rows))
    law = scene.check()["interfaces"][0]
    # Where each interface node is: its distance from the centre of the glued face.
    X = sim.reference_coordinates[sim.interface_nodes]
    radius = np.linalg.norm(X[:, :2] - X[:, :2].mean(axis=0), axis=1)
    return dict(t=t, alpha=alpha, counts=counts, reaction=reaction, imposed=imposed, law=law,
                radius=radius, summary=sim.summary())


def figure(param: str, values: list[float], runs: list[dict], reference: int, out: Path) -> None:
    fig, ax = plt.subplots(2, 2, figsize=(12, 8.5), constrained_layout=True)
    ref = runs[reference]
    law = ref["law"]
    name = param.split(".")[-1]
    # Paper fig. 6, left: α(t) of every interface node, with α_e and u_r.
    a = ax[0, 0]
    shade = plt.cm.plasma(ref["radius"] / ref["radius"].max() * 0.85)
    for k in np.argsort(ref["radius"]):
        a.plot(ref["t"], 1e3 * ref["alpha"][:, k], lw=0.8, color=shade[k])
    bar = plt.cm.ScalarMappable(cmap="plasma", norm=plt.Normalize(0, ref["radius"].max() / 0.85))
    fig.colorbar(bar, ax=a, label="distance of the node from the face centre [m]")
    for level, label in ((law["alpha_e"], "α_e"), (law["u_r"], "u_r")):
        a.axhline(1e3 * level, ls="--", color="k", lw=0.8)
        a.text(ref["t"][-1], 1e3 * level, f" {label}", va="bottom", ha="right")
    a.set(xlabel="t [s]", ylabel="α [mm]",
          title=f"damage α(t) of the {ref['alpha'].shape[1]} interface nodes ({name} = {values[reference]:g})")
    # Paper fig. 6, right: the state counts over time.
    a = ax[0, 1]
    for k, (label, colour) in enumerate((("elastic", "tab:green"), ("transition", "tab:orange"),
                                         ("ruptured", "tab:red"))):
        a.plot(ref["t"], ref["counts"][:, k], color=colour, lw=2, label=label)
    a.set(xlabel="t [s]", ylabel="interface nodes", title="interface states (paper fig. 6)")
    a.legend()
    # The reaction on the pulled face against its imposed displacement, for every value.
    a = ax[1, 0]
    colours = plt.cm.viridis(np.linspace(0, 0.9, len(runs)))
    for v, r, c in zip(values, runs, colours):
        a.plot(1e3 * r["imposed"], 1e-3 * r["reaction"], color=c, lw=1.5, label=f"{name} = {v:g}")
    ruptured = [r["summary"]["time_full_rupture"] or r["t"][-1] for r in runs]
    u_end = max(np.interp(t, r["t"], r["imposed"]) for t, r in zip(ruptured, runs))
    a.axhline(0.0, color="k", lw=0.5)
    a.set(xlabel="imposed displacement U_z [mm]", ylabel="reaction F_z [kN]",
          title="reaction against imposed displacement (until all are ruptured, + 30 %)",
          xlim=(0, 1.3e3 * u_end))
    a.legend()
    # Dissipated energy against G_c·A: the law's price of breaking the interface.
    a = ax[1, 1]
    gca = np.array([r["law"]["energy_to_break"] for r in runs])
    dissipated = np.array([r["summary"]["energies"]["damage_dissipated"] for r in runs])
    a.plot(1e-3 * gca, 1e-3 * gca, "k--", lw=0.8, label="D = G_c·A")
    a.scatter(1e-3 * gca, 1e-3 * dissipated, c=colours, s=60, zorder=3, label="computed")
    for v, x, y in zip(values, gca, dissipated):
        a.annotate(f" {v:g}", (1e-3 * x, 1e-3 * y))
    a.set(xlabel="G_c·A [kJ]", ylabel="damage dissipated D [kJ]",
          title=f"dissipation against fracture energy ({name})")
    a.legend()
    fig.suptitle(f"{ref['summary']['scene']}: sweep of {param}", fontsize=14)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=100)
    print(f"wrote {out}")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--scene", default=str(REPO / "scenes" / "pull_off.toml"))
    p.add_argument("--param", default="interface.law.u_r", help="key path of the swept value")
    p.add_argument("--values", default="0.003,0.004,0.006,0.008",
                   help="comma-separated values [SI units]")
    p.add_argument("--reference", type=int, default=1, help="index of the value of figure 6")
    p.add_argument("--samples", type=int, default=500, help="instants sampled per run")
    p.add_argument("--quick", action="store_true", help="two values, 40 samples (for CI)")
    p.add_argument("--out", default=str(REPO / "screenshots" / "python_study.png"))
    args = p.parse_args()
    values = [float(v) for v in args.values.split(",")]
    samples, reference = args.samples, args.reference
    if args.quick:
        values, samples, reference = values[:2], 40, 0
    runs = []
    for v in values:
        scene = decohesion.Scene.load(args.scene, overrides={args.param: v})
        r = simulate(scene, samples)
        s = r["summary"]
        print(f"{args.param} = {v:g}: {s['status']}, {s['steps']} steps, full rupture at "
              f"{s['time_full_rupture']} s, D = {s['energies']['damage_dissipated']:.1f} J "
              f"(G_c·A = {r['law']['energy_to_break']:.1f} J)")
        runs.append(r)
    figure(args.param, values, runs, reference, Path(args.out))


if __name__ == "__main__":
    main()
