#!/usr/bin/env bash
# jnd pop --decide on the shared meshes (issue 12, "Done when"): with a
# level chain, the popping-free switch distance of every level for a static
# and a moving camera. The camera pans (turns in place), so every point
# sweeps the screen at the pan rate whatever the distance: where motion masks
# (004 Fig. 2), the moving camera's distances are nearer than the static
# one's. Checked on each mesh: never farther for any level, strictly nearer
# for some; and max R < 1 at every chosen distance —
# recomputed here by rendering the switch at that distance with
# `jnd pop MODEL --distance` — and no distance only where even the farthest
# distance searched pops.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
shared_data || skip "no shared data (../shared/data)"
need_renderer
M="$JND_SHARED/data/meshes"
V=(--size 128x128 --views 1 --quiet)
expect_exit 0 "spot decisions run" "$JND" pop "$M/spot.obj" -o "$T/spot" "${V[@]}" --errors 0.002,0.008 --pan 0 --speeds 0,480
for m in spot teapot stanford-bunny; do
  expect_exit 0 "$m decisions run" "$JND" pop "$M/$m.obj" -o "$T/$m" "${V[@]}" --errors 0.002,0.008 --pan 0 --speeds 0,480
  check "$m: two levels x two speeds" jq -e '(.result.switch | length == 4) and .parameters.motion.kind == "pan"' "$T/$m/pop.json"
  check "$m: a moving camera's distance is never farther than the static one's" python3 - "$T/$m/pop.json" <<'PY'
import json, sys
rows = json.load(open(sys.argv[1]))["result"]["switch"]
inf = float("inf")
d = {(r["level"], r["speed_dps"]): (inf if r["distance_m"] is None else r["distance_m"]) for r in rows}
for lv in (1, 2):
    assert d[(lv, 480)] <= d[(lv, 0)], (lv, d)
PY
  check "$m: and strictly nearer for some level" python3 - "$T/$m/pop.json" <<'PY'
import json, sys
rows = json.load(open(sys.argv[1]))["result"]["switch"]
d = {(r["level"], r["speed_dps"]): r["distance_m"] for r in rows}
assert any(d[(lv, 480)] is not None and d[(lv, 0)] is not None and d[(lv, 480)] < d[(lv, 0)] for lv in (1, 2)), d
PY
  # every chosen distance, rendered again as a pair: max R < 1 there
  python3 - "$T/$m/pop.json" > "$T/rows.txt" <<'PY'
import json, sys
for r in json.load(open(sys.argv[1]))["result"]["switch"]:
    if r["distance_m"] is not None:
        print(r["level"] - 1, r["speed_dps"], repr(r["distance_m"]))
PY
  check "$m: level 1 has a distance at every speed" test "$(grep -c '^0 ' "$T/rows.txt")" -eq 2
  check "$m: no distance only where it pops even at the farthest" jq -e 'all(.result.switch[] | select(.distance_m == null); .status == "none" and .max_rating >= 1)' "$T/$m/pop.json"
  while read -r k s dist; do
    expect_exit 0 "$m: pair at level $k, $s deg/s, $dist m" "$JND" pop "$M/$m.obj" -o "$T/p_${m}_${k}_$s" "${V[@]}" \
      --errors 0.002,0.008 --switch "$k" --pan "$s" --distance "$dist"
    check "$m: max R < 1 at level $((k + 1)), $s deg/s" jq -e '.result.max_rating == null or .result.max_rating < 1' "$T/p_${m}_${k}_$s/pop.json"
  done < "$T/rows.txt"
done
finish
