#!/usr/bin/env bash
# jnd pca on the DamagedHelmet set (5 JPEG maps, 2048²): 13 informative
# channels, energies summing to the total variance, ≥ 60 dB with every
# component in float, 001's 5-component table, and albedo weighting.
set -euo pipefail
[ -d "${JND_SHARED:-}/data/texsets/damagedhelmet" ] || { echo "skip: no shared data"; exit 0; }
command -v python3 >/dev/null || { echo "skip: needs python3"; exit 0; }
T=${JND_TMP:-/tmp/jnd-e2e-pca-helmet}
rm -rf "$T" && mkdir -p "$T"
H="$JND_SHARED/data/texsets/damagedhelmet"
MAPS="$H/Default_AO.jpg $H/Default_albedo.jpg $H/Default_emissive.jpg $H/Default_metalRoughness.jpg $H/Default_normal.jpg"

"$JND" pca $MAPS -o "$T/all" --no-bc --quiet
"$JND" pca $MAPS -o "$T/k5" --components 5 --quiet
"$JND" pca $MAPS -o "$T/k5w" --components 5 --weight albedo=2 --no-bc --quiet
python3 - "$T" <<'PY'
import json, sys
t = sys.argv[1]
a = json.load(open(f'{t}/all/pca.json'))['result']
k5 = json.load(open(f'{t}/k5/pca.json'))['result']
w = json.load(open(f'{t}/k5w/pca.json'))['result']
assert a['channel_count'] == 13, a['channel_count']
assert abs(sum(a['energy']) - a['total_variance']) <= 1e-9 * a['total_variance']
assert all(c['psnr_float_db'] >= 60 for c in a['channels']), a['channels']
assert k5['components_kept'] == 5 and len(k5['reconstruction'][0]) == 6
print('5 components:', ' '.join(f"{c['name']}={c['psnr_db']:.1f}" for c in k5['channels']))
alb = lambda r: sum(c['psnr_float_db'] for c in r['channels'] if c['name'].startswith('albedo')) / 3
assert alb(w) > alb(k5), (alb(w), alb(k5))
assert any(cw['psnr_float_db'] < c['psnr_float_db'] for c, cw in zip(k5['channels'], w['channels'])
           if not c['name'].startswith('albedo'))
bc = k5['block_compression']
assert bc['pca_bc4_bytes'] > 0 and bc['plain_bc_bytes'] > 0
PY
echo "pca helmet e2e ok"
