#!/usr/bin/env bash
# jnd batch's statuses against the exit status of the command it runs
# (docs/batch.md): exit 0 is "ok", exit 1 (a visible difference above the
# criterion, here diff's --fail-above) is "above" and never "ok", exit 2 is
# "failed". The same status wherever batch reports it: its progress lines,
# its --json totals, each asset's record, the merged summary (JSON and CSV)
# and the HTML report; and the same outcome as the command run alone. jnd
# diff on a tiny pair: no renderer, a few seconds.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
command -v python3 >/dev/null || skip "needs python3"
cd "$T" || exit 1
"$JND" example -o pairs --size 64x64 >/dev/null 2>&1 || { bad "jnd example"; finish; }

# four rows: identical images (P = 0), a visible difference gated at 0 and
# at 1, and an option diff refuses
cat >assets.csv <<EOF
id,asset,command,options
same,pairs/reference.png,diff,pairs/reference.png --fail-above 0.5
seen,pairs/reference.png,diff,pairs/test.png --fail-above 0
let,pairs/reference.png,diff,pairs/test.png --fail-above 1
bad,pairs/reference.png,diff,pairs/test.png --fail-above x
EOF

# the same commands alone: their exit statuses are what batch must report
want=""
for row in "same pairs/reference.png --fail-above 0.5" "seen pairs/test.png --fail-above 0" \
           "let pairs/test.png --fail-above 1" "bad pairs/test.png --fail-above x"; do
  set -- $row
  id=$1; shift
  mkdir -p "alone_$id"
  "$JND" diff pairs/reference.png "$@" --json "alone_$id/diff.json" --quiet >/dev/null 2>&1
  want="$want $id=$?"
done
check "alone: diff exits 0, 1, 0, 2 (same, seen above --fail-above 0, let, bad)" \
  test "$want" = " same=0 seen=1 let=0 bad=2"

expect_exit 0 "batch runs (an asset above the criterion is not a failure of the run)" \
  "$JND" batch assets.csv -o out --json run.json
check "its progress says which asset is above the criterion" bash -c \
  "grep -q ' seen (diff) ok, above the criterion in ' '$T/err.txt' && grep -q ' same (diff) ok in ' '$T/err.txt' &&
   grep -q ' let (diff) ok in ' '$T/err.txt' && grep -q ' bad (diff) FAILED (exit 2)' '$T/err.txt'"
check "the run's totals: 2 ok, 1 above, 1 failed" python3 - run.json <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["result"]
assert (r["assets"], r["ran"], r["ok"], r["above"], r["failed"]) == (4, 4, 2, 1, 1), r
PY
check "each record holds its command's exit status and the status it means" python3 - out/_batch/records <<'PY'
import json, os, sys
d = sys.argv[1]
rec = {i: json.load(open(os.path.join(d, i + ".json"))) for i in ("same", "seen", "let", "bad")}
want = {"same": ("ok", 0), "seen": ("above", 1), "let": ("ok", 0), "bad": ("failed", 2)}
for i, (st, code) in want.items():
    assert (rec[i]["status"], rec[i]["exit_status"]) == (st, code), (i, rec[i])
PY
check "an asset above the criterion keeps its output (it is complete), a failed one has none" \
  test -s out/seen/diff.json -a -s out/same/diff.json -a ! -e out/bad

expect_exit 0 "merge" "$JND" batch merge out --no-timings
check "merge's line counts it as above, not ok" grep -q ': 4 assets, 2 ok, 1 above, 1 failed, 0 pending' "$T/err.txt"
check "the summary: statuses and totals follow the exit statuses; P as the command alone reports it" \
  python3 - out/summary.json <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))["result"]
t, a = d["totals"], {e["id"]: e for e in d["assets"]}
assert (t["assets"], t["ok"], t["above"], t["failed"], t["pending"]) == (4, 2, 1, 1, 0), t
assert t["ok"] + t["above"] + t["failed"] + t["pending"] == t["assets"]
for i, st, code in (("same", "ok", 0), ("seen", "above", 1), ("let", "ok", 0), ("bad", "failed", 2)):
    assert a[i]["status"] == st and a[i]["exit_status"] == code, a[i]
    if st != "failed":
        alone = json.load(open("alone_%s/diff.json" % i))["result"]
        assert a[i]["p_detect"] == alone["p_detect"], (i, a[i]["p_detect"], alone["p_detect"])
        assert a[i]["error"] is None, a[i]
assert a["same"]["p_detect"] == 0 and a["seen"]["p_detect"] > 0, (a["same"], a["seen"])
# seen and let are the same pair: the same P, another verdict only through the gate
assert a["seen"]["p_detect"] == a["let"]["p_detect"]
PY
check "summary.csv: the status column" python3 - out/summary.csv <<'PY'
import csv, sys
rows = {r["id"]: r for r in csv.DictReader(open(sys.argv[1]))}
assert [rows[i]["status"] for i in ("same", "seen", "let", "bad")] == ["ok", "above", "ok", "failed"], rows
assert [rows[i]["exit_status"] for i in ("same", "seen", "let", "bad")] == ["0", "1", "0", "2"], rows
PY

expect_exit 0 "jnd report" "$JND" report out
check "the report's index: the asset's row and the totals say above" python3 - out/report <<'PY'
import os, re, sys
html = open(os.path.join(sys.argv[1], "index.html")).read()
rows = dict(re.findall(r'<tr data-status="([a-z]+)" data-id="([a-z]+)"', html)[i][::-1]
            for i in range(len(re.findall(r'<tr data-status=', html))))
assert rows == {"same": "ok", "seen": "above", "let": "ok", "bad": "failed"}, rows
for k, v in (("ok", 2), ("above", 1), ("failed", 1), ("pending", 0), ("assets", 4)):
    assert 'id="total-%s" data-value="%d"' % (k, v) in html, (k, v)
page = open(os.path.join(sys.argv[1], "seen.html")).read()
assert '<span class="status above">above</span></h1>' in page, page[:800]
assert '<span class="status ok">ok</span></h1>' in open(os.path.join(sys.argv[1], "same.html")).read()
PY

# a rerun: the complete assets (above included) are skipped, keeping their
# statuses; the failed one runs again
expect_exit 0 "a rerun" "$JND" batch assets.csv -o out --json rerun.json --quiet
check "the rerun skips the three complete assets and counts the one above as above" python3 - rerun.json <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["result"]
assert (r["ran"], r["skipped"], r["ok"], r["above"], r["failed"]) == (1, 3, 2, 1, 1), r
PY
finish
