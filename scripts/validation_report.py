#!/usr/bin/env python3
"""The validation report, docs/src/validation.md, from what the tests recorded.

The integration tests of both crates, run with DECOHESION_VALIDATION_DIR=DIR, append one JSON
line per compared quantity to DIR/cases.jsonl and write the compared curves to DIR/curves/
(tests/common/validation.rs). This script merges them with the prose of
docs/validation-cases.toml (what each case is and checks) and the hand-written
docs/validation-other.md (the checks without an independent reference value), writes
docs/src/validation.md and, if matplotlib can be imported, one PNG per case with a curve into
docs/src/validation/. It exits with 1 if a recorded quantity failed its tolerance, or (with
--strict) if a case of docs/validation-cases.toml recorded nothing.

Usually run by scripts/validation.sh, which runs the tests first.
"""

import argparse
import json
import math
import os
import sys
import textwrap
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
COMMAND = "scripts/validation.sh"


def load_records(directory):
    """The records of cases.jsonl, the last one kept when a (case, quantity) repeats."""
    path = directory / "cases.jsonl"
    if not path.exists():
        sys.exit(f"{path}: no records (run the tests with DECOHESION_VALIDATION_DIR={directory})")
    records = {}
    for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if not line.strip():
            continue
        try:
            r = json.loads(line)
        except json.JSONDecodeError as e:
            sys.exit(f"{path}:{n}: {e}")
        records[(r["case"], r["quantity"])] = r
    return list(records.values())


def load_curves(directory):
    """{case: [curve, ...]} from DIR/curves/*.json, each case's curves in name order."""
    curves = {}
    for path in sorted((directory / "curves").glob("*.json")):
        c = json.loads(path.read_text(encoding="utf-8"))
        curves.setdefault(c["case"], []).append(c)
    return curves


def passes(r):
    """The tolerance check, redone from the recorded numbers (as the test's helper does)."""
    ours, ref, tol = r["ours"], r["reference"], r["tolerance"]
    if not math.isfinite(ours):
        return False
    kind = r["tolerance_kind"]
    if kind == "relative":
        return abs(ours - ref) <= tol * abs(ref)
    if kind == "absolute":
        return abs(ours - ref) <= tol
    if kind == "interval":
        return tol[0] <= ours <= tol[1]
    raise ValueError(f"unknown tolerance kind {kind!r}")


def digits(r):
    """Significant digits that show where ours and the reference part (6 to 12)."""
    ours, ref = r["ours"], r["reference"]
    if not (math.isfinite(ours) and math.isfinite(ref)) or ref == 0 or ours == ref:
        return 6
    rel = abs(ours - ref) / abs(ref)
    return min(12, max(6, math.ceil(-math.log10(rel)) + 2))


def num(x, significant=6):
    """A value for the table, to `significant` digits."""
    if isinstance(x, float) and not math.isfinite(x):
        return "∞" if x > 0 else ("−∞" if x < 0 else "NaN")
    if x == 0:
        return "0"
    a = abs(x)
    if 1e-3 <= a < 1e6:
        s = f"{x:.{significant}g}"
    else:
        s = f"{x:.{max(significant - 1, 1)}e}"
        mantissa, exponent = s.split("e")
        mantissa = mantissa.rstrip("0").rstrip(".")
        s = f"{mantissa}e{int(exponent)}"
    return s.replace("-", "−")


def error_text(r):
    e = r["error"]
    if not math.isfinite(e):
        return num(e)
    if r["tolerance_kind"] == "absolute" or r["reference"] == 0:
        return num(e, 3)
    if e != 0 and abs(e) < 1e-6:
        return num(e, 3) + " rel."
    return f"{100 * e:+.3g} %".replace("-", "−")


def tolerance_text(r):
    tol = r["tolerance"]
    kind = r["tolerance_kind"]
    if kind == "relative":
        return f"±{num(100 * tol, 3)} %" if tol >= 1e-4 else f"±{num(tol, 3)} rel."
    if kind == "absolute":
        return f"±{num(tol, 3)}"
    return f"[{num(tol[0])}, {num(tol[1])}]"


def cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def slug(s):
    return "".join(c if c.isascii() and c.isalnum() else "_" for c in s)


def wrap(text):
    """A paragraph of the page, wrapped at 100 columns."""
    return textwrap.fill(" ".join(text.split()), width=100, break_on_hyphens=False)


def plot(case, curves, reference_label, out_dir):
    """One PNG of the case's curves (one panel each): ours solid, the reference dashed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(curves)
    fig, axes = plt.subplots(1, n, figsize=(5.2 * n, 3.4), squeeze=False)
    for ax, c in zip(axes[0], curves):
        ax.plot(c["x"], c["ours"], "-", lw=1.2, color="tab:blue", label="decohesion")
        ref = [(x, y) for x, y in zip(c["x"], c["reference"]) if math.isfinite(y)]
        if ref:
            ax.plot(
                [p[0] for p in ref],
                [p[1] for p in ref],
                "--",
                lw=1.4,
                color="tab:red",
                label=reference_label,
            )
        ax.set_xlabel(c["x_label"])
        ax.set_ylabel(c["y_label"])
        if n > 1:
            ax.set_title(c["name"], fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(case, fontsize=10)
    fig.tight_layout()
    path = out_dir / f"{slug(case)}.png"
    # No timestamp in the file: the same curves give the same bytes with the same matplotlib.
    fig.savefig(path, dpi=100, metadata={"Software": None})
    plt.close(fig)
    return path


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--dir", type=Path, default=ROOT / "out" / "validation")
    parser.add_argument("--cases", type=Path, default=ROOT / "docs" / "validation-cases.toml")
    parser.add_argument("--other", type=Path, default=ROOT / "docs" / "validation-other.md")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "src" / "validation.md")
    parser.add_argument(
        "--strict",
        action="store_true",
        help="fail if a case described in --cases recorded nothing",
    )
    parser.add_argument("--no-plots", action="store_true", help="write the tables only")
    args = parser.parse_args()

    described = tomllib.loads(args.cases.read_text(encoding="utf-8"))
    families = described.get("family", [])
    cases = described.get("case", {})
    records = load_records(args.dir)
    curves = load_curves(args.dir)

    # Cases in the order of the description file, then any undescribed ones by name.
    by_case = {}
    for r in records:
        by_case.setdefault(r["case"], []).append(r)
    order = [c for c in cases if c in by_case] + sorted(c for c in by_case if c not in cases)
    missing = [c for c in cases if c not in by_case]

    failed = []
    for r in records:
        ok = passes(r)
        if ok != r["pass"]:
            print(
                f"warning: {r['case']} / {r['quantity']}: the test recorded pass = {r['pass']}, "
                f"the numbers give {ok}",
                file=sys.stderr,
            )
        if not (ok and r["pass"]):
            failed.append(r)

    plots = {}
    plot_note = None
    if args.no_plots:
        plot_note = "plots not drawn (--no-plots)"
    else:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            plot_note = "plots not drawn: matplotlib is not installed for this Python"
    if plot_note is None:
        png_dir = args.out.parent / "validation"
        png_dir.mkdir(parents=True, exist_ok=True)
        for old in png_dir.glob("*.png"):
            if old.stem not in {slug(c) for c in curves}:
                old.unlink()
        for case in order:
            if case in curves:
                source = by_case[case][0]["source"]
                label = source if len(source) <= 48 else source.split(" (")[0]
                path = plot(case, curves[case], label, png_dir)
                plots[case] = path.relative_to(args.out.parent).as_posix()
    else:
        print(f"{plot_note}; the report has the tables only", file=sys.stderr)

    n_quantities = len(records)
    lines = [
        "# Validation",
        "",
        "<!-- Generated by scripts/validation_report.py: edit docs/validation-cases.toml, "
        "docs/validation-other.md or the tests, then run scripts/validation.sh. -->",
        "",
        wrap(
            "Every case below compares a result of the code with an independent reference: an "
            "analytic solution, a published law, or an independent computation. The tables are "
            "generated from the test suite itself: each test that makes such a comparison "
            "records, right where it asserts, the value it compares, the reference, its source "
            "and the tolerance it asserts (`tests/common/validation.rs`). One command runs both "
            "crates' integration tests and writes this page and its plots:"
        ),
        "",
        "```sh",
        COMMAND,
        "```",
        "",
        wrap(
            "(the integration tests with `DECOHESION_VALIDATION_DIR=out/validation`, then "
            "`scripts/validation_report.py`). The numbers are those of the last run committed "
            "with the page; CI regenerates it from its own `cargo test --release` and fails if "
            "a case fails, not if a number moved in its last digits. Why each tolerance is what "
            "it is, is said in the test (and summarised under each table). **error** is "
            "ours/reference − 1 for a relative tolerance or a band, ours − reference for an "
            "absolute one; a band [lo, hi] bounds our value itself."
        ),
        "",
        f"**{len(order)} cases, {n_quantities} compared quantities: "
        + ("all pass.**" if not failed else f"{len(failed)} FAIL.**"),
        "",
    ]
    if missing:
        lines += [
            "Described but not recorded in this run: "
            + ", ".join(f"`{c}`" for c in missing)
            + ".",
            "",
        ]
    if plot_note:
        lines += [f"*{plot_note[0].upper()}{plot_note[1:]}.*", ""]

    family_of = {c: cases.get(c, {}).get("family", "other") for c in order}
    all_families = families + (
        [{"id": "other", "title": "Other cases", "intro": ""}]
        if any(f == "other" for f in family_of.values())
        else []
    )
    lines += ["| family | cases | quantities | pass |", "|---|---|---|---|"]
    for fam in all_families:
        members = [c for c in order if family_of[c] == fam["id"]]
        rows = [r for c in members for r in by_case[c]]
        if rows:
            bad = sum(1 for r in rows if not (passes(r) and r["pass"]))
            lines.append(
                f"| {fam['title']} | {len(members)} | {len(rows)} | "
                + ("all" if not bad else f"**{bad} failed**")
                + " |"
            )
    lines.append("")
    for fam in all_families:
        members = [c for c in order if family_of[c] == fam["id"]]
        if not members:
            continue
        lines += [f"## {fam['title']}", ""]
        if fam.get("intro", "").strip():
            lines += [wrap(fam["intro"]), ""]
        lines += [
            "| case | quantity | reference | source | ours | error | tolerance | pass |",
            "|---|---|---|---|---|---|---|---|",
        ]
        for case in members:
            for r in by_case[case]:
                ok = passes(r) and r["pass"]
                lines.append(
                    "| "
                    + " | ".join(
                        cell(x)
                        for x in [
                            f"`{case}`",
                            r["quantity"],
                            num(r["reference"], digits(r)),
                            r["source"],
                            num(r["ours"], digits(r)),
                            error_text(r),
                            tolerance_text(r),
                            "yes" if ok else "**NO**",
                        ]
                    )
                    + " |"
                )
        lines.append("")
        for case in members:
            info = cases.get(case, {})
            test = info.get("test") or sorted({r["at"].split(":")[0] for r in by_case[case]})[0]
            title = info.get("title", case)
            what = info.get("what", "")
            item = " ".join(f"**`{case}`**: {title}. {what} (`{test}`)".split())
            lines.append(
                textwrap.fill(
                    item,
                    width=100,
                    initial_indent="- ",
                    subsequent_indent="  ",
                    break_on_hyphens=False,
                )
            )
        lines.append("")
        for case in members:
            if case in plots:
                lines += [f"![{case}: ours against the reference]({plots[case]})", ""]

    if args.other.exists():
        lines += [args.other.read_text(encoding="utf-8").rstrip(), ""]

    args.out.write_text("\n".join(lines), encoding="utf-8")
    print(
        f"{args.out.relative_to(ROOT) if args.out.is_relative_to(ROOT) else args.out}: "
        f"{len(order)} cases, {n_quantities} quantities, {len(failed)} failed, "
        f"{len(plots)} plots"
    )
    for r in failed:
        print(
            f"FAILED {r['case']} / {r['quantity']}: ours {r['ours']!r}, reference "
            f"{r['reference']!r}, tolerance {r['tolerance_kind']} {r['tolerance']!r} ({r['at']})",
            file=sys.stderr,
        )
    status = 1 if failed else 0
    if missing:
        print(f"no records for: {', '.join(missing)}", file=sys.stderr)
        if args.strict:
            status = 1
    return status


if __name__ == "__main__":
    sys.exit(main())
