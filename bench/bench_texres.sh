#!/usr/bin/env bash
# jnd texres on real assets (controllers of @webxr-input-profiles/assets, MIT):
# chosen sizes, memory before/after, the baseColor x normal matrix (000 Fig. 13),
# the held-out check on 32 views, and the time at 8 views (the target: under
# 60 s on 2 cores for <= 5 materials x 3 maps).
set -uo pipefail
: "${JND:?}"
here=$(cd "$(dirname "$0")" && pwd)
. "$here/webxr_assets.sh"
out=${BENCH_OUT:-$here/out}/texres
mkdir -p "$out"
ASSETS=$(webxr_assets_fetch && webxr_assets) || { echo "   skipped: @webxr-input-profiles/assets not available (npm/network)"; exit 0; }
for m in ${BENCH_TEXRES_MODELS:-generic-trigger-squeeze-thumbstick/left.glb oculus-touch/left.glb}; do
  f="$ASSETS/dist/profiles/$m"
  d="$out/$(echo "$m" | tr / _)"
  t0=$(date +%s.%N)
  "$JND" texres "$f" -o "$d" --views 8 --timings --quiet; rc=$?
  t1=$(date +%s.%N)
  "$JND" texres "$f" -o "$d.verify" --views 8 --verify-views 32 --no-matrix --quiet; rc2=$?
  python3 - "$d/texres.json" "$d.verify/texres.json" "$m" "$t0" "$t1" "$rc" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["result"]
v = json.load(open(sys.argv[2]))["result"]
m, t0, t1, rc = sys.argv[3], float(sys.argv[4]), float(sys.argv[5]), sys.argv[6]
print("   %s: %d maps, %d evaluations, %d renderings, %.1f s at 8 views (exit %s) on %s"
      % (m, len(r["maps"]), r["evaluations"], r["renderings"], t1 - t0, rc, r["renderer"]))
for x in r["maps"]:
    print("     %-58s %5dx%-5d -> %5dx%-5d (mip bound %d, eye %d, eq.1 at P=0.2: %s)"
          % (x["name"], x["original"][0], x["original"][1], x["chosen"][0], x["chosen"][1], max(x["mip_bound"]),
             max(x["eye_bound"]), "%.0f" % x["psychometric"]["resolution_at_p"] if "psychometric" in x else "-"))
mem = r["memory"]
print("     memory RGBA8 + mips: %.2f MB -> %.2f MB (-%.0f%%); block-compressed %.2f -> %.2f MB"
      % (mem["before_bytes"] / 2**20, mem["after_bytes"] / 2**20, 100 * mem["reduction"],
         mem["block_before_bytes"] / 2**20, mem["block_after_bytes"] / 2**20))
for mx in r["matrices"]:
    print("     matrix (criterion statistic: the view quantile of pooled P), rows %s, columns %s:" % (mx["rows"].split("/")[-1], mx["columns"].split("/")[-1]))
    print("       %6s " % "" + " ".join("%6d" % s for s in mx["column_sizes"]))
    for s, row in zip(mx["row_sizes"], mx["stat"]):
        print("       %6d " % s + " ".join("%6.3f" % p for p in row))
vv = v["verify"]
print("     held out: %.0f%% of %d views above P=0.2 (criterion <= 10%%: %s)"
      % (100 * vv["fraction_above"], vv["views"], "passes" if vv["passes"] else "FAILS"))
PY
done
