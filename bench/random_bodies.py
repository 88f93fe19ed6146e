#!/usr/bin/python3
"""Writes random closed genus-0 bodies that are not star-shaped, as binary STL files, for
trying `hexmesh run` on bodies it was never tuned on (bench/run_bodies.sh --bodies DIR).

Each body is a core (an ellipsoid, or a box with sharp edges) with 3 to 6 limbs: chains of
two capsules, bent by up to 70 degrees at the knee, 0.05 to 0.14 thick, reaching 0.5 to 1.1
out from the core. Limbs keep clear of one another (a limb touching another would make a
handle), and the union is contoured (VTK flying edges, 150 cells along the longest side);
a body whose contour is not one closed genus-0 piece is drawn again. Deterministic: body k
of seed s is the same on every machine.

usage: /usr/bin/python3 bench/random_bodies.py OUT_DIR [--count N] [--seed S]
Needs Debian's python3-vtk9 (and its numpy).
"""
import argparse
import math
import os

import numpy as np
import vtk
from vtk.util import numpy_support


def segment_distance(p, a, b):
    """Distance of the points p (n x 3) to the segment ab."""
    ab = b - a
    t = np.clip(((p - a) @ ab) / (ab @ ab), 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * ab), axis=1)


def segments_distance(a, b, c, d, samples=64):
    """Distance between the segments ab and cd (sampled along ab, exact across cd)."""
    t = np.linspace(0.0, 1.0, samples)[:, None]
    return segment_distance(a + t * (b - a), c, d).min()


def unit(v):
    return v / np.linalg.norm(v)


def random_direction(rng):
    return unit(rng.normal(size=3))


def outer(limb, s):
    """Segment s of a limb's two; of the first, only the part beyond 45 % of it from the root
    (where two limbs' roots may touch)."""
    a, b = limb["points"][s], limb["points"][s + 1]
    return (a + 0.45 * (b - a) if s == 0 else a), b


def draw_body(rng):
    """One body: its core and limbs (a dict), or None when its limbs could not be kept apart."""
    core = {"box": bool(rng.random() < 0.5), "half": rng.uniform(0.25, 0.55, size=3)}
    limbs = []
    for _ in range(int(rng.integers(3, 7))):
        for _attempt in range(40):
            direction = random_direction(rng)
            # Where the ray from the centre leaves the core (ellipsoid or box), a little inside.
            if core["box"]:
                reach = np.min(core["half"] / np.maximum(np.abs(direction), 1e-9))
            else:
                reach = 1.0 / np.linalg.norm(direction / core["half"])
            root = 0.7 * reach * direction
            radius = rng.uniform(0.05, 0.14)
            first = rng.uniform(0.25, 0.55) + 0.3 * reach
            knee = root + first * direction
            bend = math.radians(rng.uniform(0.0, 70.0))
            side = unit(np.cross(direction, random_direction(rng)))
            second_dir = math.cos(bend) * direction + math.sin(bend) * side
            foot = knee + rng.uniform(0.25, 0.55) * second_dir
            limb = {"points": [root, knee, foot], "radius": radius}
            # Clear of the other limbs outside the core (their roots may meet inside it).
            clear = all(segments_distance(*outer(limb, s), *outer(other, t))
                        >= 0.08 + radius + other["radius"]
                        for other in limbs for s in range(2) for t in range(2))
            # The foot must not come back into the core (that would close a loop).
            half = core["half"] + radius + 0.05
            clear = clear and not (np.all(np.abs(foot) < half) if core["box"]
                                   else np.linalg.norm(foot / half) < 1.0)
            if clear:
                limbs.append(limb)
                break
        else:
            return None
    return {"core": core, "limbs": limbs, "rotation": rotation(rng)}


def rotation(rng):
    """A random rotation matrix (QR of a Gaussian matrix, signs fixed)."""
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q


def field(body, points):
    """Signed distance-like value of the body (negative inside) at the points (n x 3)."""
    half = body["core"]["half"]
    if body["core"]["box"]:
        q = np.abs(points) - half
        value = np.linalg.norm(np.maximum(q, 0.0), axis=1) + np.minimum(q.max(axis=1), 0.0)
    else:
        value = (np.linalg.norm(points / half, axis=1) - 1.0) * half.min()
    for limb in body["limbs"]:
        p = limb["points"]
        for s in range(2):
            value = np.minimum(value, segment_distance(points, p[s], p[s + 1]) - limb["radius"])
    return value


def contour(body, cells=150):
    """The surface value = 0 of the body, rotated, as vtkPolyData (cleaned triangles)."""
    lo = -body["core"]["half"] - 0.05
    hi = body["core"]["half"] + 0.05
    for limb in body["limbs"]:
        for p in limb["points"]:
            lo = np.minimum(lo, p - limb["radius"] - 0.05)
            hi = np.maximum(hi, p + limb["radius"] + 0.05)
    step = (hi - lo).max() / cells
    dims = np.ceil((hi - lo) / step).astype(int) + 3
    lo = lo - step
    axes = [lo[i] + step * np.arange(dims[i]) for i in range(3)]
    z, y, x = np.meshgrid(axes[2], axes[1], axes[0], indexing="ij")  # x fastest, as VTK
    values = field(body, np.column_stack([x.ravel(), y.ravel(), z.ravel()]))
    image = vtk.vtkImageData()
    image.SetDimensions(*[int(d) for d in dims])
    image.SetOrigin(*lo)
    image.SetSpacing(step, step, step)
    image.GetPointData().SetScalars(numpy_support.numpy_to_vtk(values, deep=True))
    surface = vtk.vtkFlyingEdges3D()
    surface.SetInputData(image)
    surface.SetValue(0, 0.0)
    surface.ComputeNormalsOff()
    clean = vtk.vtkCleanPolyData()
    clean.SetInputConnection(surface.GetOutputPort())
    clean.Update()
    out = clean.GetOutput()
    points = numpy_support.vtk_to_numpy(out.GetPoints().GetData()) @ body["rotation"].T
    out.GetPoints().SetData(numpy_support.numpy_to_vtk(np.ascontiguousarray(points), deep=True))
    return out


def closed_genus(poly):
    """(pieces, genus) of a triangle surface, or (pieces, None) when it has open or
    non-manifold edges."""
    edges = vtk.vtkFeatureEdges()
    edges.SetInputData(poly)
    edges.BoundaryEdgesOn()
    edges.NonManifoldEdgesOn()
    edges.FeatureEdgesOff()
    edges.ManifoldEdgesOff()
    edges.Update()
    pieces = vtk.vtkPolyDataConnectivityFilter()
    pieces.SetInputData(poly)
    pieces.SetExtractionModeToAllRegions()
    pieces.Update()
    count = pieces.GetNumberOfExtractedRegions()
    if edges.GetOutput().GetNumberOfCells() > 0:
        return count, None
    faces = poly.GetNumberOfPolys()
    euler = poly.GetNumberOfPoints() - 3 * faces // 2 + faces
    return count, (2 * count - euler) // 2


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("--count", type=int, default=10)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    rng = np.random.default_rng(a.seed)
    made = 0
    while made < a.count:
        body = draw_body(rng)
        if body is None:
            continue
        poly = contour(body)
        pieces, genus = closed_genus(poly)
        if pieces != 1 or genus != 0:
            continue
        made += 1
        name = os.path.join(a.out, f"random{a.seed}_{made:02d}.stl")
        writer = vtk.vtkSTLWriter()
        writer.SetInputData(poly)
        writer.SetFileTypeToBinary()
        writer.SetFileName(name)
        writer.Write()
        kind = "box" if body["core"]["box"] else "ellipsoid"
        print(f"{name}: {kind} core, {len(body['limbs'])} limbs, {poly.GetNumberOfPolys()} triangles")


if __name__ == "__main__":
    main()
