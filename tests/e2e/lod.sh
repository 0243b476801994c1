#!/usr/bin/env bash
# jnd lod: the chain, 003's analysis per screen, the report's fields, the
# model with every level (loads back in jnd render with each level
# selectable, triangles as in lod.json), determinism, and bad input (one
# line, exit 2, nothing written, the input untouched).
set -uo pipefail
. "$(dirname "$0")/lib.bash"
need_renderer
SMALL=(--screens 320x240,800x600@40 --views 1 --map-size 64 --surface-samples 4096 --quiet
       --judge-views 1 --max-px 96 --tolerance 0.5 --far-coverage 0.05)

expect_exit 0 "builtin:sphere runs" "$JND" lod builtin:sphere -o "$T/a" "${SMALL[@]}"
check "lod.json has the fields issue 11 names" python3 - "$T/a/lod.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
assert r["command"] == "lod" and "jnd_version" in r and "inputs" in r and "parameters" in r
res = r["result"]
lv = res["levels"]
assert res["chain_source"] == "made" and lv[0]["method"] == "input" and lv[0]["error"] == 0
assert len(lv) >= 5
for a, b in zip(lv, lv[1:]):
    assert b["triangles"] < a["triangles"] and b["error"] >= a["error"], (a, b)
    assert b["error"] <= b["target_error"] * (1 + 1e-5), b
    assert b["distance_rms"] >= 0 and b["distance_max"] >= b["distance_rms"]
assert [s["name"] for s in res["screens"]] == ["320x240", "800x600"]
for s in res["screens"]:
    assert s["width_px"] > 0 and s["height_px"] > 0 and len(s["curve"]) == len(lv)
    for k, c in enumerate(s["curve"]):
        assert c["level"] == k and c["error"] >= 0 and c["error_lit"] >= 0
        assert abs(c["error"] - (c["object"] + c["e_p"])) < 1e-12                 # eq. 1
        assert abs(c["error_lit"] - c["error"] * c["m_p"]) < 1e-12 * (1 + c["error"])  # eq. 3
    assert s["curve"][0]["object"] == 0 and s["curve"][0]["m_p"] == 0
    # a curve that stays flat and then rises has its knee inside the chain
    assert 0 < s["poi_level"] < len(lv) - 1 and s["poi_triangles"] == lv[s["poi_level"]]["triangles"]
    assert 0 < s["poi_level_unlit"] < len(lv) - 1 and s["poi_triangles_unlit"] == lv[s["poi_level_unlit"]]["triangles"]
    assert s["poi_level"] >= s["poi_level_unlit"]        # lit never finer than unlit here
    # the perceptual choice (through the judge) and the switch distances
    n = len(lv)
    assert 0 <= s["perceptual_level"] < n and s["perceptual_triangles"] == lv[s["perceptual_level"]]["triangles"]
    sd, sc = s["switch_distance_m"], s["switch_coverage"]
    assert len(sd) == n and len(sc) == n and sd[0] == 0 and sc[0] == 1
    inf = float("inf")
    d = [inf if x is None else x for x in sd]
    assert all(a <= b for a, b in zip(d, d[1:])), sd                   # monotone in the level
    assert all(a >= b for a, b in zip(sc, sc[1:])), sc
    # each switch distance is the farthest of the criterion's, the popping one's and the finer level's
    da = [inf if x is None else x for x in s["switch_distance_criterion_m"]]
    db = [None if k == 0 or not s["pop"][k - 1]["searched"] else inf if x is None else x
          for k, x in enumerate(s["switch_distance_pop_m"])]
    assert s["switch_by"][0] == "reference" and len(s["pop"]) == n - 1
    for k in range(1, n):
        want = max(da[k], db[k] if db[k] is not None else -inf, d[k - 1])
        assert d[k] == want, (k, d[k], want)
        # popping decides only beyond both the criterion and the finer level (its search starts there)
        by = "popping" if db[k] is not None and db[k] > max(da[k], d[k - 1]) else \
             "finer level" if d[k - 1] > da[k] else "criterion"
        assert s["switch_by"][k] == by, (k, s["switch_by"][k], by)
        row = s["pop"][k - 1]
        assert row["level"] == k
        if row["searched"] and not row["never"]:
            assert row["max_rating"] is None or row["max_rating"] < 1   # R < 1 where written (null: no region)
    if d[1] < inf:
        assert s["pop"][0]["searched"] and s["pop_evaluations"] > 0  # popping on by default
    vc = s["viewing_condition"]
    assert abs(vc["coverage"] - 0.5) < 1e-9 and vc["window_px"] == 96 and 0 < vc["scale"] < 1
    # each switch judged at its own distance's scale: at least the viewing condition's, growing with
    # the distance, at most the screen's own (1)
    ss = s["switch_scale"]
    assert ss[0] is None and all((ss[k] is None) == (da[k] == inf) for k in range(1, n)), ss
    known = [(da[k], ss[k]) for k in range(1, n) if ss[k] is not None]
    assert all(vc["scale"] - 1e-12 <= x <= 1 for _, x in known), ss
    assert all(a[1] <= b[1] for a, b in zip(known, known[1:])), known
    for k in range(1, n):
        if sd[k] is not None:
            assert sd[k] >= vc["distance"] * (1 - 1e-12) and 0 < sc[k] <= 0.5 + 1e-9
        else:
            assert sc[k] == 0
    # the perceptual level passed at the viewing condition: its statistic is at most p
    if s["perceptual_level"] > 0:
        assert s["statistic"][s["perceptual_level"]] <= r["parameters"]["perceptual"]["criterion"]["p"]
    assert s["statistic"][0] == 0 and s["p_max"][0] == 0
    assert s["rules"]["meshopt"]["level"] <= len(lv) - 1
    assert s["pareto_png"] == "pareto_%s.png" % s["name"]
assert "pending" not in res
# a smaller screen never gets a finer meshoptimizer-rule level (pixels scale with the screen)
assert res["screens"][0]["rules"]["meshopt"]["level"] >= res["screens"][1]["rules"]["meshopt"]["level"]
t = res["textures"][0]
assert t["name"] == "builtin/baseColor" and t["levels"][0] == [64, 64] and len(t["screens"]) == 2
m = res["model"]
assert m["path"] == "model/builtin_sphere.glb" and len(m["screen_coverage"]) == len(lv)
assert all(a >= b for a, b in zip(m["screen_coverage"], m["screen_coverage"][1:])) and m["screen_coverage"][-1] == 0
# MSFT_screencoverage from the first screen's switch coverages (projected sphere area over screen area)
import math
s0 = res["screens"][0]
assert "perceptual switch distances" in m["screen_coverage_rule"]
# which screen's: said, never silently the first of --screens
assert "on 320x240 (320x240), the first of 2 screens" in m["screen_coverage_rule"], m["screen_coverage_rule"]
for k in range(len(lv) - 1):
    c = min(s0["switch_coverage"][k + 1], 1.0)
    want = min(math.pi * c * c * s0["height_px"] / (4 * s0["width_px"]), m["screen_coverage"][k - 1] if k else 1)
    assert abs(m["screen_coverage"][k] - want) < 1e-9, (k, m["screen_coverage"][k], want)
PY
check "the rules' pixels are the deviations seen at the coverage (recomputed from the sphere, the extent and the screen), and their levels the last within the documented 1 and 0.5 pixels" python3 - "$T/a/lod.json" <<'PY'
import json, math, sys
r = json.load(open(sys.argv[1]))
par, res = r["parameters"], r["result"]
# docs/lod.md: meshoptimizer's error within 1 pixel, the measured deviation within 0.5
assert par["meshopt_pixels"] == 1 and par["pixel_error"] == 0.5, (par["meshopt_pixels"], par["pixel_error"])
lv, R, ext = res["levels"], res["radius"], res["extent"]
# the sphere of radius R fills `coverage` of the height: its half-angle t has
# tan t = coverage·tan(fov/2), the camera is R/sin t away, and one object
# unit spans object_px·cos(t)/(2R) pixels there
t = math.atan(par["coverage"] * math.tan(math.radians(par["fov_y_deg"]) / 2))
for s in res["screens"]:
    assert s["object_px"] == round(par["coverage"] * s["height_px"]), (s["object_px"], s["height_px"])
    ppu = s["object_px"] * math.cos(t) / (2 * R)
    mo, pe = s["rules"]["meshopt"], s["rules"]["pixel_error"]
    want_mo = want_pe = 0
    for k, c in enumerate(s["curve"]):
        dev = lv[k]["distance_max"] * ext * ppu
        err = lv[k]["error_abs"] if lv[k]["error_abs"] is not None else lv[k]["distance_max"] * ext
        assert abs(c["deviation_px"] - dev) <= 1e-6 * dev + 1e-9, (s["name"], k, c["deviation_px"], dev)
        assert abs(c["meshopt_px"] - err * ppu) <= 1e-6 * err * ppu + 1e-9, (s["name"], k, c["meshopt_px"], err * ppu)
        if c["meshopt_px"] <= mo["pixels"]: want_mo = k
        if c["deviation_px"] <= pe["pixels"]: want_pe = k
    assert (mo["level"], pe["level"]) == (want_mo, want_pe), (s["name"], mo, pe, want_mo, want_pe)
    assert mo["triangles"] == lv[want_mo]["triangles"] and pe["triangles"] == lv[want_pe]["triangles"]
    assert max(c["deviation_px"] for c in s["curve"]) > pe["pixels"], s["name"]   # the rule had a choice
PY
check "the Pareto plots are PNGs" python3 - "$T/a" <<'PY'
import sys
for n in ("pareto_320x240.png", "pareto_800x600.png"):
    assert open(sys.argv[1] + "/" + n, "rb").read(8) == b"\x89PNG\r\n\x1a\n", n
PY

# a texture covers `coverage` of the screen's height whatever its width: on a
# screen twice as wide it is shown at the same size, so its E_p sums are the
# same and E_p (normalised by the screen's pixels, 003 eq. 2) is 1/√2 of it
expect_exit 0 "two screens of one height run" "$JND" lod builtin:sphere -o "$T/wide" --screens 320x240@40,640x240@40 \
  --views 1 --map-size 64 --surface-samples 4096 --no-perceptual --quiet
check "a texture's on-screen size comes from the screen's height, not its width" python3 - "$T/wide/lod.json" <<'PY'
import json, math, sys
t = json.load(open(sys.argv[1]))["result"]["textures"][0]
narrow, wide = (s["curve"] for s in t["screens"])
assert len(narrow) > 2 and any(c["e_p"] > 0 for c in narrow), narrow
for a, b in zip(narrow, wide):
    assert abs(b["e_p"] - a["e_p"] * math.sqrt(320 / 640)) <= 1e-9 + 1e-6 * a["e_p"], (a, b)
PY

# the written model: MSFT_lod with every level, each selectable in jnd render
GLB="$T/a/model/builtin_sphere.glb"
check "the model is a GLB with MSFT_lod and MSFT_screencoverage" python3 - "$GLB" "$T/a/lod.json" <<'PY'
import json, struct, sys
b = open(sys.argv[1], "rb").read()
assert b[:4] == b"glTF"
n = struct.unpack("<I", b[12:16])[0]
g = json.loads(b[20:20 + n])
lv = json.load(open(sys.argv[2]))["result"]["levels"]
node = g["nodes"][0]
assert "MSFT_lod" in g["extensionsUsed"]
assert node["extensions"]["MSFT_lod"]["ids"] == list(range(1, len(lv)))
assert len(node["extras"]["MSFT_screencoverage"]) == len(lv)
assert g["scenes"][0]["nodes"] == [0]
for k, l in enumerate(lv):
    mesh = g["meshes"][g["nodes"][k]["mesh"]]
    tris = sum(g["accessors"][p["indices"]]["count"] // 3 for p in mesh["primitives"])
    assert tris == l["triangles"], (k, tris, l["triangles"])
PY
"$JND" render "$GLB" --list-lods >"$T/lods.txt" 2>/dev/null
check "jnd render lists the levels with the JSON's triangles" python3 - "$T/lods.txt" "$T/a/lod.json" <<'PY'
import json, sys
got = [int(line.split()[2]) for line in open(sys.argv[1]) if line.startswith("level")]
want = [l["triangles"] for l in json.load(open(sys.argv[2]))["result"]["levels"]]
assert got == want, (got, want)
PY
n=$(python3 -c "import json,sys; print(len(json.load(open(sys.argv[1]))['result']['levels']))" "$T/a/lod.json")
for k in 0 $((n / 2)) $((n - 1)); do
  expect_exit 0 "jnd render --lod $k renders level $k" "$JND" render "$GLB" --lod "$k" -o "$T/r$k" --views 1 --size 64x64 --quiet --json "$T/r$k.json"
  check "level $k is drawn with its triangles" python3 - "$T/r$k.json" "$T/a/lod.json" "$k" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["result"]
lv = json.load(open(sys.argv[2]))["result"]["levels"]
k = int(sys.argv[3])
assert r["lod"] == k and r["triangles"] == lv[k]["triangles"], (r["triangles"], lv[k]["triangles"])
PY
done
expect_exit 2 "jnd render --lod past the chain: exit 2" "$JND" render "$GLB" --lod "$n" -o "$T/rx" --views 1 --size 64x64
check "one line" one_line_error

# the chain the file has is analysed, not made again
expect_exit 0 "the written model's chain is taken as it is" "$JND" lod "$GLB" -o "$T/b" --chain-only --quiet
check "chain_source is file, same triangles" python3 - "$T/b/lod.json" "$T/a/lod.json" <<'PY'
import json, sys
b, a = (json.load(open(p))["result"] for p in sys.argv[1:3])
assert b["chain_source"] == "file" and [l["method"] for l in b["levels"][1:]] == ["imported"] * (len(b["levels"]) - 1)
assert [l["triangles"] for l in b["levels"]] == [l["triangles"] for l in a["levels"]]
PY
check "a glTF input written again: every material is drawn, none added (assimp's default material left out)" python3 - "$T/b" "$GLB" <<'PY'
import glob, json, struct, sys
def doc(path):
    b = open(path, "rb").read()
    n, = struct.unpack_from("<I", b, 12)
    return json.loads(b[20:20 + n])
out, src = doc(glob.glob(sys.argv[1] + "/model/*.glb")[0]), doc(sys.argv[2])
drawn = {p["material"] for m in out["meshes"] for p in m["primitives"]}
assert drawn == set(range(len(out["materials"]))), (drawn, len(out["materials"]))
assert len(out["materials"]) == len(src["materials"]), (len(out["materials"]), len(src["materials"]))
PY
# levels from files given on the command line
"$JND" lod builtin:sphere -o "$T/c" --errors 0.01 --chain-only --map-size 64 --quiet
expect_exit 0 "--level files make the chain" "$JND" lod builtin:sphere --level "$T/c/model/builtin_sphere.glb" -o "$T/d" --chain-only --map-size 64 --quiet
check "the chain is the input and the file's level 0" python3 - "$T/d/lod.json" "$T/c/lod.json" <<'PY'
import json, sys
d, c = (json.load(open(p))["result"] for p in sys.argv[1:3])
assert d["chain_source"] == "levels" and len(d["levels"]) == 2
assert d["levels"][1]["triangles"] == c["levels"][0]["triangles"] and d["levels"][1]["source"].endswith(".glb")
PY

# a built-in asset's options load what jnd render loads (one chain loader, jnd_scene_open's)
"$JND" render builtin:box,parts=3 -o "$T/rparts" --views 1 --size 16x16 --map-size 16 --quiet
expect_exit 0 "builtin:box,parts=3 runs" "$JND" lod builtin:box,parts=3 -o "$T/parts" --chain-only --map-size 16 --quiet
check "builtin:box,parts=3: level 0 is what jnd render loads (triangles, materials)" python3 - "$T/rparts/views.json" "$T/parts/lod.json" "$T/parts" <<'PY2'
import json, struct, sys
r = json.load(open(sys.argv[1]))["result"]
l = json.load(open(sys.argv[2]))["result"]
glb = open(sys.argv[3] + "/" + l["model"]["path"], "rb").read()
n, = struct.unpack_from("<I", glb, 12)
g = json.loads(glb[20:20 + n])
assert r["materials"] == 3 and l["levels"][0]["triangles"] == r["triangles"], (r["triangles"], l["levels"][0])
assert len(g["materials"]) == r["materials"], len(g["materials"])
PY2

# without the perceptual step: null, said so, and the model's coverages by meshoptimizer's rule
expect_exit 0 "--no-pop runs" "$JND" lod builtin:sphere -o "$T/nopop" "${SMALL[@]}" --no-pop --no-textures --screens 320x240
check "--no-pop: switch distances from the criterion alone" python3 - "$T/nopop/lod.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
assert r["parameters"]["perceptual"]["pop"]["enabled"] is False
for s in r["result"]["screens"]:
    assert s["switch_distance_m"] == s["switch_distance_criterion_m"]
    assert all(x is None for x in s["switch_distance_pop_m"]) and not any(p["searched"] for p in s["pop"])
    assert all(b in ("reference", "criterion") for b in s["switch_by"]) and s["pop_evaluations"] == 0
PY
expect_exit 2 "--pop-motion of another kind: exit 2" "$JND" lod builtin:sphere -o "$T/x" --pop-motion walk
check "one line" one_line_error
expect_exit 0 "--no-perceptual runs" "$JND" lod builtin:sphere -o "$T/np" "${SMALL[@]}" --no-perceptual --no-textures
check "--no-perceptual: null fields, the rule named" python3 - "$T/np/lod.json" <<'PY'
import json, sys
res = json.load(open(sys.argv[1]))["result"]
assert all(s["perceptual_level"] is None and s["switch_distance_m"] is None for s in res["screens"])
assert "meshoptimizer" in res["model"]["screen_coverage_rule"] and "perceptual" in res
PY

# the same command gives the same report, whatever the thread count
"$JND" lod builtin:sphere -o "$T/e" "${SMALL[@]}" --threads 1
check "deterministic (threads 1, and the default: the screens judged in parallel, beside 003's analysis)" cmp -s "$T/a/lod.json" "$T/e/lod.json"

# bad input: one line, exit 2, nothing written, the input untouched
B="$T/bad"
mkdir -p "$B"
: >"$B/empty.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\n' >"$B/nofaces.obj"
printf 'v 0 0 0\nv 1 0 0\nv inf 1 0\nf 1 2 3\n' >"$B/inf.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n' >"$B/range.obj"
printf 'v 0 0 0\nv 1 1 1\nv 2 2 2\nv 3 3 3\nf 1 2 3\nf 2 3 4\n' >"$B/flat.obj"
python3 - "$B" <<'PY'
import base64, json, struct, sys
pos = [(0, 0, 0), (1, 0, 0), (float("nan"), 1, 0)]
pb = b"".join(struct.pack("<3f", *p) for p in pos); ib = struct.pack("<3I", 0, 1, 2)
buf = pb + ib
g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
     "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
     "buffers": [{"byteLength": len(buf), "uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode()}],
     "bufferViews": [{"buffer": 0, "byteLength": len(pb)}, {"buffer": 0, "byteOffset": len(pb), "byteLength": len(ib)}],
     "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                   {"bufferView": 1, "componentType": 5125, "count": 3, "type": "SCALAR"}]}
open(sys.argv[1] + "/nan.gltf", "w").write(json.dumps(g))
g["nodes"][0]["extensions"] = {"MSFT_lod": {"ids": [5]}}
open(sys.argv[1] + "/badlod.gltf", "w").write(json.dumps(g))
PY
for f in empty.obj:"empty" nofaces.obj:"no faces" inf.obj:"not finite" nan.gltf:"not finite" range.obj:"out of range" \
         flat.obj:"zero area" badlod.gltf:"MSFT_lod"; do
  file=${f%%:*} why=${f#*:}
  sum=$(md5sum "$B/$file" | cut -c1-32)
  expect_exit 2 "$file: exit 2" "$JND" lod "$B/$file" -o "$T/x_$file" --chain-only
  check "$file: one line saying '$why'" bash -c "[ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q '^jnd: .*$file' '$T/err.txt' && grep -qi '$why' '$T/err.txt'"
  check "$file: nothing written" [ ! -e "$T/x_$file" ]
  check "$file: the input is unchanged" [ "$(md5sum "$B/$file" | cut -c1-32)" = "$sum" ]
done
# the viewing task (docs/model.md "Viewing task"): side by side by default, --task through the shared parser,
# popping always flickered (a switch in place)
check "the default task is side by side; popping is judged flickered" \
  jq -e '.parameters.perceptual.task == "side-by-side" and .parameters.perceptual.pop.task == "flicker"' "$T/a/lod.json"
expect_exit 0 "--task flicker is taken" "$JND" lod builtin -o "$T/task" --task flicker --chain-only --map-size 16 --quiet
check "--task flicker is the judges' task; popping's stays flicker" \
  jq -e '.parameters.perceptual.task == "flicker" and .parameters.perceptual.pop.task == "flicker"' "$T/task/lod.json"
expect_exit 2 "an unknown task: exit 2" "$JND" lod builtin -o "$T/x" --task toggle --map-size 16
check "one line naming --task" bash -c "[ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q -- '--task' '$T/err.txt'"
expect_exit 2 "an unknown screen: exit 2" "$JND" lod builtin -o "$T/x" --screens vr
check "one line naming it" bash -c "[ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q 'vr' '$T/err.txt'"
expect_exit 2 "falling error targets: exit 2" "$JND" lod builtin -o "$T/x" --errors 0.01,0.001 --map-size 16
check "one line" one_line_error
expect_exit 2 "error targets that are not numbers: exit 2" "$JND" lod builtin -o "$T/x" --errors 0.01,abc --map-size 16
check "one line naming --errors" bash -c "[ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q -- '--errors' '$T/err.txt'"
# --errors: one parser (src/cli/args.c) for every command that makes a chain: fractions as gaze --help and
# docs/gaze.md write them, one range [1e-6, 1], rising
expect_exit 0 "--errors takes fractions" "$JND" lod builtin -o "$T/frac" --errors 1/1024,0.001,1/256 --chain-only --map-size 16 --quiet
check "--errors fractions are the numbers they name" jq -e '.parameters.chain.errors == [0.0009765625, 0.001, 0.00390625]' "$T/frac/lod.json"
for cmd in lod pop gaze "gaze observers"; do
  for bad in 0 2 1e-7 1/0 1/-4 0.01,1/1024 1/1024,x; do
    expect_exit 2 "$cmd --errors $bad: exit 2" "$JND" $cmd builtin -o "$T/x" --errors "$bad" --map-size 16
    check "$cmd --errors $bad: one line naming --errors" bash -c "[ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q -- '^jnd: --errors: ' '$T/err.txt'"
    [ "$bad" = 1e-7 ] && check "$cmd --errors 1e-7: the one range" grep -qF -- '--errors: 1e-07 is outside [1e-06, 1]' "$T/err.txt"
  done
done
check "nothing written for a bad --errors" [ ! -e "$T/x" ]
# one limit on views (JND_VIEWS_MAX, 4096): the library's and every command's parser, for both kinds of views
for opt in --views --judge-views; do
  expect_exit 2 "$opt 4097: exit 2" "$JND" lod builtin -o "$T/x" "$opt" 4097 --map-size 16
  check "$opt 4097: one line naming the limit" bash -c "[ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q -- \"^jnd: $opt: 4097 is outside \\[1, 4096\\]\" '$T/err.txt'"
done
# issue 28: a bad perceptual option is refused before any work, in one line, writing nothing (the library
# checks them too before 003's analysis: unit.test_lod's bad_perceptual_options_are_refused_before_any_work)
for bad in "--tolerance 0.0005" "--max-px 31" "--judge-views 0"; do
  expect_exit 2 "$bad: exit 2" "$JND" lod builtin -o "$T/x" $bad
  check "$bad: one line naming the option, nothing written" bash -c "[ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -q -- '^jnd: ${bad% *}' '$T/err.txt' && [ ! -e '$T/x' ]"
done
check "--help states the limit" bash -c "'$JND' lod --help | grep -- '--judge-views N .*1\.\.4096' >/dev/null"
expect_exit 2 "a --level file with another material: exit 2" "$JND" lod builtin --level "$B/range.obj" -o "$T/x" --map-size 16
check "nothing written for bad options" [ ! -e "$T/x" ]
check "--help prints the usage" bash -c "'$JND' lod --help | grep -- '--screens' >/dev/null"
finish
