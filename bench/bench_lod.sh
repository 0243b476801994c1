#!/usr/bin/env bash
# jnd lod: (1) the chain of a 1 M-triangle mesh (the Stanford bunny of the
# shared data, every triangle split in 4 twice: 1.1 M triangles) — the
# target is 2 s; one pass over the input, cut in slabs on the 2 cores; (2) 003's analysis of a 100 K-triangle asset (the teapot
# split twice: 101 K triangles) for the 4 default screens — the whole
# `jnd lod`, perceptual step included, is to stay under 60 s on 2 cores.
# Wall times are medians of BENCH_LOD_RUNS runs (3; the analysis 1 unless
# BENCH_LOD_ANALYSIS_RUNS says otherwise), user + sys CPU beside them.
set -uo pipefail
: "${JND:?}"
# Threads that wait spin under libgomp's default policy; on a shared 2-core
# machine that spinning took 59% of the analysis's CPU samples (perf) and
# made it 2.4x slower (README: passive when running more processes than
# cores). The bench says which policy it ran with.
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
here=$(cd "$(dirname "$0")" && pwd)
. "$here/targets.sh"
out=${BENCH_OUT:-$here/out}/lod
data=${JND_SHARED:-$here/../../shared}/data/meshes
mkdir -p "$out"
if [ ! -f "$data/stanford-bunny.obj" ] || [ ! -f "$data/teapot.obj" ]; then
  echo "   skipped: the shared meshes are not at $data"
  exit 0
fi
[ -s "$out/bunny_1m.obj" ] || python3 "$here/subdivide_obj.py" "$data/stanford-bunny.obj" "$out/bunny_1m.obj" 2
[ -s "$out/teapot_100k.obj" ] || python3 "$here/subdivide_obj.py" "$data/teapot.obj" "$out/teapot_100k.obj" 2

# one run: prints "WALL_S USER_S SYS_S STAGE_S STAGE_CPU_S" for the whole
# command and, from the report's timings, for one stage (wall, and user +
# sys of all threads: on a shared machine the CPU time is the steadier)
run() { # run KEY ARGS...
  local key=$1; shift
  local t
  t=$( { /usr/bin/time -f "%e %U %S" "$JND" lod "$@" --timings --quiet --json "$out/r.json" >/dev/null; } 2>&1 | tail -1) || return 1
  echo "$t $(python3 -c "import json,sys; t=json.load(open(sys.argv[1]))['result']['timings']; print('%.3f %.3f' % (t[sys.argv[2] + '_s'], t[sys.argv[2] + '_cpu_s']))" "$out/r.json" "$key")"
}
median() { sort -n | awk '{a[NR]=$0} END {print a[int((NR+1)/2)]}'; }

runs=${BENCH_LOD_RUNS:-3}
: >"$out/chain.txt"
for i in $(seq "$runs"); do run chain "$out/bunny_1m.obj" -o "$out/chain" --chain-only >>"$out/chain.txt" || exit 1; done
tris=$(python3 -c "import json,sys; r=json.load(open(sys.argv[1]))['result']['levels']; print(r[0]['triangles'], '->', ' '.join(str(l['triangles']) for l in r[1:]))" "$out/r.json")
echo "   chain of bunny_1m.obj ($tris triangles):"
echo "     chain: wall $(cut -d' ' -f4 "$out/chain.txt" | median) s, user + sys $(cut -d' ' -f5 "$out/chain.txt" | median) s" \
     "(medians of $runs; the target is 2 s on 2 cores); whole command (loading the 43 MB OBJ, writing the" \
     "10-level GLB): wall $(cut -d' ' -f1 "$out/chain.txt" | median) s, user $(cut -d' ' -f2 "$out/chain.txt" | median) s," \
     "sys $(cut -d' ' -f3 "$out/chain.txt" | median) s; load average $(cut -d' ' -f1 /proc/loadavg)"
target "lod chain of a 1.1 M-triangle bunny: the chain's wall" "$(cut -d' ' -f4 "$out/chain.txt" | median)" "<=" 2 "s"

aruns=${BENCH_LOD_ANALYSIS_RUNS:-1}
: >"$out/analysis.txt"
for i in $(seq "$aruns"); do run analysis "$out/teapot_100k.obj" -o "$out/analysis" >>"$out/analysis.txt" || exit 1; done
python3 - "$out/r.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
res = r["result"]
print("   003 analysis of teapot_100k.obj (%d triangles, %d levels), %d views, virtual screen %d px, %d renderings on %s:"
      % (res["levels"][0]["triangles"], len(res["levels"]), r["parameters"]["views"], res["virtual_px"], res["renderings"],
         res["renderer"]))
for s in res["screens"]:
    perc = s.get("perceptual_triangles")
    sd = " ".join("never" if x is None else "%.3g" % x for x in (s.get("switch_distance_m") or []))
    # the screen's scale each switch was judged at (1: its own pixels per degree; -: level 0 or never)
    ss = " ".join("-" if x is None else "%.2g" % x for x in (s.get("switch_scale") or []))
    print("     %-13s perceptual %6s  PoI lit %6d  unlit %6d  meshopt 1px %6d  px rule %6d triangles; switch %s"
          " (judged at scale %s);"
          " judged %d distances, %d popping evaluations"
          % (s["name"], perc if perc is not None else "-", s["poi_triangles"], s["poi_triangles_unlit"],
             s["rules"]["meshopt"]["triangles"], s["rules"]["pixel_error"]["triangles"], sd, ss,
             s["judge"]["distances"], s.get("pop_evaluations", 0)))
PY
echo "     analysis: wall $(cut -d' ' -f4 "$out/analysis.txt" | median) s, user + sys $(cut -d' ' -f5 "$out/analysis.txt" | median) s" \
     "(medians of $aruns); whole command: wall $(cut -d' ' -f1 "$out/analysis.txt" | median) s, user" \
     "$(cut -d' ' -f2 "$out/analysis.txt" | median) s, sys $(cut -d' ' -f3 "$out/analysis.txt" | median) s;" \
     "load average $(cut -d' ' -f1 /proc/loadavg), OMP_WAIT_POLICY=$OMP_WAIT_POLICY"
# the target (issue 29 item 4): the whole command <= 60 s on 2 cores. On a
# shared machine wall time waits for others' work, so beside it the CPU time
# over the cores it may use: what the run needs of 2 cores kept busy
wall=$(cut -d' ' -f1 "$out/analysis.txt" | median)
cpu=$(awk '{print $2 + $3}' "$out/analysis.txt" | median)
python3 - "$wall" "$cpu" <<'PY'
import sys
wall, cpu = float(sys.argv[1]), float(sys.argv[2])
est = cpu / 2
print("     lod of teapot_100k on 4 screens: wall %.1f s, user + sys %.1f s = %.1f s on 2 busy cores; target 60 s: %s (wall), %s (CPU over 2 cores)"
      % (wall, cpu, est, "met" if wall <= 60 else "NOT met", "met" if est <= 60 else "NOT met"))
PY
target "lod of a 100 K-triangle teapot on 4 screens: wall (issue 29)" "$wall" "<=" 60 "s"
