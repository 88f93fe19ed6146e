#!/usr/bin/env bash
# Tet-mesh benchmark: `hexmesh tetmesh CASE -o OUT --compare-cgal`, the variational optimizer
# against CGAL's perturb + exude on the same Delaunay-refined mesh, side by side.
#
# Cases (uniform cell size h; --scale S multiplies every h, e.g. 0.5 for 8x the tets):
#   sphere        analytic sphere, radius 1                        h 0.1
#   box-cylinder  CSG union of cases/box_cylinder (14 creases, 8 corners)   h 0.1
#   cylinder-stl  closed cylinder STL, 128 side facets, radius 0.5, height 1
#                 (2 sharp rims), written by this script              h 0.05
#   bean-stl      cases/bean/bean.stl (smooth, non-convex)           h 0.05
# For each it records, from the printed comparison table, per column (refined, CGAL
# perturb+exude, variational): tets, min / max dihedral angle, slivers (< 10 deg), min radius
# ratio, max boundary distance / h, seconds; and the peak RSS of the whole run from
# /usr/bin/time -v. Prints a markdown table; logs stay in the work dir.
#
# --cgal-sliver-bound B is passed on: the smallest dihedral angle CGAL's perturber aims at
# (0, the default: CGAL's own default of 12 degrees).
#
# Usage: bench/run_tetmesh.sh [--hexmesh PATH] [--work DIR] [--scale S] [--cgal-sliver-bound B]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
exe="$here/build/hexmesh/cli/hexmesh"
work=$(mktemp -d /tmp/hexmesh_tet_bench.XXXXXX)
scale=1
bound=0
while [ $# -gt 0 ]; do
  case "$1" in
    --hexmesh) exe="$2"; shift 2 ;;
    --work) work="$2"; shift 2 ;;
    --scale) scale="$2"; shift 2 ;;
    --cgal-sliver-bound) bound="$2"; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
mkdir -p "$work"
[ -x "$exe" ] || { echo "no hexmesh executable at $exe (build first, or --hexmesh PATH)" >&2; exit 2; }

python3 - "$work/cylinder.stl" <<'PY'
import math, sys
n = 128
def rim(k, z):
    k %= n
    return (0.5 * math.cos(2 * math.pi * k / n), 0.5 * math.sin(2 * math.pi * k / n), z)
tris = []
for k in range(n):
    tris += [(rim(k, 0), rim(k + 1, 0), rim(k + 1, 1)), (rim(k, 0), rim(k + 1, 1), rim(k, 1)),
             ((0, 0, 0), rim(k + 1, 0), rim(k, 0)), ((0, 0, 1), rim(k, 1), rim(k + 1, 1))]
with open(sys.argv[1], "w") as f:
    f.write("solid cylinder\n")
    for t in tris:
        f.write("facet normal 0 0 0\nouter loop\n")
        f.write("".join("vertex %.17g %.17g %.17g\n" % p for p in t))
        f.write("endloop\nendfacet\n")
    f.write("endsolid cylinder\n")
PY

h() { python3 -c "print($1 * $scale)"; }
cat > "$work/sphere.json" <<J
{"geometry": {"sphere": {"center": [0, 0, 0], "radius": 1}}, "tet_mesh": {"cell_size": $(h 0.1)}}
J
cat > "$work/box-cylinder.json" <<J
{"geometry": {"union": [{"box": {"center": [0, 0, 0], "size": [2, 2, 1.2]}},
  {"cylinder": {"center": [0, 0, 0.5], "radius": 0.6, "height": 1.4}}]},
 "tet_mesh": {"cell_size": $(h 0.1)}}
J
cat > "$work/cylinder-stl.json" <<J
{"geometry": {"file": "$work/cylinder.stl"}, "tet_mesh": {"cell_size": $(h 0.05)}}
J
cat > "$work/bean-stl.json" <<J
{"geometry": {"file": "$here/cases/bean/bean.stl", "voxel_size": 0.01}, "tet_mesh": {"cell_size": $(h 0.05)}}
J

echo "| case | h | column | tets | min dihedral | max dihedral | slivers < 10° | min radius ratio | max boundary dist / h | time (s) | peak RSS (MB) |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for name in sphere box-cylinder cylinder-stl bean-stl; do
  log="$work/$name.log"
  /usr/bin/time -v "$exe" tetmesh "$work/$name.json" -o "$work/$name.vtu" --compare-cgal --cgal-sliver-bound "$bound" > "$log" 2> "$work/$name.time"
  rss=$(awk '/Maximum resident set size/ {printf "%.0f", $NF / 1024}' "$work/$name.time")
  size=$(python3 -c "import json; print(json.load(open('$work/$name.json'))['tet_mesh']['cell_size'])")
  python3 - "$log" "$name" "$size" "$rss" <<'PY'
import sys
log, name, size, rss = sys.argv[1:]
text = open(log).read()
def row(label):  # the comparison table's row: the last one of that label, three columns
    found = ["-"] * 3
    for line in text.splitlines():
        if line.startswith("  " + label + " ") and len(line[2 + len(label):].split()) == 3:
            found = line[2 + len(label):].split()
    return found
rows = {k: row(k) for k in ["tets", "min dihedral angle (deg)", "max dihedral angle (deg)",
                            "slivers (dihedral < 10 deg)", "min radius ratio", "max boundary distance / h",
                            "time (s)"]}
for i, column in enumerate(["refined", "CGAL perturb+exude", "variational"]):
    cells = [rows[k][i] for k in rows]
    print(f"| {name} | {size} | {column} | " + " | ".join(cells) + f" | {rss if i == 2 else ''} |")
PY
done
echo
echo "logs: $work"
