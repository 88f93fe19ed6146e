#!/usr/bin/python3
"""Reads a mesh with meshio (an independent reader) and prints one JSON line: point count,
cells per type, boundary quads per tag, hexahedra whose corner frames are not all right-handed
(VTK order), and boundary quads whose normal points towards the origin (the test grids' bodies
are centred there, so an outward quad's normal points away from it: wall of an interior grid,
far field of an exterior one) per tag."""
import json, sys
import numpy as np
import meshio

mesh = meshio.read(sys.argv[1])
out = {"points": len(mesh.points), "cells": {}, "quads_per_tag": {}, "left_handed_hexes": 0,
       "quads_facing_origin_per_tag": {}}
tags = next(iter(mesh.cell_data.values())) if mesh.cell_data else None
p = mesh.points
for block, cells in enumerate(mesh.cells):
    out["cells"][cells.type] = out["cells"].get(cells.type, 0) + len(cells.data)
    if cells.type == "hexahedron":
        # Corner c's frame: edges to its three neighbours in VTK order.
        nb = [(1, 3, 4), (2, 0, 5), (3, 1, 6), (0, 2, 7), (7, 5, 0), (4, 6, 1), (5, 7, 2), (6, 4, 3)]
        bad = np.zeros(len(cells.data), bool)
        for c, (a, b, d) in enumerate(nb):
            x = p[cells.data[:, c]]
            det = np.einsum("ij,ij->i", np.cross(p[cells.data[:, a]] - x, p[cells.data[:, b]] - x), p[cells.data[:, d]] - x)
            bad |= det <= 0
        out["left_handed_hexes"] += int(bad.sum())
    if cells.type == "quad" and tags is not None:
        q = p[cells.data]
        normal = np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1])
        facing = np.einsum("ij,ij->i", normal, q.mean(axis=1)) < 0
        for t in np.unique(tags[block]):
            key = str(int(t))
            mine = tags[block] == t
            out["quads_per_tag"][key] = out["quads_per_tag"].get(key, 0) + int(mine.sum())
            out["quads_facing_origin_per_tag"][key] = int((facing & mine).sum())
print(json.dumps(out, sort_keys=True))
