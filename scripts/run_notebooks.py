#!/usr/bin/env python3
"""Executes every notebook of examples/python/ with nbclient (a fresh kernel each, run from the
repository's root) and fails on the first cell that raises; also fails when a committed notebook
carries outputs or execution counts, which the repository keeps stripped.

    python3 scripts/run_notebooks.py [NOTEBOOK ...]

Needs nbclient, nbformat and ipykernel in the interpreter that runs it, and the decohesion package.
"""

import sys
from pathlib import Path

import nbformat
from nbclient import NotebookClient

ROOT = Path(__file__).resolve().parents[1]


def main(paths):
    notebooks = [Path(p) for p in paths] or sorted((ROOT / "examples" / "python").glob("*.ipynb"))
    if not notebooks:
        print("run_notebooks: no notebook in examples/python/", file=sys.stderr)
        return 1
    failed = 0
    for path in notebooks:
        nb = nbformat.read(path, as_version=4)
        dirty = [i for i, c in enumerate(nb.cells)
                 if c.cell_type == "code" and (c.get("outputs") or c.get("execution_count"))]
        if dirty:
            print(f"{path}: cells {dirty} carry outputs: strip them before committing "
                  f"(jupyter nbconvert --clear-output --inplace {path})", file=sys.stderr)
            failed += 1
            continue
        client = NotebookClient(nb, timeout=600, kernel_name="python3",
                                resources={"metadata": {"path": str(ROOT)}})
        try:
            client.execute()
        except Exception as e:  # nbclient's CellExecutionError names the cell and the traceback
            print(f"{path}: {e}", file=sys.stderr)
            failed += 1
            continue
        print(f"{path}: {len(nb.cells)} cells executed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
