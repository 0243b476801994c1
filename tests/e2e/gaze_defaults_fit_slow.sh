#!/usr/bin/env bash
# scripts/fit-gaze-defaults.sh, run whole on the shared meshes, reproduces
# the committed fit (scripts/gaze-defaults.json) that the defaults carry:
# the same parameters to the digits committed, the same figures.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
shared_data || skip "the shared data (JND_SHARED) is not available"
root="$(dirname "$0")/../.."
expect_exit 0 "the script runs" env JND_SHARED="$JND_SHARED" bash "$root/scripts/fit-gaze-defaults.sh" "$JND" "$T/fit"
check "it prints what is committed" python3 - "$T/fit/gaze-defaults.json" "$root/scripts/gaze-defaults.json" <<'PY'
import json, sys
got, want = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
def walk(a, b, path):
    if isinstance(b, dict):
        assert set(a) == set(b), path
        for k in b: walk(a[k], b[k], path + "." + k)
    elif isinstance(b, (int, float)) and b is not None:
        # renderers and maths libraries may differ in the last bits: the
        # committed digits within 1%
        assert abs(a - b) <= 0.01 * max(abs(b), 1e-3), (path, a, b)
    else:
        assert a == b, (path, a, b)
walk(got, want, "")
PY
finish
