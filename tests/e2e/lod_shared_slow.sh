#!/usr/bin/env bash
# jnd lod on the shared meshes (spot, the 69 K-triangle Stanford bunny, the
# teapot) with the default chain, screens and views: what 003 claims of its
# Point of Imperceptibility, checked on real scans; and the perceptual step's
# display order on them and on a 101 K-triangle mesh (the teapot split twice,
# bench/subdivide_obj.py).
#  - Hypothesis 2 (003 §3): lighting lowers the PoI — the lit knee is never
#    finer than the unlit one, on every screen.
#  - 003 §1: a smaller screen shows less detail — the phone's PoI is never
#    finer than the full-HD monitor's, which is never finer than the 4K
#    one's; and on at least one mesh the phone's is strictly coarser than the
#    4K's. docs/lod.md says why 003's terms as written rarely separate the
#    full-HD and 4K monitors (their pictures of the object are about as large
#    in degrees) and reports the levels found.
#  - The perceptual step (jnd's model through the judge, 2 views per distance
#    to keep the test short): the chosen level passes the criterion, switch
#    distances grow with the level, the model's MSFT_screencoverage follows
#    the first screen's. 003's ordering for it: at the viewing condition
#    the phone's level is never finer than the full-HD monitor's, never
#    finer than the 4K one's; and, at every distance, the level the
#    criterion lets a phone show is at least as coarse as full HD's, at
#    least as coarse as 4K's — each level's criterion switch distance is
#    nearest on the phone (the same distance grid serves every screen), never
#    farther on full HD than on 4K (the 4K monitor is as large or larger in
#    degrees and has more pixels: docs/lod.md "The same image at every pixel
#    count"), on every level of every mesh — strictly nearer on the phone and
#    on full HD than on 4K at the first level 4K does not show at the viewing
#    condition.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
need_renderer
shared_data || skip "no shared data (../shared/data)"
M="$JND_SHARED/data/meshes"
for m in spot stanford-bunny teapot; do
  expect_exit 0 "$m runs" "$JND" lod "$M/$m.obj" -o "$T/$m" --quiet --judge-views 2
done
python3 "$(dirname "$0")/../../bench/subdivide_obj.py" "$M/teapot.obj" "$T/teapot_100k.obj" 2
expect_exit 0 "teapot_100k runs" "$JND" lod "$T/teapot_100k.obj" -o "$T/teapot_100k" --quiet --judge-views 2 --screens standard-fhd,standard-4k,phone

check "the lit PoI is never finer than the unlit one" python3 - "$T" <<'PY'
import json, sys
for m in ("spot", "stanford-bunny", "teapot"):
    r = json.load(open("%s/%s/lod.json" % (sys.argv[1], m)))["result"]
    for s in r["screens"]:
        assert s["poi_level"] >= s["poi_level_unlit"], (m, s["name"], s["poi_level"], s["poi_level_unlit"])
PY
check "phone >= standard-fhd >= standard-4k, and phone > standard-4k on some mesh" python3 - "$T" <<'PY'
import json, sys
strict = []
for m in ("spot", "stanford-bunny", "teapot"):
    r = json.load(open("%s/%s/lod.json" % (sys.argv[1], m)))["result"]
    poi = {s["name"]: s["poi_level"] for s in r["screens"]}
    print("  %-15s PoI levels %s" % (m, poi))
    assert poi["phone"] >= poi["standard-fhd"] >= poi["standard-4k"], (m, poi)
    strict.append(poi["phone"] > poi["standard-4k"])
assert any(strict), strict
PY
check "the perceptual step: the choice passes, switch distances grow with the level, phone >= fhd >= 4k" python3 - "$T" <<'PY'
import json, math, sys
for m in ("spot", "stanford-bunny", "teapot", "teapot_100k"):
    d = json.load(open("%s/%s/lod.json" % (sys.argv[1], m)))
    r, p = d["result"], d["parameters"]["perceptual"]["criterion"]["p"]
    print("  %-15s perceptual levels %s" % (m, {s["name"]: s["perceptual_level"] for s in r["screens"]}))
    for s in r["screens"]:
        k = s["perceptual_level"]
        assert s["statistic"][0] == 0 and (k == 0 or s["perceptual_statistic"] <= p), (m, s["name"])
        sd = [math.inf if x is None else x for x in s["switch_distance_m"]]
        assert sd[0] == 0 and all(a <= b for a, b in zip(sd, sd[1:])), (m, s["name"], sd)
    by = {s["name"]: s for s in r["screens"]}
    lv = [by[n]["perceptual_level"] for n in ("phone", "standard-fhd", "standard-4k")]
    assert lv[0] >= lv[1] >= lv[2], (m, lv)
    sd = {n: [math.inf if x is None else x for x in by[n]["switch_distance_criterion_m"]] for n in by}
    print("  %-15s criterion switch distances phone %s" % (m, sd["phone"]))
    print("  %-15s                            fhd   %s" % (m, sd["standard-fhd"]))
    print("  %-15s                            4k    %s" % (m, sd["standard-4k"]))
    for k, (a, b, c) in enumerate(zip(sd["phone"], sd["standard-fhd"], sd["standard-4k"])):
        assert a <= b <= c, (m, k, a, b, c)
    # strict at the first level 4K does not show at the viewing condition already (levels shown
    # there on every screen tie at its distance)
    d0 = by["standard-4k"]["viewing_condition"]["distance"]
    k1 = next((k for k in range(1, len(sd["standard-4k"])) if sd["standard-4k"][k] > d0 * (1 + 1e-9)), None)
    assert k1 is not None, (m, sd["standard-4k"])
    assert sd["phone"][k1] < sd["standard-4k"][k1], (m, k1, sd["phone"][k1], sd["standard-4k"][k1])
    assert sd["standard-fhd"][k1] < sd["standard-4k"][k1], (m, k1, sd["standard-fhd"][k1], sd["standard-4k"][k1])
    s0, cov = r["screens"][0], r["model"]["screen_coverage"]
    for k in range(len(cov) - 1):
        c = min(s0["switch_coverage"][k + 1], 1.0)
        assert abs(cov[k] - min(math.pi * c * c * s0["height_px"] / (4 * s0["width_px"]), cov[k - 1] if k else 1)) < 1e-9
PY
finish
