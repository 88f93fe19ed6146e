#!/usr/bin/env python3
"""Writes part.obj: a capsule along x (radius 0.5, straight part from x = -0.5 to 0.5).

Run from this folder: python3 make_part.py. Deterministic; the committed part.obj is its
output. 24 segments around, 6 rings per hemisphere: 576 triangles, counter-clockwise seen
from outside.
"""
import math

R, HALF, AROUND, RINGS = 0.5, 0.5, 24, 6

points, faces = [], []
rings = []  # point ids of each ring, from the -x pole side to the +x pole side
points.append((-HALF - R, 0.0, 0.0))
for side, sign in ((0, -1), (1, 1)):
    for k in (range(1, RINGS + 1) if side == 0 else range(RINGS, 0, -1)):
        polar = math.pi / 2 * k / RINGS  # angle from the pole
        x = sign * (HALF + R * math.cos(polar))
        ring = []
        for j in range(AROUND):
            phi = 2 * math.pi * j / AROUND
            ring.append(len(points))
            points.append((x, R * math.sin(polar) * math.cos(phi), R * math.sin(polar) * math.sin(phi)))
        rings.append(ring)
points.append((HALF + R, 0.0, 0.0))
west, east = 0, len(points) - 1

for j in range(AROUND):
    n = (j + 1) % AROUND
    faces.append((west, rings[0][n], rings[0][j]))
    for k in range(len(rings) - 1):
        a, b = rings[k][j], rings[k][n]
        c, d = rings[k + 1][n], rings[k + 1][j]
        faces.append((a, b, c))
        faces.append((a, c, d))
    faces.append((east, rings[-1][j], rings[-1][n]))

with open("part.obj", "w") as out:
    out.write("# capsule written by make_part.py\n")
    for p in points:
        out.write("v %.9g %.9g %.9g\n" % p)
    for f in faces:
        out.write("f %d %d %d\n" % (f[0] + 1, f[1] + 1, f[2] + 1))
