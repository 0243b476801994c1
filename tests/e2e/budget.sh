#!/usr/bin/env bash
# jnd budget: texture sizes and the LOD chain chosen together. The report's
# fields; the written GLB (every level renders with jnd render --lod K, its
# MSFT_screencoverage, the texture memory and triangles recomputed from the
# file); the choice at most as costly as texres + pca + lod chosen separately;
# budget mode (a budget the separate choice exceeds gives a candidate within
# it); a budget nothing meets and bad input: one line, exit 2, nothing written.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
need_renderer
command -v python3 >/dev/null || skip "needs python3"
SMALL=(--map-size 128 --size 96x96 --samples 1 --views 4 --confirm 0 --screens 640x480
       --errors 0.002,0.008,0.03 --judge-views 2 --max-px 128 --tolerance 0.5 --far-coverage 0.05
       --verify-views 2 --quiet)

expect_exit 0 "cheapest unnoticed: builtin:sphere passes" "$JND" budget builtin:sphere -o "$T/a" "${SMALL[@]}"
check "budget.json, the model and pareto.png are written" test -s "$T/a/budget.json" -a -s "$T/a/pareto.png" \
  -a -s "$T/a/model/builtin_sphere.glb"

check "the choice is at most as costly as texres + pca + lod separately, and passes at every switch distance" \
  python3 - "$T/a/budget.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
assert r["command"] == "budget" and r["parameters"]["mode"] == "cheapest"
res = r["result"]
ch, se = res["chosen"], res["separate"]
assert ch["kind"] in ("searched", "separate", "encoded") and ch["passes_with_margin"]
# a cheaper encoding than the slot's block format only in the encoding search's candidate
cheaper = [n for n, f in ch["formats"].items() if n.split("/")[-1] in ("baseColor", "normal") and f == "bc1"]
assert bool(cheaper) == (ch["kind"] == "encoded"), (ch["kind"], ch["formats"])
enc = [c for c in res["candidates"] if c["kind"] == "encoded"]
assert len(enc) <= 1 and all(c["passes_with_margin"] and c["level"] == ch["level"] for c in enc)
# the separate pair is a candidate of the search: where it passes, the choice is no dearer
if se["passes_with_margin"]:
    assert ch["cost_bytes"] <= se["cost_bytes"] + 1e-6, (ch["cost_bytes"], se["cost_bytes"])
rate = r["parameters"]["bytes_per_triangle"]
for c in res["candidates"]:
    assert abs(c["cost_bytes"] - (c["memory_bytes"] + rate * c["triangles"])) < 1e-3 * max(1, c["cost_bytes"])
# a ladder state not rendered follows one of the same level, one halving fewer, whose statistic was 1
for c in res["candidates"]:
    if c.get("inferred"):
        prev = res["candidates"][c["index"] - 1]
        assert c["statistic"] == 1 and not c["pass"] and prev["level"] == c["level"], c
        assert prev["halvings"] == c["halvings"] - 1 and prev["statistic"] >= 1, (prev, c)
# the front: nobody dominates a point on it, and every point off it is dominated
cs = res["candidates"]
def dom(a, b):
    return (a["memory_bytes"] <= b["memory_bytes"] and a["triangles"] <= b["triangles"] and a["statistic"] <= b["statistic"]
            and (a["memory_bytes"] < b["memory_bytes"] or a["triangles"] < b["triangles"] or a["statistic"] < b["statistic"]))
for c in cs:
    if c["pareto"]:
        assert not any(dom(d, c) for d in cs), c
    else:
        assert any(dom(d, c) or (d["index"] < c["index"] and d["memory_bytes"] == c["memory_bytes"]
                   and d["triangles"] == c["triangles"] and d["statistic"] == c["statistic"]) for d in cs), c
lv = res["levels"]
assert lv[0]["level"] == ch["level"] and lv[0]["switch_distance"] == 0
assert res["passes"] and all(l["verification"]["pass"] for l in lv)
shown = [l for l in lv[1:] if l["switch_distance"] is not None]
assert shown, "a coarser level is shown somewhere"
prev = 0
for l in shown:
    assert l["switch_distance"] >= prev and l["verification"]["views"] == 2
    prev = l["switch_distance"]
    # Unreal ScreenSize and Unity's transition height: the sphere's projected diameter over the screen height
    e = l["engines"][0]
    assert abs(e["unreal_screen_size"] - l["switch_coverage"]) < 1e-9
    assert abs(e["unity_screen_relative_transition_height"] - l["switch_coverage"]) < 1e-9
    # a level seen only from afar samples at most the finer level's sizes ...
    for name, wh in l["sizes"].items():
        assert wh[0] <= ch["sizes"][name][0] and wh[1] <= ch["sizes"][name][1]
    # ... and where the sphere fills under a tenth of the height, fewer (000 §4: coarser mips only)
    if l["switch_coverage"] < 0.1:
        assert l["texture_bytes"] < ch["memory_bytes"], (l["level"], l["texture_bytes"], ch["memory_bytes"])
PY

check "the separate candidate is texres + pca + lod: pca's own choice per material, at texres's sizes" \
  python3 - "$T/a/budget.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
res = r["result"]
se, sp = res["separate"], res["separate_pca"]
assert res["separate_is"] == "texres + pca + lod" and [q["material"] for q in sp] == ["builtin"], sp
q = sp[0]
# pca's rendered choice on the file's maps; taken where its components, at texres's sizes, take fewer bytes
assert q["status"] in ("taken", "dearer than its images", "none passes"), q
if q["status"] != "none passes":
    assert 0 <= q["statistic"] <= r["parameters"]["criterion"]["p"], q
    assert (q["status"] == "taken") == (q["components_bytes"] < q["images_bytes"]), q
taken = q["status"] == "taken"
assert all((f == "pca") == taken for f in se["formats"].values()), se["formats"]
if taken:
    lay = se["pca_layouts"]["builtin"]
    assert lay["components"] == q["encoding"]["components"] == se["pca_components"]["builtin/baseColor"]
    # texres's maps are at most the file's: each component keeps pca's texels, no more than the set's
    assert all(0 <= a <= b for a, b in zip(lay["scale"], q["encoding"]["scale"])), (lay, q)
PY

# 001's packing refused: the built-in sphere's maps are independent patterns, and 3 or 4
# components are seen on every view (statistic 1) while 5 take more than its images; its
# baseColor in BC1 is not seen, and that is the choice
check "the sphere's choice: baseColor in BC1, its material not packed (PCA refused)" python3 - "$T/a/budget.json" <<'PY'
import json, sys
ch = json.load(open(sys.argv[1]))["result"]["chosen"]
assert ch["kind"] == "encoded" and ch["formats"]["builtin/baseColor"] == "bc1", ch["formats"]
assert "pca" not in ch["formats"].values() and "pca_components" not in ch, ch
PY

# 001's packing chosen: a ball whose three images (baseColor, metallicRoughness, occlusion)
# are affine in one pattern: one principal component rebuilds them, in BC4 a quarter of
# their bytes after baseColor's BC1
PYTHONPATH="$(dirname "$0")" python3 - "$T" <<'PY'
import math, struct, sys, zlib
from gltfwrite import write_ball
d, N = sys.argv[1], 64
def png(f):   # RGB, every channel affine in one pattern v (rank 1 once centred)
    raw = bytearray()
    for y in range(N):
        raw.append(0)
        for x in range(N):
            v = 0.5 + 0.4 * math.sin(0.21 * x + 0.13 * y) * math.cos(0.17 * y - 0.05 * x)
            raw.extend(max(0, min(255, int(round(c * 255)))) for c in f(v))
    ch = lambda t, b: struct.pack('>I', len(b)) + t + b + struct.pack('>I', zlib.crc32(t + b) & 0xffffffff)
    return (b'\x89PNG\r\n\x1a\n' + ch(b'IHDR', struct.pack('>IIBBBBB', N, N, 8, 2, 0, 0, 0))
            + ch(b'IDAT', zlib.compress(bytes(raw))) + ch(b'IEND', b''))
write_ball(d + "/ball.glb", [png(lambda v: (v, 0.2 + 0.6 * v, 0.9 - 0.5 * v)),
                             png(lambda v: (0, 0.3 + 0.5 * v, 0.7 - 0.6 * v)),
                             png(lambda v: (1 - 0.6 * v, 1 - 0.6 * v, 1 - 0.6 * v))])
PY
expect_exit 0 "cheapest unnoticed: a ball whose maps are one pattern passes" "$JND" budget "$T/ball.glb" -o "$T/p" \
  "${SMALL[@]}" --errors 0.03
check "... its material packed in one principal component (001), counted in BC4 with its mip chain" \
  env PYTHONPATH="$(dirname "$0")" python3 - "$T/p/budget.json" <<'PY'
import json, sys
from gltfwrite import mip_chain_bytes as chain
r = json.load(open(sys.argv[1]))["result"]
ch = r["chosen"]
assert ch["kind"] == "encoded" and ch["passes_with_margin"] and r["passes"], ch
assert set(ch["formats"].values()) == {"pca"} and set(ch["pca_components"].values()) == {1}, ch
w = max(max(wh) for wh in ch["sizes"].values())   # the set: the material's largest map
assert ch["memory_bytes"] == chain(w, w, 8), (ch["memory_bytes"], chain(w, w, 8))
unpacked = [c for c in r["candidates"] if c["kind"] != "encoded" and c.get("passes_with_margin") is True]
assert unpacked and all(ch["cost_bytes"] < c["cost_bytes"] for c in unpacked)
PY

check "... separately, pca's layout on texres's halved maps: each component keeps pca's texels (scales less texres's halvings)" \
  env PYTHONPATH="$(dirname "$0")" python3 - "$T/p/budget.json" <<'PY'
import json, math, sys
from gltfwrite import mip_chain_bytes as chain
res = json.load(open(sys.argv[1]))["result"]
se, q = res["separate"], [q for q in res["separate_pca"] if q["material"] == "ball"][0]
assert q["status"] == "taken", q
lay, enc = se["pca_layouts"]["ball"], q["encoding"]
w = max(max(wh) for wh in se["sizes"].values())   # texres's set; the file's is 64
d = int(round(math.log2(64 / w)))
assert d >= 1 and lay["scale"] == [max(0, k - d) for k in enc["scale"]], (d, lay, enc)
assert q["components_bytes"] == sum(chain(w >> k, w >> k, 8) for k in lay["scale"]), q
assert se["memory_bytes"] == q["components_bytes"], se
PY

# budget mode packs too: under the ball's images at their size, its material in one component at
# full size (001, BC4) is less visible than the maps halved (the searched size) or in BC1
"$JND" budget "$T/ball.glb" -o "$T/pb" --memory 2800B "${SMALL[@]}" --errors 0.03 >"$T/out.txt" 2>"$T/err.txt"
check "budget mode searches PCA packing: the ball's choice within 2800 B is its material packed, the least visible" \
  env PYTHONPATH="$(dirname "$0")" python3 - "$T/pb/budget.json" <<'PY'
import json, sys
from gltfwrite import mip_chain_bytes as chain
res = json.load(open(sys.argv[1]))["result"]
ch, M = res["chosen"], 2800
assert ch["kind"] == "encoded" and set(ch["formats"].values()) == {"pca"}, ch
assert ch["memory_bytes"] == chain(64, 64, 8) <= M and ch["packed_materials"] == 1, ch
plain = [c for c in res["candidates"] if c["packed_materials"] == 0 and c["memory_bytes"] <= M]
assert plain and ch["statistic"] < min(c["statistic"] for c in plain), (ch["statistic"], plain)
PY

# the written model: levels, MSFT_screencoverage, texture memory and triangles as budget.json says
check "memory and triangles recomputed from the written GLB" env PYTHONPATH="$(dirname "$0")" python3 - "$T/a/budget.json" "$T/a/model/builtin_sphere.glb" <<'PY'
import json, struct, sys
from gltfwrite import mip_chain_bytes as chain
r = json.load(open(sys.argv[1]))["result"]
data = open(sys.argv[2], "rb").read()
n = struct.unpack_from("<I", data, 12)[0]
g = json.loads(data[20:20 + n])
binoff = 20 + n + 8
node0 = g["nodes"][0]
ids = node0["extensions"]["MSFT_lod"]["ids"]
assert len(ids) + 1 == len(r["levels"])
cov = node0["extras"]["MSFT_screencoverage"]
assert len(cov) == len(r["levels"]) and all(a >= b for a, b in zip(cov, cov[1:]))
def tris(mesh):
    return sum(g["accessors"][p["indices"]]["count"] // 3 for p in g["meshes"][mesh]["primitives"])
assert tris(node0["mesh"]) == r["chosen"]["triangles"], (tris(node0["mesh"]), r["chosen"]["triangles"])
for j, nid in enumerate(ids):
    assert tris(g["nodes"][nid]["mesh"]) == r["levels"][j + 1]["triangles"]
# each image once, its PNG size, the block format its slots need, with its mip chain
def png_size(i):
    v = g["bufferViews"][g["images"][i]["bufferView"]]
    off = binoff + v.get("byteOffset", 0)
    return struct.unpack_from(">II", data, off + 16)
# the encoding budget.json gives each map (the slot's block format, or bc1 where chosen)
block = {"bc7": 16, "bc5": 16, "bc4": 8, "bc1": 8}   # bytes per 4x4 block
formats = r["chosen"]["formats"]
slots_of = {"baseColorTexture": "baseColor", "normalTexture": "normal", "occlusionTexture": "occlusion",
            "metallicRoughnessTexture": "metallicRoughness", "emissiveTexture": "emissive"}
need = {}
for m in g["materials"]:
    slots = dict(m.get("pbrMetallicRoughness", {}), **m)
    for k, slot in slots_of.items():
        if k in slots:
            img = g["textures"][slots[k]["index"]]["source"]
            need[img] = max(need.get(img, 0), block[formats[m["name"] + "/" + slot]])
mem = sum(chain(*png_size(i), b) for i, b in need.items())
assert mem == r["chosen"]["memory_bytes"], (mem, r["chosen"]["memory_bytes"])
PY

# the Khronos glTF-Validator: 0 errors (the pinned npm package, cached by scripts/install-deps.sh)
. "$(dirname "$0")/../../scripts/gltf_validator.sh"
if gltf_validator >/dev/null && command -v node >/dev/null; then
  check "the written model passes the Khronos glTF-Validator with 0 errors" \
    gltf_validator_run "$T/a/model/builtin_sphere.glb"
else
  echo "skip: the glTF-Validator check: gltf-validator@$GLTF_VALIDATOR_VERSION is not cached or node is missing (scripts/install-deps.sh)"
  if [ -n "${JND_NO_SKIP:-}" ]; then bad "the glTF-Validator check skipped, but JND_NO_SKIP is set"; fi
fi

nl=$(python3 -c 'import json,sys; print(len(json.load(open(sys.argv[1]))["result"]["levels"]))' "$T/a/budget.json")
for k in $(seq 0 $((nl - 1))); do
  expect_exit 0 "jnd render --lod $k renders written level $k" "$JND" render "$T/a/model/builtin_sphere.glb" --lod "$k" \
    -o "$T/r$k" --views 1 --size 48x48 --quiet
done

# budget mode: a memory budget below the separate choice's
sep=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["result"]["separate"]["memory_bytes"])' "$T/a/budget.json")
half=$((sep / 2))
"$JND" budget builtin:sphere -o "$T/b" --memory "${half}B" --triangles 3000 "${SMALL[@]}" >"$T/out.txt" 2>"$T/err.txt"
rc=$?
check "budget mode runs (exit 0 or 1: the statistic says how visible; rc $rc)" test "$rc" -le 1 -a -s "$T/b/budget.json"
check "budget mode: a candidate within the budget, the lowest statistic of those" python3 - "$T/b/budget.json" "$half" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); M = float(sys.argv[2])
assert r["parameters"]["mode"] == "budget"
res = r["result"]; ch = res["chosen"]
assert ch["memory_bytes"] <= M and ch["triangles"] <= 3000 and ch["statistic"] is not None
assert res["separate"]["memory_bytes"] > M
inb = [c for c in res["candidates"] if c["memory_bytes"] <= M and c["triangles"] <= 3000]
assert min(c["statistic"] for c in inb) == ch["statistic"]
PY

# budget mode where candidates of different statistics fit: the least visible is chosen
# (under half the separate memory every candidate that fits is seen, statistic 1). One
# byte under the separate memory the sphere's maps at the slots' formats that fit are all
# halved past what is unnoticed; budget mode's encoding search brings larger ones within
# the budget with BC1 for the baseColor, less visible than any of those
"$JND" budget builtin:sphere -o "$T/b2" --memory "$((sep - 1))B" "${SMALL[@]}" >"$T/out.txt" 2>"$T/err.txt"
check "budget mode under the separate memory: of candidates seen differently, the least visible" python3 - "$T/b2/budget.json" "$((sep - 1))" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); M = float(sys.argv[2])
res = r["result"]; ch = res["chosen"]
inb = [c for c in res["candidates"] if c["memory_bytes"] <= M and c["statistic"] is not None]
assert len({c["statistic"] for c in inb}) >= 2, inb
assert ch["statistic"] == min(c["statistic"] for c in inb), (ch["statistic"], inb)
PY
check "budget mode searches encodings: the choice is an encoded candidate within the budget, less visible than every one at the slots' formats" \
  python3 - "$T/b2/budget.json" "$((sep - 1))" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); M = float(sys.argv[2])
res = r["result"]; ch = res["chosen"]
assert ch["kind"] == "encoded" and ch["memory_bytes"] <= M, ch
assert any(f == "bc1" for n, f in ch["formats"].items() if n.split("/")[-1] in ("baseColor", "normal")), ch["formats"]
plain = [c for c in res["candidates"] if c["kind"] != "encoded" and c["memory_bytes"] <= M]
assert plain and ch["statistic"] < min(c["statistic"] for c in plain), (ch["statistic"], plain)
enc = [c for c in res["candidates"] if c["kind"] == "encoded"]
assert all(c["memory_bytes"] <= M for c in enc)
key = lambda c: (c["level"], c["memory_bytes"], c["statistic"], c["packed_materials"])
assert len({key(c) for c in enc}) == len(enc), "an encoded variant made twice"
PY

# a budget nothing meets: one line naming the smallest possible, nothing written
expect_exit 2 "a budget nothing meets: exit 2" "$JND" budget builtin:sphere -o "$T/c" --memory 1KiB "${SMALL[@]}"
check "... one line naming the smallest possible" sh -c "grep -q 'smallest possible is' '$T/err.txt' && [ \$(wc -l <'$T/err.txt') -eq 1 ]"
check "... nothing written" test ! -e "$T/c"

# jnd batch runs budget rows: the summary's costs and decision, the asset's page with its levels
{
  echo "id,asset,command,options"
  echo "sph,builtin:sphere,budget,\"${SMALL[*]/--quiet/}\""
} >"$T/m.csv"
expect_exit 0 "jnd batch runs a budget row" "$JND" batch "$T/m.csv" -o "$T/batch" --quiet
expect_exit 0 "... merged" "$JND" batch merge "$T/batch" --quiet
expect_exit 0 "... reported" "$JND" report "$T/batch" --quiet
check "... summary.json: the file's cost before, the chosen after, the decision against texres + pca + lod" \
  python3 - "$T/batch/summary.json" "$T/batch/sph/budget.json" <<'PY'
import json, sys
a = json.load(open(sys.argv[1]))["result"]["assets"][0]
r = json.load(open(sys.argv[2]))["result"]
assert a["command"] == "budget" and a["status"] == "ok", a
assert a["memory_before_bytes"] == r["comparison"]["original_cost_bytes"]
assert a["memory_after_bytes"] == r["comparison"]["chosen_cost_bytes"]
assert a["decision"].startswith("level %d, " % r["chosen"]["level"]) and "texres + pca + lod separately" in a["decision"], a["decision"]
PY
check "... the asset's page shows the written levels and pareto.png" \
  sh -c "grep -q 'Written levels' '$T/batch/report/sph.html' && grep -q 'pareto.png' '$T/batch/report/sph.html'"

# bad input: one line, exit 2, nothing written
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$T/plain.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\n' >"$T/points.obj"
bad_cases=("--memory 0" "--memory -8MiB" "--memory 8XiB" "--triangles 0" "--triangles -5")
for opt in "${bad_cases[@]}"; do
  # shellcheck disable=SC2086
  expect_exit 2 "budget $opt: exit 2" "$JND" budget builtin:sphere -o "$T/d" $opt "${SMALL[@]}"
  check "budget $opt: one line, nothing written" sh -c "[ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q '^jnd: ' '$T/err.txt' && [ ! -e '$T/d' ]"
done
expect_exit 2 "an asset without maps: exit 2" "$JND" budget "$T/plain.obj" -o "$T/e" "${SMALL[@]}"
check "... one line naming the file, nothing written" sh -c "[ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q 'plain.obj: .*no texture maps' '$T/err.txt' && [ ! -e '$T/e' ]"
expect_exit 2 "an asset without a mesh: exit 2" "$JND" budget "$T/points.obj" -o "$T/f" "${SMALL[@]}"
check "... one line, nothing written" sh -c "[ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q '^jnd: ' '$T/err.txt' && [ ! -e '$T/f' ]"
expect_exit 2 "an output over the input: exit 2" "$JND" budget "$T/plain.obj" -o "$T" "${SMALL[@]}"
check "--help is complete" sh -c "'$JND' budget --help | grep -q -- '--bytes-per-triangle' && '$JND' budget --help | grep -q 'screenRelativeTransitionHeight'"
finish
