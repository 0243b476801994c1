#!/usr/bin/env bash
# jnd calibrate's report (src/tasks/calibrate_report.c), its numbers from a
# second route: each scene's measured threshold from its µ and σ by 000's
# eq. 1 inverse at the criterion's p (x = µ + σ·Φ⁻¹(1 − p)), the training
# error the mean |predicted − measured|, the held-out error the mean of the
# scenes' held-out errors (one scene per fold here), and the calibration's
# error that held-out one. Prepared pairs of tiny PNGs, no renderer.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
command -v python3 >/dev/null || skip "needs python3"

HERE=$(cd "$(dirname "$0")" && pwd)
cd "$T" || exit 1
PYTHONPATH="$HERE" python3 -B - <<'PY'
import math
from pngwrite import png
f = lambda a: (lambda x, y: ((0.5 + 0.25 * (1 - 4 * a) * math.sin(x * 0.8) * math.sin(y * 0.6)),) * 3)
png('ref.png', 64, 48, 3, f(0))
for s, a in ((128, 0.0), (64, 0.03), (32, 0.08)):
    png(f't{s}.png', 64, 48, 3, f(a))
PY
{
  echo "scene,resolution,reference,test"
  for sc in one two three; do for s in 128 64 32; do echo "$sc,$s,ref.png,t$s.png"; done; done
} >pairs.csv
printf 'scene,mu,sigma\none,60,15\ntwo,80,20\nthree,50,10\n' >mu.csv
expect_exit 0 calibrate_from_pairs "$JND" calibrate mu.csv --pairs pairs.csv -o cal.json --folds 3 --quiet
check numbers_from_a_second_route python3 - cal.json <<'PY'
import json, sys
from statistics import NormalDist
r = json.load(open(sys.argv[1]))
par, res = r["parameters"], r["result"]
p = par["threshold_p"]
want = {"one": (60, 15), "two": (80, 20), "three": (50, 10)}
sc = res["scenes"]
assert sorted(s["scene"] for s in sc) == sorted(want), sc
for s in sc:
    mu, sigma = want[s["scene"]]
    assert (s["mu"], s["sigma"]) == (mu, sigma), s
    x = mu + sigma * NormalDist().inv_cdf(1 - p)
    assert abs(s["measured_px"] - x) < 1e-6 * x, (s, x)
train = sum(abs(s["predicted_px"] - s["measured_px"]) for s in sc) / len(sc)
assert abs(res["train_mae_px"] - train) < 1e-9 * (train + 1), (res["train_mae_px"], train)
held = [abs(s["heldout_error_px"]) for s in sc]
cv = sum(held) / len(held)
assert abs(res["cv_mae_px"] - cv) < 1e-9 * (cv + 1), (res["cv_mae_px"], cv)
assert len(res["fold_mae_px"]) == par["folds"] == 3
assert all(abs(a - b) < 1e-9 * (b + 1) for a, b in zip(sorted(res["fold_mae_px"]), sorted(held))), (res["fold_mae_px"], held)
c = res["calibration"]
assert c["mae_px"] == res["cv_mae_px"] and c["threshold_p"] == p and c["beta"] == par["beta"], c
PY

echo "$((checks - fails)) passed, $fails failed"
[ "$fails" -eq 0 ]
