#!/usr/bin/env bash
# jnd pca: the decomposition of the DamagedHelmet set (2048² × 13 channels)
# on 2 threads — target ≤ 2 s — and the whole run with block compression.
# Prints seconds and MB/s (MB of float32 channel data per second).
set -uo pipefail
: "${JND:?JND must point at the jnd binary}"
H="${JND_SHARED:-$(cd "$(dirname "$0")/../.." && pwd)/shared}/data/texsets/damagedhelmet"
[ -d "$H" ] || { echo "   skip: no shared data ($H)"; exit 0; }
OUT="${BENCH_OUT:-/tmp}/pca"
mkdir -p "$OUT"
MAPS="$H/Default_AO.jpg $H/Default_albedo.jpg $H/Default_emissive.jpg $H/Default_metalRoughness.jpg $H/Default_normal.jpg"
best=""
for run in 1 2 3; do
  OMP_NUM_THREADS=2 "$JND" pca $MAPS -o "$OUT" --components 5 --no-bc --timings --quiet || exit 1
  t=$(python3 -c "import json;print(json.load(open('$OUT/pca.json'))['result']['timings_s']['decomposition'])")
  best=$(python3 -c "print(min(float('$t'), float('${best:-1e9}')))")
done
python3 - "$OUT/pca.json" "$best" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))['result']; t = float(sys.argv[2])
mb = r['width'] * r['height'] * r['channel_count'] * 4 / 1e6
print(f"   decomposition {r['width']}x{r['height']}x{r['channel_count']} on 2 threads: {t:.3f} s, "
      f"{mb / t:.0f} MB/s (target <= 2 s){'' if t <= 2 else '  OVER TARGET'}")
tm = r['timings_s']
print(f"   --components 5: read {tm['read']:.2f} s, encode {tm['encoding']:.2f} s, total {tm['total']:.2f} s")
PY
OMP_NUM_THREADS=2 "$JND" pca $MAPS -o "$OUT" --components 5 --timings --quiet || exit 1
python3 -c "
import json; t=json.load(open('$OUT/pca.json'))['result']['timings_s']
print(f\"   with block compression (BC1/BC4/BC5 encode + decode, 3 variants): {t['block_compression']:.2f} s, total {t['total']:.2f} s\")"
OMP_NUM_THREADS=2 "$JND" pca $MAPS -o "$OUT" --psnr 35 --no-bc --timings --quiet || exit 1
python3 -c "
import json; r=json.load(open('$OUT/pca.json'))['result']; t=r['timings_s']
print(f\"   --psnr 35: choice {t['choice']:.2f} s, K={r['components_kept']}, {r['storage_bytes']/1e6:.2f} MB, total {t['total']:.2f} s\")"
