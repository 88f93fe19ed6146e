#!/usr/bin/env bash
# Black-box pipeline benchmark: `hexmesh run CASE -o OUT`, end to end, under /usr/bin/time -v.
#
# What it runs. Four cases, each at the sizes of --sizes (default: about 32^3, 64^3 and
# 128^3 cells in total; "1M" is the project's target size), all with a boundary layer of
# first_height 0.005 and growth_ratio 1.15:
#
#   case        body                                  grid                                       layers
#   sphere-int  analytic sphere, radius 1             O-H, n = cells_per_edge, wall_cells n/2,    6
#                                                     core_size 0.45       -> n^3 + 6 n^2 n/2 = 4 n^3 cells
#   bean-int    cases/bean/bean.stl, voxel_size 0.01  O-H, same, core_size 0.4                    6
#   sphere-ext  analytic sphere, radius 1             exterior O-grid, far_field sphere size 10,  10
#                                                     wall_cells 2n        -> 6 n^2 2n = 12 n^3 cells
#   bean-ext    bean.stl, voxel_size 0.01             exterior O-grid, far_field sphere size 12   10
#
#   size  interior n (cells)     exterior n (cells)
#   32    20 (32 000)            14 (32 928)
#   64    40 (256 000)           28 (263 424)
#   1M    64 (1 048 576)         44 (1 022 208)     the project's target size
#   128   80 (2 048 000)         56 (2 107 392)
#
# The solver is the case default (newton-cg, theta 0.8, 10 optimize iterations), i.e. what a
# user gets from a case file without a "solver" key; --optimize-iterations K writes
# "solver": {"optimize_iterations": K} into every case (0: the grid as constructed, which
# `run` still optimizes if it has inverted cells). Each run is killed after --timeout
# seconds (default 1200) and reported as TIMEOUT; its address space is capped at
# --mem-limit-gb (default 16, prlimit --as) so that a run too big for the machine fails
# (reported as OUT OF MEMORY) instead of pushing the machine into swap or the OOM killer.
# For every run it records the per-phase times that `run` reports (quality.json "phases":
# geometry, grid, surface, optimization, quality, write), the wall and CPU (user+sys) time and the
# peak RSS ("Maximum resident set size") from /usr/bin/time -v, and from quality.json the
# min/mean scaled Jacobian, inverted cells and the fraction of wall cells whose first
# layer is within 10 % of first_height. It prints a markdown table at the end (and a line
# after every run to stderr), and keeps results.tsv, the case files, logs and grids in the
# work dir. The 1-minute load average before and after
# each run is recorded too: on a shared machine the wall times are only as good as that.
# Use one work dir per concurrent invocation (the binary snapshot is rewritten at start).
#
# The binary and its build-tree shared libraries are first copied into the work dir and run
# from there (LD_LIBRARY_PATH overrides their RUNPATH), so a rebuild of the build tree during
# the benchmark cannot change or break the binary under test.
#
# Reproduce (from the repository root, Release build in build/):
#   bash bench/run_pipeline.sh               # everything: hours (a 128^3 run takes 12-20+ min
#                                            # and ~12 GB with the default solver)
#   bash bench/run_pipeline.sh --sizes "32 64"                   # the small and medium sizes
#   bash bench/run_pipeline.sh --sizes 128 --cases sphere-int --timeout 1200
#   bash bench/run_pipeline.sh --sizes "64 1M" --optimize-iterations 0   # construction only
#   HEXMESH=/work/build/hexmesh/cli/hexmesh bash bench/run_pipeline.sh --workdir /tmp/hxbench
#   bash bench/run_pipeline.sh --table /tmp/hxbench/results.tsv  # print the table of past runs
# Needs: bash, GNU time (/usr/bin/time), coreutils timeout and stdbuf, util-linux prlimit, jq.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(dirname "$here")"
HEXMESH="${HEXMESH:-$repo/build/hexmesh/cli/hexmesh}"
sizes="32 64 128"
cases="sphere-int sphere-ext bean-int bean-ext"
timeout_s=1200
mem_limit_gb=16
optimize_iterations=""
workdir=""
table_only=""

usage() { sed -n '2,/^# Needs:/p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit "${1:-0}"; }
while (($#)); do
    case "$1" in
        --sizes) sizes="$2"; shift 2 ;;
        --cases) cases="$2"; shift 2 ;;
        --timeout) timeout_s="$2"; shift 2 ;;
        --workdir) workdir="$2"; shift 2 ;;
        --mem-limit-gb) mem_limit_gb="$2"; shift 2 ;;
        --optimize-iterations) optimize_iterations="$2"; shift 2 ;;
        --table) table_only="$2"; shift 2 ;;
        -h|--help) usage 0 ;;
        *) echo "run_pipeline.sh: unknown argument $1" >&2; usage 1 ;;
    esac
done

# Markdown table of a results.tsv.
print_table() {
    echo "| case | n | wall cells | cells | status | geometry (s) | grid (s) | surface (s) | optimization (s) | quality (s) | write (s) | wall total (s) | CPU user+sys (s) | peak RSS (MB) | min SJ | mean SJ | inverted | first layer within 10 % | load avg start/end |"
    echo "|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    tail -n +2 "$1" | while IFS=$'\t' read -r name n w cells status geo grid surf opt qual wr wall cpu rss minsj meansj inv fl load; do
        echo "| $name | $n | $w | $cells | $status | $geo | $grid | $surf | $opt | $qual | $wr | $wall | $cpu | $rss | $minsj | $meansj | $inv | $fl | ${load:--} |"
    done
}
if [[ -n "$table_only" ]]; then print_table "$table_only"; exit 0; fi

for tool in /usr/bin/time timeout stdbuf prlimit jq; do
    command -v "$tool" >/dev/null || { echo "run_pipeline.sh: needs $tool" >&2; exit 1; }
done
[[ -x "$HEXMESH" ]] || { echo "run_pipeline.sh: no executable $HEXMESH (set HEXMESH)" >&2; exit 1; }
[[ -n "$workdir" ]] || workdir="$(mktemp -d /tmp/hexmesh-bench.XXXXXX)"
mkdir -p "$workdir/bin"

# Snapshot of the binary and of the shared libraries it loads from outside the system dirs.
cp "$HEXMESH" "$workdir/bin/hexmesh"
ldd "$HEXMESH" | awk '$2 == "=>" && $3 ~ /^\// && $3 !~ /^\/(usr\/)?lib/ {print $3}' |
    while read -r lib; do
        cp "$lib" "$workdir/bin/"
        # The module MeshSdf loads at run time (OpenVDB) lives beside libhexmesh_surface.so.
        module="$(dirname "$lib")/libhexmesh_openvdb.so"
        if [[ -f "$module" ]]; then cp "$module" "$workdir/bin/"; fi
    done
export LD_LIBRARY_PATH="$workdir/bin${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
bin="$workdir/bin/hexmesh"
stl="$repo/cases/bean/bean.stl"

tsv="$workdir/results.tsv"
[[ -f "$tsv" ]] || printf 'case\tn\twall_cells\tcells\tstatus\tgeometry\tgrid\tsurface\toptimization\tquality\twrite\twall\tcpu\trss_mb\tmin_sj\tmean_sj\tinverted\tfirst_layer_10pct\tload\n' >"$tsv"

# n for a size label: interior 4 n^3 cells, exterior 12 n^3 cells.
n_for() {  # domain size
    case "$1:$2" in
        int:32) echo 20 ;; int:64) echo 40 ;; int:1M) echo 64 ;; int:128) echo 80 ;;
        ext:32) echo 14 ;; ext:64) echo 28 ;; ext:1M) echo 44 ;; ext:128) echo 56 ;;
        *) echo "run_pipeline.sh: size $2: expected 32, 64, 1M or 128" >&2; exit 1 ;;
    esac
}

write_case() {  # name n file
    local name="$1" n="$2" file="$3" geometry solver=""
    [[ -n "$optimize_iterations" ]] && solver="
  \"solver\": {\"optimize_iterations\": $optimize_iterations},"
    case "$name" in
        sphere-*) geometry='{"sphere": {"center": [0, 0, 0], "radius": 1.0}}' ;;
        bean-*) geometry="{\"file\": \"$stl\", \"voxel_size\": 0.01}" ;;
    esac
    case "$name" in
        sphere-int|bean-int)
            local core=0.45; [[ "$name" == bean-int ]] && core=0.4
            cat >"$file" <<EOF
{
  "geometry": $geometry,
  "grid": {"topology": "o-h", "cells_per_edge": $n, "wall_cells": $((n / 2)), "core_size": $core},
  "boundary_layer": {"first_height": 0.005, "growth_ratio": 1.15, "layers": 6},$solver
  "outputs": ["vtk"]
}
EOF
            ;;
        sphere-ext|bean-ext)
            local far=10; [[ "$name" == bean-ext ]] && far=12
            cat >"$file" <<EOF
{
  "geometry": $geometry,
  "domain": "exterior",
  "far_field": {"shape": "sphere", "size": $far},
  "grid": {"cells_per_edge": $n, "wall_cells": $((2 * n))},
  "boundary_layer": {"first_height": 0.005, "growth_ratio": 1.15, "layers": 10},$solver
  "outputs": ["vtk"]
}
EOF
            ;;
        *) echo "run_pipeline.sh: unknown case $name" >&2; exit 1 ;;
    esac
}

run_one() {  # name size
    local name="$1" size="$2" domain="${1#*-}" n w cells dir status rc
    n="$(n_for "$domain" "$size")"
    if [[ "$domain" == int ]]; then w=$((n / 2)); cells=$((n * n * n + 6 * n * n * w));
    else w=$((2 * n)); cells=$((6 * n * n * w)); fi
    dir="$workdir/$name-$size${optimize_iterations:+-opt$optimize_iterations}"
    rm -rf "$dir" && mkdir -p "$dir"
    write_case "$name" "$n" "$dir/case.json"
    # stdbuf -oL: the log lines reach run.log as they are printed, so a killed run still
    # shows how far it got (phases done, optimizer iterations).
    echo "== $name size $size: n $n, wall_cells $w, $cells cells ($(date +%T))" >&2
    local load0 load1
    load0="$(cut -d' ' -f1 /proc/loadavg)"
    set +e
    /usr/bin/time -v -o "$dir/time.txt" \
        timeout --kill-after=30 "$timeout_s" \
        prlimit --as=$((mem_limit_gb * 1024 * 1024 * 1024)) \
        stdbuf -oL "$bin" run "$dir/case.json" -o "$dir/out" >"$dir/run.log" 2>&1
    rc=$?
    set -e
    load1="$(cut -d' ' -f1 /proc/loadavg)"
    local rss wall cpu
    rss="$(awk -F': ' '/Maximum resident set size/ {printf "%.0f", $2 / 1024}' "$dir/time.txt")"
    wall="$(awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, t, ":"); s = 0;
             for (i = 1; i <= n; i++) s = s * 60 + t[i]; printf "%.1f", s}' "$dir/time.txt")"
    cpu="$(awk -F': ' '/User time/ {u = $2} /System time/ {s = $2} END {printf "%.1f", u + s}' "$dir/time.txt")"
    if [[ $rc -eq 124 || $rc -eq 137 ]]; then status="TIMEOUT (${timeout_s} s)"
    elif grep -qi 'bad_alloc\|cannot allocate' "$dir/run.log"; then status="OUT OF MEMORY (> ${mem_limit_gb} GB address space)"
    elif [[ $rc -ne 0 ]]; then status="FAILED (exit $rc)"
    else status="ok"; fi
    local q="$dir/out/quality.json" geo=- grid=- surf=- opt=- qual=- wr=- minsj=- meansj=- inv=- fl=-
    if [[ $rc -eq 0 && -f "$q" ]]; then
        read -r geo grid surf opt qual wr minsj meansj inv fl < <(jq -r '[
            (.phases.geometry // 0 | . * 100 | round / 100),
            (.phases.grid // 0 | . * 100 | round / 100),
            (.phases.surface // 0 | . * 100 | round / 100),
            (.phases.optimization // 0 | . * 100 | round / 100),
            (.phases.quality // 0 | . * 100 | round / 100),
            (.phases.write // 0 | . * 100 | round / 100),
            (.min_scaled_jacobian * 1000 | round / 1000),
            (.mean_scaled_jacobian * 1000 | round / 1000),
            .inverted_cells,
            ((.wall.first_layer_thickness.fraction_within_10_percent // 0) * 1000 | round / 10 | tostring + " %")
          ] | map(tostring) | join(" ")' "$q")
    else
        # Phases finished before the kill or failure, from the log lines "  PHASE ... N s".
        grep -E '^  (geometry|grid|surface|optimization|quality|write)\b.* s$' "$dir/run.log" >"$dir/phases.txt" || true
        for p in geometry grid surface optimization quality write; do
            local v; v="$(awk -v p="$p" '$1 == p {print $(NF-1)}' "$dir/phases.txt" | tail -1)"
            [[ -n "$v" ]] && printf -v "$(case $p in geometry) echo geo;; grid) echo grid;; surface) echo surf;; optimization) echo opt;; quality) echo qual;; write) echo wr;; esac)" '%s' "$v"
        done
    fi
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' \
        "$name${optimize_iterations:+ (optimize_iterations $optimize_iterations)}" "$n" "$w" "$cells" "$status" "$geo" "$grid" "$surf" "$opt" "$qual" "$wr" "$wall" "$cpu" \
        "$rss" "$minsj" "$meansj" "$inv" "$fl" "$load0/$load1" >>"$tsv"
    echo "   $status: wall $wall s, CPU $cpu s, peak RSS $rss MB, optimization $opt s" >&2
}

echo "work dir: $workdir (binary snapshot of $HEXMESH)" >&2
for size in $sizes; do
    for name in $cases; do run_one "$name" "$size"; done
done
print_table "$tsv"
