#!/usr/bin/env bash
# jnd budget, step 6 (src/tasks/budget.c, jnd_budget_search): a choice seen
# on its held-out views is dropped, with every candidate drawing its state,
# and the next cheapest that passes is verified on fresh held-out views. On
# the built-in sphere judged on one view without texres's margin, the
# cheapest choice is seen on 8 held-out views at the viewing condition
# (statistic 1); the next cheapest passes its own 8.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
need_renderer
command -v python3 >/dev/null || skip "needs python3"

ARGS=(--map-size 128 --size 96x96 --samples 1 --confirm 0 --screens 640x480
      --errors 0.002,0.008,0.03 --judge-views 2 --max-px 128 --tolerance 0.5 --far-coverage 0.05
      --views 1 --margin 0 --verify-views 8)
"$JND" budget builtin:sphere -o "$T/a" "${ARGS[@]}" >"$T/out.txt" 2>"$T/err.txt"
rc=$?
check "a choice seen on its held-out views is followed by one that passes them: exit 0 (rc $rc)" test "$rc" -eq 0
check "the stage log says the first choice was dropped" grep -q "seen on its held-out views: dropped" "$T/err.txt"
check "budget.json: the dropped choice is cheaper than the chosen one, a different state, and every written level passes" \
  python3 - "$T/a/budget.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["result"]
cands = r["candidates"]
dropped = [c for c in cands if c.get("dropped_on_held_out")]
ch = r["chosen"]
assert len(dropped) == 1, [c["index"] for c in dropped]
d = dropped[0]
assert d["cost_bytes"] < ch["cost_bytes"], (d["cost_bytes"], ch["cost_bytes"])
assert not ch.get("dropped_on_held_out")
assert (d["level"], d.get("sizes")) != (ch["level"], ch.get("sizes")) or d["memory_bytes"] != ch["memory_bytes"]
assert r["passes"] is True
for L in r["levels"]:
    v = L.get("verification")
    assert v is None or v["pass"], L
# the candidates that draw the dropped state are not chosen either
same = [c for c in cands if c["level"] == d["level"] and c["memory_bytes"] == d["memory_bytes"]
        and c["kind"] in ("searched", "separate", "encoded") and c["cost_bytes"] < ch["cost_bytes"]]
assert all(c["index"] != ch["index"] for c in same)
print("dropped", d["index"], d["kind"], d["cost_bytes"], "chosen", ch["index"], ch["kind"], ch["cost_bytes"])
PY
finish
