#!/usr/bin/env bash
# jnd pca end to end on small synthetic maps: outputs, the JSON contract,
# the float reconstruction, and one-line errors with exit 2 for bad input.
set -euo pipefail
T=${JND_TMP:-/tmp/jnd-e2e-pca}
rm -rf "$T" && mkdir -p "$T"
command -v python3 >/dev/null || { echo "skip: needs python3"; exit 0; }

# three correlated maps (RGB albedo, grey height stored as RGB, RG normal-ish)
# and one of another shape, written as PNG with the standard library only
python3 - "$T" <<'PY'
import math, struct, sys, zlib
d = sys.argv[1]
def png(path, w, h, ch, f):
    raw = bytearray()
    for y in range(h):
        raw.append(0)
        for x in range(w):
            raw.extend(max(0, min(255, int(round(v * 255)))) for v in f(x, y))
    colour = {1: 0, 3: 2, 4: 6}[ch]
    def chunk(t, b): return struct.pack('>I', len(b)) + t + b + struct.pack('>I', zlib.crc32(t + b) & 0xffffffff)
    open(path, 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, colour, 0, 0, 0))
                           + chunk(b'IDAT', zlib.compress(bytes(raw))) + chunk(b'IEND', b''))
def a(x, y): return 0.5 + 0.3 * math.sin(x * 0.1) * math.cos(y * 0.13)
def b(x, y): return 0.5 + 0.2 * math.sin((x + y) * 0.07)
png(f'{d}/mat_albedo.png', 96, 64, 3, lambda x, y: (a(x, y), 0.8 * a(x, y) + 0.1 * b(x, y), 0.3 + 0.4 * b(x, y)))
png(f'{d}/mat_height.png', 96, 64, 3, lambda x, y: (0.6 * a(x, y) + 0.2,) * 3)
png(f'{d}/mat_normal.png', 96, 64, 3, lambda x, y: (b(x, y), 1 - a(x, y), 1.0))
png(f'{d}/mat_small.png', 48, 32, 1, lambda x, y: (a(2 * x, 2 * y),))
png(f'{d}/mat_square.png', 64, 64, 1, lambda x, y: (a(x, y),))
PY
M="$T/mat_albedo.png $T/mat_height.png $T/mat_normal.png"

"$JND" pca --help | grep -q -- "--components K"

# all components, float reconstruction; energies sum to the total variance
"$JND" pca $M -o "$T/all" --quiet
for f in pca.json component_00.png contribution.png; do test -s "$T/all/$f"; done
python3 - "$T/all/pca.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))['result']
names = [c['name'] for c in r['channels']]
# height is grey stored as RGB: counted once; normal.b is constant: left out
assert names == ['albedo.r', 'albedo.g', 'albedo.b', 'height', 'normal.r', 'normal.g'], names
e = r['energy']
assert all(e[i] >= e[i + 1] for i in range(len(e) - 1)), e
assert abs(sum(e) - r['total_variance']) <= 1e-9 * r['total_variance'], (sum(e), r['total_variance'])
assert all(c['psnr_float_db'] >= 60 for c in r['channels']), r['channels']
assert all(c['psnr_db'] >= 40 for c in r['channels']), r['channels']   # 8-bit components
C = len(names)
assert len(r['reconstruction']) == C and all(len(row) == C + 1 for row in r['reconstruction'])
assert r['storage_bytes'] > 0 and 'block_compression' in r
PY

# K components at 16 bits: reconstruction C × (K+1); storage shrinks
"$JND" pca $M -o "$T/k2" --components 2 --bits 16 --quiet --json "$T/k2.json" --write-maps
for f in albedo height normal; do test -s "$T/k2/$f.png"; done
python3 - "$T/k2/pca.json" "$T/all/pca.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))['result']; a = json.load(open(sys.argv[2]))['result']
assert r['components_kept'] == 2 and len(r['reconstruction'][0]) == 3
assert all(c['bits'] == 16 for c in r['components'])
assert r['storage_bytes'] < a['storage_bytes']
PY
cmp "$T/k2/pca.json" "$T/k2.json"
test ! -e "$T/k2/component_02.png"

# deterministic: the same report on any thread count
OMP_NUM_THREADS=1 "$JND" pca $M -o "$T/k2b" --components 2 --bits 16 --quiet
cmp "$T/k2/pca.json" "$T/k2b/pca.json"
OMP_NUM_THREADS=1 "$JND" pca $M -o "$T/p1" --psnr 40 --quiet
OMP_NUM_THREADS=3 "$JND" pca $M -o "$T/p3" --psnr 40 --quiet
cmp "$T/p1/pca.json" "$T/p3/pca.json"

# bits per component
"$JND" pca $M -o "$T/bits" --components 3 --bits 16,8 --no-bc --quiet
python3 - "$T/bits/pca.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))['result']
assert [c['bits'] for c in r['components']] == [16, 8, 8], r['components']
PY

# --psnr: every channel meets the floor
"$JND" pca $M -o "$T/psnr" --psnr 42 --no-bc --quiet
python3 - "$T/psnr/pca.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))['result']
assert all(c['psnr_db'] >= 42 for c in r['channels']), r['channels']
PY

# a smaller map of the same shape is resampled with a warning
"$JND" pca $M "$T/mat_small.png" -o "$T/small" --no-bc 2>"$T/small.err"
grep -q "warning: .*mat_small.png" "$T/small.err"

# bad input: one line "jnd: FILE: problem", exit 2
expect_bad() {   # expect_bad PATTERN ARGS...
  local pat=$1; shift
  set +e; "$JND" pca "$@" 2>"$T/err" >/dev/null; local rc=$?; set -e
  [ "$rc" = 2 ] || { echo "exit $rc for: $*"; cat "$T/err"; exit 1; }
  [ "$(wc -l <"$T/err")" = 1 ] || { echo "not one line:"; cat "$T/err"; exit 1; }
  grep -q "^jnd: .*$pat" "$T/err" || { echo "unexpected message:"; cat "$T/err"; exit 1; }
}
expect_bad "missing.png" $M "$T/missing.png" -o "$T/x"
echo "not an image" >"$T/bad.png"
expect_bad "bad.png" $M "$T/bad.png" -o "$T/x"
expect_bad "mat_square.png" $M "$T/mat_square.png" -o "$T/x"
expect_bad "weight" $M -o "$T/x" --weight roughness=2
expect_bad "channels" $M -o "$T/x" --channels albedo=q
expect_bad "max-p needs --model" $M -o "$T/x" --max-p 0.1
expect_bad "rendered visibility needs the renderer" $M -o "$T/x" --max-p 0.1 --model "$T/m.glb" --material m
expect_bad "needs maps" -o "$T/x"
expect_bad "bits" $M -o "$T/x" --bits 12
echo "pca e2e ok"
