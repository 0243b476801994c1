#!/usr/bin/env bash
# jnd render: the manifest, the outputs, determinism, map edits and the errors.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
need_renderer
# checke 'EXPRESSION' NAME: the expression is evaluated (it may use $T and pipes)
checke() { if eval "$1"; then ok "$2"; else bad "$2"; fi; }
MODELS=/usr/share/assimp/models
command -v python3 >/dev/null || skip "needs python3"

# the builtin asset, every output
"$JND" render builtin --map-size 256 -o "$T/a" --views 3 --size 96x64 --seed 7 \
    --outputs color,depth,mask,motion,mip --quiet
checke '[ $? -eq 0 ] && [ -f "$T/a/views.json" ]' "builtin renders and writes views.json"
checke 'python3 - "$T/a" <<"PY"
import json, os, sys
d = sys.argv[1]
m = json.load(open(os.path.join(d, "views.json")))
assert m["command"] == "render" and len(m["views"]) == 3
for v in m["views"]:
    for k in ("color", "depth", "mask", "motion", "mip"):
        assert os.path.isfile(os.path.join(d, v[k])), (k, v[k])
    assert 0.05 < v["coverage"] < 0.9, v["coverage"]
    assert len(v["lights"]) == 1 and "eye" in v["camera"] and "prev_camera" in v
assert [x["name"] for x in m["maps"]] == ["builtin/baseColor", "builtin/metallicRoughness", "builtin/normal", "builtin/occlusion"]
assert all("mip_min" in x for x in m["maps"])
PY' "views.json lists every output, the cameras, lights and maps"

# determinism: the same command gives identical images
"$JND" render builtin --map-size 256 -o "$T/b" --views 3 --size 96x64 --seed 7 \
    --outputs color,depth,mask,motion,mip --quiet
same=1
for f in "$T"/a/*.png; do cmp -s "$f" "$T/b/$(basename "$f")" || same=0; done
checke '[ $same -eq 1 ]' "the same command gives identical images"
checke 'cmp -s "$T/a/views.json" "$T/b/views.json"' "and an identical manifest"

# another seed moves the cameras
"$JND" render builtin --map-size 256 -o "$T/c" --views 1 --size 64x64 --seed 8 --quiet
checke '! cmp -s "$T/a/view_000.png" "$T/c/view_000.png"' "another seed gives another view"

# map edits: a halved albedo changes the image, --scale of the original size does not
"$JND" render builtin --map-size 256 -o "$T/d" --views 1 --size 64x64 --quiet
"$JND" render builtin --map-size 256 -o "$T/e" --views 1 --size 64x64 --quiet --scale builtin/baseColor=0.125
"$JND" render builtin --map-size 256 -o "$T/f" --views 1 --size 64x64 --quiet --scale 'builtin/baseColor=256x256'
checke '! cmp -s "$T/d/view_000.png" "$T/e/view_000.png"' "--scale resamples a map"
checke 'cmp -s "$T/d/view_000.png" "$T/f/view_000.png"' "--scale to the original size changes nothing"
checke 'python3 -c "import json,sys; m=json.load(open(sys.argv[1])); assert m[\"maps\"][0][\"width\"]==32" "$T/e/views.json"' \
    "views.json records the resolution used"
"$JND" render builtin --map-size 256 -o "$T/g" --views 1 --size 64x64 --quiet --replace "builtin/normal=$JND_SRC/tests/data/render/builtin_128.png"
checke '[ $? -eq 0 ] && ! cmp -s "$T/d/view_000.png" "$T/g/view_000.png"' "--replace swaps a map for an image file"
checke '"$JND" render builtin --map-size 64 --list-maps | grep -q "builtin/normal"' "--list-maps names the maps"

# explicit cameras, including a views.json written before
"$JND" render builtin --map-size 256 -o "$T/h" --size 96x64 --cameras "$T/a/views.json" --quiet
checke 'cmp -s "$T/a/view_002.png" "$T/h/view_002.png"' "a views.json given back as --cameras reproduces the views"

# a bad environment: one line naming the file, exit 2, nothing written; the
# renderer keeps the last prepared environment, so a good one after it still
# lights the scene
expect_exit 2 "a missing environment file is refused" \
    "$JND" render builtin --size 64x64 --views 1 --map-size 64 --env "$T/none.hdr" -o "$T/env1" --quiet
checke 'one_line_error && grep -q "none.hdr" "$T/err.txt" && [ ! -e "$T/env1" ]' "in one line naming it, nothing written"
expect_exit 2 "an 8-bit environment is refused" \
    "$JND" render builtin --size 64x64 --views 1 --map-size 64 --env "$T/a/view_000.png" -o "$T/env2" --quiet
checke 'one_line_error && grep -q "must be linear" "$T/err.txt" && [ ! -e "$T/env2" ]' "in one line: it must be linear"

# errors: one line "jnd: FILE: problem", exit 2, nothing written
err() {  # expected-substring, args...
  local want=$1; shift
  "$JND" render "$@" >"$T/out" 2>"$T/err"; local rc=$?
  [ $rc -eq 2 ] && [ "$(wc -l <"$T/err")" -eq 1 ] && grep -q "^jnd: .*$want" "$T/err" || { cat "$T/err"; return 1; }
}
checke 'err "no such file" /nonexistent.glb -o "$T/x"' "a missing model: exit 2, one line"
# a corrupt .glb/.gltf is said to be one (not guessed as another format by content: assimp's OBJ reader once
# answered "OBJ: Invalid face index" for it)
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n' >"$T/objlike.glb"
printf 'glTF\002\000\000\000\100\000\000\000\377\000\000\000JSON{"asset":' >"$T/short.glb"
printf '{"asset": {"version": "2.0"}, oops' >"$T/broken.gltf"
checke 'err "objlike.glb: GLB parse error" "$T/objlike.glb" -o "$T/x" && ! grep -q OBJ "$T/err"' \
    "a .glb that is not one: one line, a GLB parse error naming the file, no OBJ"
checke 'err "short.glb: GLB parse error" "$T/short.glb" -o "$T/x"' "a .glb whose JSON chunk runs past its end: a GLB parse error"
checke 'err "broken.gltf: glTF parse error: the JSON does not parse" "$T/broken.gltf" -o "$T/x"' \
    "a .gltf whose JSON is broken: a glTF parse error"
if [ -d "$MODELS" ]; then
  for f in glTF2/MissingBin/BoxTextured.gltf glTF2/RecursiveNodes/RecursiveNodes.gltf \
           glTF2/wrongTypes/badNumber.gltf glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb \
           glTF2/TestNoRootNode/NoScene.gltf; do
    checke "err '$MODELS/$f' '$MODELS/$f' -o '$T/x'" "broken $(basename "$f"): exit 2, one line naming it"
  done
  head -c 1000 "$MODELS/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb" >"$T/trunc.glb"
  checke 'err "trunc.glb" "$T/trunc.glb" -o "$T/x"' "a truncated .glb: exit 2"
  # a missing texture falls back to the factor with a warning, or fails with --strict
  mkdir -p "$T/missing"
  sed 's/CesiumLogoFlat.png/nothere.png/' "$MODELS/glTF2/BoxTextured-glTF/BoxTextured.gltf" >"$T/missing/box.gltf"
  cp "$MODELS/glTF2/BoxTextured-glTF/"*.bin "$T/missing/"
  "$JND" render "$T/missing/box.gltf" -o "$T/m" --views 1 --size 32x32 2>"$T/err"
  checke '[ $? -eq 0 ] && grep -q "warning: .*nothere.png" "$T/err" && [ -f "$T/m/view_000.png" ]' \
      "a missing texture falls back to the factor with a warning"
  checke 'err "nothere.png" "$T/missing/box.gltf" -o "$T/m2" --strict' "--strict makes it an error"
  checke '[ ! -e "$T/x" ] && [ ! -e "$T/m2" ]' "nothing is written for bad input"
fi
checke 'err "is not a number" builtin -o "$T/x" --coverage abc' "a bad option value: exit 2"
checke 'err "no such map" builtin --map-size 16 -o "$T/x" --scale nothing/normal=0.5' "an unknown map: exit 2"
# --cameras: a camera that cannot make an image, and text that is not views
echo '[{"eye": [0, 5, 0], "target": [0, 0, 0]}]' >"$T/upcam.json"
checke 'err "upcam.json: camera 0 is invalid" builtin --map-size 16 -o "$T/x" --cameras "$T/upcam.json"' \
    "--cameras looking along up: exit 2, one line naming the file and camera"
echo 'not json' >"$T/notjson.json"
checke 'err "notjson.json: not a JSON list of cameras" builtin --map-size 16 -o "$T/x" --cameras "$T/notjson.json"' \
    "--cameras that is not JSON: exit 2, one line"
checke '[ ! -e "$T/x" ]' "nothing is written for bad cameras"
checke '"$JND" render --help | grep -- "--coverage" >/dev/null' "--help prints the usage"
# llvmpipe's own anisotropic filter never finished this frame (issue 12:
# every time, at 4.3 and not at 3.9 or 4.6); the shader's filter renders it
# at once. 60 s is a hang, not a speed target.
checke 'timeout 60 "$JND" render builtin --size 64x64 --views 1 --map-size 64 --distance 4.3 -o "$T/stall" --quiet' \
    "a frame that hung llvmpipe's anisotropic filter renders"
[ -d "$MODELS" ] || skip "$MODELS is missing (Debian package assimp-testmodels): its broken and textured glTF files were not tried"
finish
