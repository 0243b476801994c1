#!/bin/bash
# jnd on a GPU machine's vendor EGL device beside Mesa llvmpipe on the same
# machine, each on all cores and on two (taskset), for docs/gpu.md. Made by
# bench/device/bundle.sh into .gpu/run.sh; run there from the repository root
# with .gpu beside it:  T=85 bash .gpu/run.sh   (T: seconds per command).
# Writes $OUT/summary.txt (label, wall, user, sys seconds, exit status) and
# $OUT/reports.tgz (every report, for comparing decisions across renderers).
set -u
G=$PWD/.gpu
O=${OUT:-/tmp/out}; mkdir -p "$O/r"
S=$O/summary.txt
T=${T:-120}      # per-command limit, s
cd "$G" || exit 1
[ -d bin ] || tar xJf jnd.tar.xz
[ -d mesa ] || tar xJf mesa.tar.xz
nv=/usr/local/nvidia
export LD_LIBRARY_PATH=$G/lib:$G/mesa:$nv/lib64:$nv/lib:${LD_LIBRARY_PATH:-}
export LIBGL_DRIVERS_PATH=$G/mesa/dri
vend=$G/mesa/50_mesa.json
for f in $nv/share/glvnd/egl_vendor.d/*.json /usr/share/glvnd/egl_vendor.d/*nvidia*.json; do [ -f "$f" ] && vend="$f:$vend"; done
export __EGL_VENDOR_LIBRARY_FILENAMES=$vend
J=$G/bin/jnd
{ date; nproc; nvidia-smi -L 2>&1 | head -2; echo "vendors: $vend"; } >"$S"
ncores=$(nproc)
run() { # run LABEL CPUS CMD...   -> one line: label wall user sys rc
  local label=$1 cpus=$2; shift 2
  local pre=() ; [ "$cpus" != all ] && pre=(taskset -c "$cpus")
  local t0=$EPOCHREALTIME
  local tf=$O/r/$label.time
  ( TIMEFORMAT="%R %U %S"; time timeout "$T" "${pre[@]}" "$@" >"$O/r/$label.out" 2>"$O/r/$label.err" ) 2>"$tf"
  local rc=$?
  echo "$label cpus=$cpus $(tail -1 "$tf") rc=$rc" | tee -a "$S"
}
W=$O/w; mkdir -p "$W"
# which renderer each platform gives; "llvmpipe" = Mesa's vendor alone

plat() { case $1 in device) echo device;; *) echo surfaceless;; esac; }
pre() { case $1 in llvmpipe) echo env __EGL_VENDOR_LIBRARY_FILENAMES=$G/mesa/50_mesa.json;; *) echo env;; esac; }
for p in device llvmpipe; do
  run render_$p all $(pre $p) $J render builtin -o "$W/render_$p" --platform $(plat $p) --json "$O/r/render_$p.json" --quiet
  python3 -c "import json,sys; print(sys.argv[2], json.load(open(sys.argv[1]))['result'].get('renderer'))" "$O/r/render_$p.json" $p >>"$S" 2>&1
done
# diff needs no renderer: CPU only
$J example -o "$W/ex" --size 1920x1080 2>/dev/null
for c in all 0,1; do for i in 1 2 3; do
  run diff_${c/,/}_$i $c $J diff "$W/ex/reference.png" "$W/ex/test.png" --json "$O/r/diff_${c/,/}_$i.json" --quiet
done; done
for task in texres lod; do
  for cfg in device:all llvmpipe:all device:0,1 llvmpipe:0,1; do
    p=${cfg%%:*}; c=${cfg#*:}; k=${task}_${p}_${c/,/}
    if [ $task = texres ]; then args=("$G/assets/hp-left.glb" --verify-views 8); else args=("$G/assets/teapot_100k.obj"); fi
    run $k $c $(pre $p) $J $task "${args[@]}" -o "$W/$k" --platform $(plat $p) --timings --quiet --json "$O/r/$k.json"
  done
done
cd "$O" && tar czf reports.tgz r && rm -rf r w
cat "$S"
