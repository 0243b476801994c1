#!/usr/bin/env bash
# The Blender add-on (blender/jnd_blender.py), headless: installed and enabled
# in Debian's blender, its operator runs jnd texres (through the Python
# package) on a plane built in the test, Apply scales the plane's 256x256
# image, and the saved .blend holds the image at the size the command line
# chooses for the same exported GLB with the same options. Then LOD: Run lod
# and Apply LOD on a UV sphere; the saved .blend holds one object per level
# of the command's chain for the same export and options (triangles, switch
# distances), parented to the sphere, levels 1.. hidden. Then budget: Run
# budget and Apply budget on a textured ball; the saved .blend holds the
# image at the command's chosen size and the command's levels, and the
# panel's distances carry their unit.
. "$(dirname "$0")/lib.bash"
build=$(dirname "$JND")
command -v blender >/dev/null || skip "blender is not installed (scripts/install-deps.sh installs Debian's)"
[ -f "$build/python/jnd/.built" ] || skip "the Python package was not built (python3-cffi, python3-numpy)"
need_renderer
script=$JND_SRC/blender/tests/addon_test.py
mkdir -p "$T/home"
env=(HOME="$T/home" JND_PYTHONPATH="$build/python" PYTHONDONTWRITEBYTECODE=1)
if [ -n "${JND_SANITIZED:-}" ]; then
  # the sanitized library in an uninstrumented Blender: the runtime preloaded,
  # leaks left to the C suite (as tests/e2e/python.sh)
  env+=(LD_PRELOAD="$(clang -print-file-name=libclang_rt.asan-x86_64.so)"
        ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:intercept_tls_get_addr=0")
fi
run_blender() {
  env "${env[@]}" blender -b -noaudio --python-exit-code 1 "$@" >"$T/blender.log" 2>&1
}
if run_blender --factory-startup --python "$script" -- run "$T"; then
  ok "the add-on installs, its operator runs and applies, the scene is saved"
else
  tail -30 "$T/blender.log"
  bad "the add-on's run in blender"
  finish
fi
expect_exit 0 "jnd texres on the same export with the same options" \
  "$JND" texres "$T/plane.glb" -o "$T/cli" --views 2 --size 96x96 --confirm 0 --quiet
if run_blender "$T/scene.blend" --python "$script" -- check "$T"; then
  ok "the saved .blend opens"
else
  tail -30 "$T/blender.log"
  bad "reading the saved .blend"
  finish
fi
verdict=$(python3 - "$T" <<'PY'
import json, sys
t = sys.argv[1]
cli = json.load(open(f"{t}/cli/texres.json"))["result"]
panel = json.load(open(f"{t}/summary.json"))
sizes = json.load(open(f"{t}/sizes.json"))
chosen = cli["memory"]["images"][0]["chosen"]
problems = []
if [im["chosen"] for im in panel["images"]] != [chosen]:
    problems.append(f"the panel's sizes {panel['images']} are not the command's {chosen}")
if panel["images"][0]["image"] != "jnd_grid":
    problems.append(f"the chosen size is not tied to the plane's image: {panel['images']}")
got = sizes.get("jnd_grid", {})
if got.get("size") != chosen:
    problems.append(f"the saved image is {got.get('size')}, the command chose {chosen}")
if not max(chosen) < 256:
    problems.append(f"the command kept {chosen}: nothing to apply")
if not got.get("packed"):
    problems.append("the scaled image is not packed into the .blend")
print("; ".join(problems) or f"ok {chosen[0]}x{chosen[1]}")
PY
)
case $verdict in
  ok*) ok "the saved image is the command's choice, smaller than 256x256 (${verdict#ok })" ;;
  *) bad "$verdict" ;;
esac

expect_exit 0 "jnd lod on the same sphere export with the panel's options" \
  "$JND" lod "$T/sphere.glb" -o "$T/cli_lod" --screens standard-fhd --p 0.2 --q 0.1 --views 1 --judge-views 2 \
  --max-px 96 --errors 1/256,1/64,1/16 --quiet
verdict=$(python3 - "$T" <<'PY'
import json, sys
t = sys.argv[1]
cli = json.load(open(f"{t}/cli_lod/lod.json"))["result"]
levels = json.load(open(f"{t}/levels.json"))
panel = json.load(open(f"{t}/lod_summary.json"))
want = [lv["triangles"] for lv in cli["levels"]]
dist = [-1 if d is None else d for d in cli["screens"][0]["switch_distance_m"]]
problems = []
if len(want) < 3 or not want[-1] < want[0]:
    problems.append(f"the command's chain {want} has nothing to apply")
if panel["levels"] != want or panel["perceptual_level"] != cli["screens"][0]["perceptual_level"]:
    problems.append(f"the panel's {panel} is not the command's {want}")
if [lv["level"] for lv in levels] != list(range(len(want))):
    problems.append(f"the saved levels are {[lv['level'] for lv in levels]}, the command made {len(want)}")
if [lv["triangles"] for lv in levels] != want:
    problems.append(f"the saved meshes have {[lv['triangles'] for lv in levels]} triangles, the command's {want}")
if [lv["switch_distance"] for lv in levels] != dist:
    problems.append(f"switch distances {[lv['switch_distance'] for lv in levels]}, the command's {dist}")
if any(lv["parent"] != "Sphere" for lv in levels) or [lv["hidden"] for lv in levels] != [False] + [True] * (len(want) - 1):
    problems.append(f"parents or visibility: {levels}")
print("; ".join(problems) or f"ok {want}")
PY
)
case $verdict in
  ok*) ok "the saved .blend holds the command's levels, triangles ${verdict#ok }, parented to the sphere" ;;
  *) bad "$verdict" ;;
esac

expect_exit 0 "jnd budget on the same ball export with the panel's options" \
  "$JND" budget "$T/ball.glb" -o "$T/cli_budget" --display standard-fhd --screens standard-fhd --p 0.2 --q 0.1 \
  --views 2 --size 96x96 --confirm 0 --min-size 32 --judge-views 2 --max-px 96 --errors 1/64,1/16 --quiet
verdict=$(python3 - "$T" <<'PY'
import json, sys
t = sys.argv[1]
cli = json.load(open(f"{t}/cli_budget/budget.json"))["result"]
panel = json.load(open(f"{t}/budget_summary.json"))
sizes = json.load(open(f"{t}/sizes.json"))
levels = json.load(open(f"{t}/ball_levels.json"))
units = json.load(open(f"{t}/units.json"))
chosen = cli["chosen"]["sizes"]
want = [lv["triangles"] for lv in cli["levels"]]
dist = [-1 if lv["switch_distance"] is None else lv["switch_distance"] for lv in cli["levels"]]  # None: never
problems = []
if [(im["maps"][0], im["chosen"], im["image"]) for im in panel["images"]] != [(k, v, "jnd_ball") for k, v in chosen.items()]:
    problems.append(f"the panel's sizes {panel['images']} are not the command's {chosen}")
if (panel["chosen"]["level"], panel["chosen"]["triangles"]) != (cli["chosen"]["level"], cli["chosen"]["triangles"]):
    problems.append(f"the panel's choice {panel['chosen']} is not the command's {cli['chosen']}")
size = list(chosen.values())[0]
if sizes.get("jnd_ball", {}).get("size") != size:
    problems.append(f"the saved image is {sizes.get('jnd_ball')}, the command chose {size}")
if size != [256, 256] and not sizes["jnd_ball"]["packed"]:
    problems.append("the scaled image is not packed into the .blend")
if len(want) < 2:
    problems.append(f"the command's chain {want} has one level: nothing to apply")
if [lv["triangles"] for lv in levels] != want or [lv["switch_distance"] for lv in levels] != dist:
    problems.append(f"the saved levels {levels} are not the command's {want} from {dist}")
if any(lv["parent"] != "Ball" for lv in levels) or [lv["hidden"] for lv in levels] != [False] + [True] * (len(want) - 1):
    problems.append(f"parents or visibility: {levels}")
if units != {"metric": "2.5 m", "none": "2.5 object units"}:
    problems.append(f"the panel's distances read {units}")
print("; ".join(problems) or f"ok {size[0]}x{size[1]}, levels {want}")
PY
)
case $verdict in
  ok*) ok "budget: the saved .blend holds the command's sizes and levels (${verdict#ok }), distances with units" ;;
  *) bad "$verdict" ;;
esac
finish
