#!/usr/bin/env bash
# Export throughput benchmark: `hexmesh export GRID --format F -o OUT` for every format, timed
# from outside (black box), with the read of GRID measured separately and subtracted.
#
# What it runs.
#   1. Unless --grid is given, the grid: `hexmesh run CASE -o WORK/grid` on the sphere interior
#      O-H case below, without optimization (4 n^3 cells; n = 136 -> 10 061 824 cells, the
#      "10 M-cell grid"; grid.vtm + 7 .vts, 339 MB, uncompressed; ~30 s on 2 cores):
#        {"geometry": {"sphere": {"radius": 1}},
#         "grid": {"cells_per_edge": n, "wall_cells": n/2, "core_size": 0.45},
#         "boundary_layer": {"first_height": 0.001, "growth_ratio": 1.1, "layers": 8},
#         "solver": {"optimize_iterations": 0}}
#   2. The read alone, --read-runs times (default 3):
#        hexmesh export GRID --format plot3d-c -o WORK/out/.
#      `export` reads GRID before it checks OUT, then refuses the empty file name "." with
#      exit 1 ("expected a file name to write") having written nothing, so this is the whole
#      command (start, read, teardown) minus the writer. The median (the lower middle one for an even
#      count) is the "read" time.
#   3. For each --formats entry (default: all 17 names of `hexmesh export --help`):
#        /usr/bin/time -v hexmesh export GRID --format F -o WORK/out/grid.EXT
#      recording wall ("Elapsed"), CPU (user + sys) and peak RSS ("Maximum resident set
#      size"); the size of everything written (du -sb of the file, its .patches.json and .nmf
#      side files for Plot3D, .mapbc for ugrid, or the whole case folder for openfoam); then deletes the output.
#      write (s) = wall - read; MB/s = size (10^6 bytes) / write (s). The same with CPU
#      time (user + sys, the read's median CPU subtracted): "write CPU" and "MB/s per CPU s",
#      the steadier figure on a shared machine (it leaves out the time spent waiting for a
#      core; for a writer that waits on nothing else, wall = CPU on an idle machine).
#   4. The write phase itself, if strace is installed (NO_STRACE=1 turns it off): every export
#      runs under `strace -f --seccomp-bpf -ttt -e trace=mkdir,openat,exit_group`, which stops
#      the process only at those (rare) system calls, not at its reads and writes; "write
#      phase" = time of exit_group - time of the first mkdir/openat of the staging folder
#      `.staging-PID` that `export` creates beside OUT once the grid is read. It holds the
#      whole writer (conversion, formatting, compression, the write calls, the rename) and
#      the teardown, and none of the read, so it needs no subtraction: this is the figure
#      to trust when the write is short next to the read's spread.
#      MB/s (write phase) = size / write phase.
#   The 1-minute load average is recorded before every run: on a shared machine wall times
#   are only as good as that. Writes go to the page cache: the times do not include the
#   flush to disk (the writers do not fsync; with enough free RAM nothing waits for the disk).
#   Prints a markdown table at the end; keeps results.tsv and the logs in WORK.
#
# The binary and its build-tree shared libraries are first copied into WORK/bin and run from
# there (LD_LIBRARY_PATH), so a rebuild of the build tree during the benchmark cannot change
# or break the binary under test.
#
# Reproduce (from the repository root, Release build in build/); needs 0.2 GB for the grid
# plus the largest output (2.2 GB, openfoam) in WORK, and 2.3 GB RAM (1.5 GB per export):
#   bash bench/run_exports.sh                                  # build the 10 M grid, all formats
#   bash bench/run_exports.sh --workdir /tmp/hxexp --grid /tmp/hxexp/grid/grid.vtm
#   bash bench/run_exports.sh --formats "plot3d-c cgns" --n 64  # quick, 1 M cells
#   bash bench/run_exports.sh --keep-grid                     # keep WORK/grid afterwards
# Options: --workdir DIR (default /tmp/hexmesh_exports), --grid GRID, --n N (default 136),
#   --formats "F ...", --read-runs K, --keep-grid, --timeout S (per export, default 1200),
#   --table TSV (print the table of a past run). Results: bench/RESULTS.md, "Export throughput".
# Needs: bash, GNU time (/usr/bin/time), coreutils (du, timeout), awk; strace (optional).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(dirname "$here")"
HEXMESH="${HEXMESH:-$repo/build/hexmesh/cli/hexmesh}"
workdir=/tmp/hexmesh_exports
grid=""
n=136
formats="vtk openfoam cgns gmsh medit su2 ugrid fluent exodus plot3d plot3d-fortran plot3d-c plot3d-ascii plot3d-single plot3d-fortran-single plot3d-c-single plot3d-ascii-single"
read_runs=3
keep_grid=0
timeout_s=1200

print_table() {
    echo "| format | kind | wall (s) | wall - read (s) | CPU (s) | CPU - read CPU (s) | write phase (s) | peak RSS (MB) | output (MB) | MB/s (wall - read) | MB/s (CPU - read CPU) | MB/s (write phase) | load |"
    echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    tail -n +2 "$1" | while IFS=$'\t' read -r f kind status wall rd wr cpu rcpu wcpu rss mb rate crate load wp wprate; do
        if [[ "$status" != ok ]]; then
            echo "| $f | $kind | $status | - | $cpu | - | - | $rss | - | - | - | - | $load |"
        else
            echo "| $f | $kind | $wall | $wr | $cpu | $wcpu | ${wp:--} | $rss | $mb | $rate | $crate | ${wprate:--} | $load |"
        fi
    done
}

while [[ $# -gt 0 ]]; do
    case "$1" in
        --workdir) workdir="$2"; shift 2 ;;
        --grid) grid="$2"; shift 2 ;;
        --n) n="$2"; shift 2 ;;
        --formats) formats="$2"; shift 2 ;;
        --read-runs) read_runs="$2"; shift 2 ;;
        --keep-grid) keep_grid=1; shift ;;
        --timeout) timeout_s="$2"; shift 2 ;;
        --table) print_table "$2"; exit 0 ;;
        *) echo "unknown option $1" >&2; exit 2 ;;
    esac
done

mkdir -p "$workdir/bin" "$workdir/logs"
cp "$HEXMESH" "$workdir/bin/hexmesh"
ldd "$HEXMESH" | awk '$2 == "=>" && $3 ~ /^\// && $3 !~ /^\/(usr\/)?lib/ {print $3}' |
    while read -r lib; do
        cp "$lib" "$workdir/bin/"
        # The module MeshSdf loads at run time (OpenVDB) lives beside libhexmesh_surface.so.
        module="$(dirname "$lib")/libhexmesh_openvdb.so"
        if [[ -f "$module" ]]; then cp "$module" "$workdir/bin/"; fi
    done
export LD_LIBRARY_PATH="$workdir/bin${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
hx="$workdir/bin/hexmesh"
load1() { cut -d' ' -f1 /proc/loadavg; }
# field of a /usr/bin/time -v log
tv() { grep -F "$2" "$1" | awk -F': ' '{print $2}'; }
to_s() { awk -F: '{ s = 0; for (i = 1; i <= NF; i++) s = s * 60 + $i; printf "%.2f", s }' <<<"$1"; }

built_grid=0
if [[ -z "$grid" ]]; then
    w=$((n / 2))
    cat >"$workdir/case.json" <<EOF
{"geometry": {"sphere": {"radius": 1}}, "grid": {"cells_per_edge": $n, "wall_cells": $w, "core_size": 0.45}, "boundary_layer": {"first_height": 0.001, "growth_ratio": 1.1, "layers": 8}, "solver": {"optimize_iterations": 0}}
EOF
    echo "building the grid: n = $n ($((4 * n * n * n)) cells)" >&2
    rm -rf "$workdir/grid"
    "$hx" run "$workdir/case.json" -o "$workdir/grid" >"$workdir/logs/run.log" 2>&1
    grid="$workdir/grid/grid.vtm"
    built_grid=1
fi
grid_mb=$(du -sb "$(dirname "$grid")" | awk '{printf "%.0f", $1 / 1e6}')
echo "grid: $grid ($grid_mb MB on disk for its folder)" >&2

out="$workdir/out"
rm -rf "$out"; mkdir -p "$out"

# 2. read alone
reads=()
for ((i = 1; i <= read_runs; i++)); do
    log="$workdir/logs/read_$i.time"
    set +e
    /usr/bin/time -v -o "$log" "$hx" export "$grid" --format plot3d-c -o "$out/." >"$workdir/logs/read_$i.out" 2>&1
    rc=$?
    set -e
    if [[ $rc -ne 1 ]] || ! grep -q "expected a file name" "$workdir/logs/read_$i.out"; then
        echo "read-only run did not stop where expected (exit $rc); see $workdir/logs/read_$i.out" >&2; exit 1
    fi
    t=$(to_s "$(tv "$log" 'Elapsed (wall clock)')")
    reads+=("$t")
    echo "read $i: $t s, peak RSS $(( $(tv "$log" 'Maximum resident set size') / 1024 )) MB, load $(load1)" >&2
done
read_s=$(printf '%s\n' "${reads[@]}" | sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}')
cpus=()
for ((i = 1; i <= read_runs; i++)); do
    cpus+=("$(awk -F': ' '/User time|System time/ {s += $2} END {printf "%.2f", s}' "$workdir/logs/read_$i.time")")
done
read_cpu=$(printf '%s\n' "${cpus[@]}" | sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}')
read_rss=$(( $(tv "$workdir/logs/read_1.time" 'Maximum resident set size') / 1024 ))
echo "read (median of $read_runs): $read_s s wall, $read_cpu s CPU; all: ${reads[*]} / ${cpus[*]}" >&2

tsv="$workdir/results.tsv"
printf 'format\tkind\tstatus\twall\tread\twrite\tcpu\tread_cpu\twrite_cpu\trss_mb\tsize_mb\tmb_per_s\tmb_per_cpu_s\tload\twrite_phase\tmb_per_s_write_phase\n' >"$tsv"
printf 'read only (median of %s)\t-\tok\t%s\t%s\t-\t%s\t%s\t-\t%s\t-\t-\t-\t%s\n' "$read_runs" "$read_s" "$read_s" "$read_cpu" "$read_cpu" "$read_rss" "$(load1)" >>"$tsv"

for f in $formats; do
    case "$f" in
        vtk) target="$out/grid.vtm"; kind=binary ;;
        openfoam) target="$out/grid_openfoam"; kind=ASCII ;;
        cgns) target="$out/grid.cgns"; kind=binary ;;
        gmsh) target="$out/grid.msh"; kind=ASCII ;;
        medit) target="$out/grid.mesh"; kind=ASCII ;;
        su2) target="$out/grid.su2"; kind=ASCII ;;
        ugrid) target="$out/grid.ugrid"; kind=ASCII ;;
        fluent) target="$out/grid_fluent.msh"; kind=ASCII ;;
        exodus) target="$out/grid.exo"; kind=binary ;;
        plot3d*ascii*) target="$out/grid.xyz"; kind=ASCII ;;
        plot3d*) target="$out/grid.xyz"; kind=binary ;;
        *) target="$out/grid.$f"; kind=? ;;
    esac
    load=$(load1)
    log="$workdir/logs/$f.time"
    set +e
    st=()
    if [[ "${NO_STRACE:-0}" != 1 ]] && command -v strace >/dev/null; then
        st=(strace -f -qq --seccomp-bpf -ttt -e trace=mkdir,openat,exit_group -o "$workdir/logs/$f.strace")
    fi
    timeout "$timeout_s" /usr/bin/time -v -o "$log" "${st[@]}" "$hx" export "$grid" --format "$f" -o "$target" \
        >"$workdir/logs/$f.out" 2>&1
    rc=$?
    set -e
    cpu=$(awk -F': ' '/User time|System time/ {s += $2} END {printf "%.2f", s}' "$log" 2>/dev/null || echo -)
    rss=$(( $(tv "$log" 'Maximum resident set size' 2>/dev/null || echo 0) / 1024 ))
    if [[ $rc -ne 0 ]]; then
        status="FAILED (exit $rc)"; [[ $rc -eq 124 ]] && status=TIMEOUT
        printf '%s\t%s\t%s\t-\t%s\t-\t%s\t%s\t-\t%s\t-\t-\t-\t%s\n' "$f" "$kind" "$status" "$read_s" "$cpu" "$read_cpu" "$rss" "$load" >>"$tsv"
        echo "$f: $status, see $workdir/logs/$f.out" >&2
        rm -rf "$out"; mkdir -p "$out"
        continue
    fi
    wall=$(to_s "$(tv "$log" 'Elapsed (wall clock)')")
    bytes=$(du -sb "$out" | awk '{print $1}')  # the output plus side files; $out held nothing else
    wp=-; wprate=-
    if [[ ${#st[@]} -gt 0 ]]; then
        wp=$(awk '/\.staging-/ && t0 == "" {t0 = $2} /exit_group/ {t1 = $2} END {if (t0 != "" && t1 != "") printf "%.2f", t1 - t0; else print "-"}' "$workdir/logs/$f.strace")
        [[ "$wp" != - ]] && wprate=$(awk -v b="$bytes" -v w="$wp" 'BEGIN {if (w > 0) printf "%.0f", b / 1e6 / w; else print "-"}')
    fi
    read -r wr wcpu mb rate crate < <(awk -v w="$wall" -v r="$read_s" -v c="$cpu" -v rc="$read_cpu" -v b="$bytes" 'BEGIN {
        wr = w - r; wc = c - rc; mb = b / 1e6
        printf "%.2f %.2f %.1f %s %s\n", wr, wc, mb, (wr > 0 ? sprintf("%.0f", mb / wr) : "-"),
               (wc > 0 ? sprintf("%.0f", mb / wc) : "-") }')
    printf '%s\t%s\tok\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$f" "$kind" "$wall" "$read_s" "$wr" "$cpu" "$read_cpu" "$wcpu" "$rss" "$mb" "$rate" "$crate" "$load" "$wp" "$wprate" >>"$tsv"
    echo "$f: wall $wall s, write $wr s ($wcpu s CPU, write phase $wp s), $mb MB, $rate MB/s ($crate per CPU s, $wprate in the write phase), CPU $cpu s, RSS $rss MB, load $load" >&2
    rm -rf "$out"; mkdir -p "$out"
done
rm -rf "$out"
if [[ $built_grid -eq 1 && $keep_grid -eq 0 ]]; then rm -rf "$workdir/grid"; fi

echo "hexmesh export, grid $grid ($grid_mb MB), $(nproc) cores, $(date -u +%Y-%m-%d)"
print_table "$tsv"
