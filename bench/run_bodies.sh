#!/usr/bin/env bash
# Black-box grids of the shared bodies at about 150 000 cells: `hexmesh run` on every surface
# of ../shared/data/bodies (or --bodies DIR), inside and out, each case naming only the file,
# the domain, a boundary layer (first height 0.2 % of the body's largest extent, growth 1.2,
# 5 layers) and the cell counts:
#   exterior  grid.cells_per_edge 23 (wall_cells twice that by default): 6 x 23^2 x 46 = 146 004 cells
#   interior  grid.cells_per_edge 34, wall_cells 17: 34^3 + 6 x 34^2 x 17 = 157 216 cells
# Each run writes with --keep-invalid, so that a refused grid's quality.json gives its time
# too. Prints a markdown table, one row per run: outcome (valid, inverted cells, or the
# one-line refusal), cells, min / mean scaled Jacobian, first layer within 10 % of the target,
# surface to wall (wall cells, max), seconds per phase (wall: the sphere map route's; levels: an
# exterior retry's lines spread on levels; rest: quality and writing) summed over the run (a
# retry's grid adds to the same phases), total, and peak memory (quality.json). Logs stay in
# the work dir.
#
# Usage: bench/run_bodies.sh [--hexmesh PATH] [--work DIR] [--bodies DIR] [--only a,b]
#                            [--domains exterior,interior] [--timeout S]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
exe="$here/build/hexmesh/cli/hexmesh"
work=""
bodies="$here/../shared/data/bodies"
only=""
domains="exterior,interior"
timeout=1800
while [ $# -gt 0 ]; do
  case "$1" in
    --hexmesh) exe="$2"; shift 2 ;;
    --work) work="$2"; shift 2 ;;
    --bodies) bodies="$2"; shift 2 ;;
    --only) only="$2"; shift 2 ;;
    --domains) domains="$2"; shift 2 ;;
    --timeout) timeout="$2"; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
[ -n "$work" ] || work=$(mktemp -d /tmp/hexmesh_bodies_bench.XXXXXX)
mkdir -p "$work"
work=$(cd "$work" && pwd)
[ -x "$exe" ] || { echo "no hexmesh executable at $exe (build first, or --hexmesh PATH)" >&2; exit 2; }
[ -d "$bodies" ] || { echo "no bodies folder at $bodies (--bodies DIR)" >&2; exit 2; }
bodies=$(cd "$bodies" && pwd)  # the cases, written in $work, name the files absolutely
shopt -s nocaseglob

echo "| body | domain | outcome | cells | min SJ | mean SJ | first layer within 10 % | cells through the wall | surface to wall | geometry s | wall s | grid s | surface s | optimization s | polish s | levels s | rest s | total s | peak MB |"
echo "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for file in "$bodies"/*.off "$bodies"/*.obj "$bodies"/*.stl; do
  [ -f "$file" ] || continue
  name=$(basename "${file%.*}")
  if [ -n "$only" ] && [[ ",$only," != *",$name,"* ]]; then continue; fi
  for domain in ${domains//,/ }; do
    run="$work/${name}_$domain"
    if ! python3 - "$file" "$domain" "$run.json" <<'PY'
import json, struct, sys

path, domain, out = sys.argv[1:4]
def points(path):
    """The vertices of an OFF, OBJ or STL (ASCII or binary) surface."""
    data = open(path, "rb").read()
    if path.lower().endswith(".stl"):
        n = struct.unpack_from("<I", data, 80)[0] if len(data) >= 84 else -1
        if len(data) != 84 + 50 * n:  # not the size of a binary STL of n triangles: ASCII
            return [tuple(map(float, l.split()[1:4]))
                    for l in data.decode("latin-1").splitlines()
                    if l.strip().startswith("vertex")]
        return [struct.unpack_from("<3f", data, 84 + 50 * t + 12 * (k + 1)) for t in range(n)
                for k in range(3)]
    lines = [l.split("#")[0].split() for l in data.decode("latin-1").splitlines()]
    lines = [l for l in lines if l]
    if path.lower().endswith(".obj"):
        return [tuple(map(float, l[1:4])) for l in lines if l[0] == "v"]
    head = lines[0][1:] if len(lines[0]) > 1 else lines[1]
    first = 1 if len(lines[0]) > 1 else 2
    return [tuple(map(float, l[:3])) for l in lines[first:first + int(head[0])]]
p = points(path)
extent = max(max(q[a] for q in p) - min(q[a] for q in p) for a in range(3))
grid = {"cells_per_edge": 23} if domain == "exterior" else {"cells_per_edge": 34, "wall_cells": 17}
json.dump({"geometry": {"file": path}, "domain": domain, "grid": grid,
           "boundary_layer": {"first_height": 0.002 * extent, "growth_ratio": 1.2, "layers": 5}},
          open(out, "w"), indent=1)
PY
    then
      printf '| %s | %s | could not read the surface for its extent |%s\n' "$name" "$domain" "$(printf ' |%.0s' $(seq 16))"
      continue
    fi
    rm -rf "$run"
    set +e
    timeout "$timeout" "$exe" run "$run.json" -o "$run" --keep-invalid > "$run.log" 2>&1
    code=$?
    set -e
    python3 - "$run" "$code" "$name" "$domain" <<'PY'
import json, os, sys

run, code, name, domain = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
q = os.path.join(run, "quality.json")
if not os.path.exists(q):
    log = open(run + ".log").read().strip().splitlines()
    why = "timed out" if code == 124 else (log[-1] if log else "exit %d" % code)
    print("| %s | %s | %s |%s" % (name, domain, why.replace("|", "/")[:160], " |" * 16))
    sys.exit(0)
j = json.load(open(q))
w = j.get("wall") or {}
outcome = ("valid" if j["valid"] else "%d inverted" % j["inverted_cells"] if j["inverted_cells"]
           else "refused by the solver's checks")
phases = j.get("phases", {})
listed = ["geometry", "wall", "grid", "surface", "optimization", "polish", "levels"]
def seconds(key):  # the phase's seconds; "wall" also as "wall (sphere map)"
    return [v for k, v in phases.items() if k == key or k.startswith(key + " (")]
def s(key):
    return "%.1f" % sum(seconds(key)) if seconds(key) else ""
total = j.get("seconds_total", sum(phases.values()))
rest = total - sum(sum(seconds(k)) for k in listed)  # quality and writing
def f(x, form):
    return form % x if x is not None else ""
layer = (w.get("first_layer_thickness") or {}).get("fraction_within_10_percent")
through = (w.get("first_layer_thickness") or {}).get("cells_through_wall")
reach = (w.get("surface_to_wall_in_cells") or {}).get("max")
print("| %s | %s | %s | %d | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %.1f | %.1f | %s |" % (
    name, domain, outcome, j["cells"], f(j.get("min_scaled_jacobian"), "%.4f"),
    f(j.get("mean_scaled_jacobian"), "%.4f"),
    "%.1f %%" % (100 * layer) if layer is not None else "", f(through, "%d"),
    "%.2f" % reach if reach is not None else "",
    s("geometry"), s("wall"), s("grid"), s("surface"), s("optimization"), s("polish"), s("levels"),
    rest, total, f(j.get("peak_memory_mb"), "%.0f")))
PY
  done
done
echo
echo "logs: $work"
