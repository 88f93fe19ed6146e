#!/usr/bin/env python3
"""Writes bean.stl: a non-convex, star-shaped body (an ellipsoid 1.2 x 0.8 x 0.7 with a dent).

Run from this folder: python3 make_bean.py. Deterministic; the committed bean.stl is its
output (binary STL). The surface is r(d) * d over unit directions d of a subdivided
octahedron, r = ellipsoid radius * (1 - 0.3 exp(-|d - (0,1,0)|^2 / 0.35)): a dent in the +y side
deep enough to make the body clearly concave there, while every ray from the origin crosses
the surface once.
"""
import math
import struct

A, B, C = 1.2, 0.8, 0.7
DENT, WIDTH = 0.3, 0.35
LEVEL = 24  # subdivisions of each octahedron edge: 8 * LEVEL^2 triangles


def radius(d):
    e = 1.0 / math.sqrt((d[0] / A) ** 2 + (d[1] / B) ** 2 + (d[2] / C) ** 2)
    far = (d[0]) ** 2 + (d[1] - 1) ** 2 + d[2] ** 2
    return e * (1 - DENT * math.exp(-far / WIDTH))


def point(v):
    n = math.sqrt(sum(c * c for c in v))
    d = tuple(c / n for c in v)
    r = radius(d)
    return tuple(r * c for c in d)


triangles = []
for sx in (-1, 1):
    for sy in (-1, 1):
        for sz in (-1, 1):
            corners = [(sx, 0, 0), (0, sy, 0), (0, 0, sz)]
            def at(i, j):  # barycentric lattice point of the face
                k = LEVEL - i - j
                return tuple((i * corners[0][c] + j * corners[1][c] + k * corners[2][c]) / LEVEL
                             for c in range(3))
            flip = sx * sy * sz < 0
            for i in range(LEVEL):
                for j in range(LEVEL - i):
                    tris = [(at(i, j), at(i + 1, j), at(i, j + 1))]
                    if i + j + 1 < LEVEL:
                        tris.append((at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)))
                    for t in tris:
                        t = [point(v) for v in t]
                        # corners[0] -> corners[1] -> corners[2] is counter-clockwise seen from
                        # outside when sx*sy*sz > 0; the lattice triangle (i,j),(i+1,j),(i,j+1)
                        # runs corners[2] -> corners[0] -> corners[1], the same orientation.
                        triangles.append((t[0], t[2], t[1]) if flip else tuple(t))


def normal(t):
    u = [t[1][c] - t[0][c] for c in range(3)]
    v = [t[2][c] - t[0][c] for c in range(3)]
    n = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    length = math.sqrt(sum(c * c for c in n)) or 1
    return tuple(c / length for c in n)


with open("bean.stl", "wb") as out:
    out.write(b"bean written by make_bean.py".ljust(80, b" "))
    out.write(struct.pack("<I", len(triangles)))
    for t in triangles:
        out.write(struct.pack("<3f", *normal(t)))
        for v in t:
            out.write(struct.pack("<3f", *v))
        out.write(b"\0\0")
print(f"bean.stl: {len(triangles)} triangles")
