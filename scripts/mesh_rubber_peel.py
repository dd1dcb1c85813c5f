#!/usr/bin/env python3
"""Meshes scenes/meshes/rubber_peel_strip.geo into scenes/meshes/rubber_peel_strip.msh (MSH 4.1
ASCII, 4-node tetrahedra, the physical groups `bond`, `grip` and `strip`), the mesh of
scenes/rubber_peel.toml. The .geo is the source; this writes the committed .msh from it.

    python3 -m pip install gmsh==4.15.2   # e.g. into a virtual environment
    python3 scripts/mesh_rubber_peel.py

Gmsh's 3-D Delaunay mesher with its default options; the same Gmsh version gives the same file.
"""
from pathlib import Path

import gmsh

ROOT = Path(__file__).resolve().parent.parent
GEO = ROOT / "scenes/meshes/rubber_peel_strip.geo"
MSH = ROOT / "scenes/meshes/rubber_peel_strip.msh"

gmsh.initialize()
try:
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.open(str(GEO))
    gmsh.model.mesh.generate(3)
    gmsh.write(str(MSH))
    types, tags, _ = gmsh.model.mesh.getElements(3)
    print(f"{MSH.relative_to(ROOT)}: {sum(len(t) for t in tags)} tetrahedra (Gmsh {gmsh.__version__})")
finally:
    gmsh.finalize()
