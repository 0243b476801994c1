#!/usr/bin/env bash
# jnd batch on one machine (issue 14): a 4-asset manifest, one row malformed,
# run as 2 shards and merged equals a single run; a rerun recomputes nothing;
# outputs are what the single command writes; an interrupted run leaves no
# result that looks complete; a timeout, a command failing with exit 2, bad
# rows and run-wide errors; a glob and a JSON manifest; the report's files.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
need_renderer
cd "$T" || exit 1
TINY=(--views 2 --size 64x64 --map-size 64)
"$JND" example -o pairs --size 96x64 >/dev/null 2>&1

cat >assets.csv <<EOF
id,asset,command,options
box,builtin,texres,${TINY[*]} --samples 1 --anisotropy 1 --no-matrix
pair,pairs/reference.png,diff,pairs/test.png --display phone
broken,builtin,texres,"--views 'two"
set,builtin,pca,--material builtin ${TINY[*]} --no-bc
EOF

# ---- two shards, then merged; a single run; the same summary ----
expect_exit 0 "shard 0/2 runs" "$JND" batch assets.csv -o sharded --shard 0/2
cp "$T/err.txt" shard0.err
expect_exit 0 "shard 1/2 runs" "$JND" batch assets.csv -o sharded --shard 1/2
check "shard 0/2 ran rows 0 and 2 (box, broken), one line each on stderr (not a terminal)" \
  bash -c "grep -q '^jnd batch: 1/2 box (texres) ok' shard0.err && grep -q '^jnd batch: 2/2 broken (texres) FAILED: .*assets.csv:4: options: a . is not closed' shard0.err"
check "shard 1/2 ran rows 1 and 3 (pair, set)" bash -c "grep -q ' pair (diff) ok' '$T/err.txt' && grep -q ' set (pca) ok' '$T/err.txt'"
expect_exit 0 "merge of the shards" "$JND" batch merge sharded --no-timings
expect_exit 0 "a single run" "$JND" batch assets.csv -o single --jobs 2 --quiet
check "--quiet leaves stderr empty" test ! -s "$T/err.txt"
expect_exit 0 "merge of the single run" "$JND" batch merge single --no-timings
check "2 shards merge to the bytes of a single run: summary.json" cmp sharded/summary.json single/summary.json
check "2 shards merge to the bytes of a single run: summary.csv" cmp sharded/summary.csv single/summary.csv
check "the summary: statuses, errors, memory, decisions, in manifest order" python3 - sharded/summary.json <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d["command"] == "batch merge" and "jnd_version" in d and "parameters" in d and "inputs" in d
a = {e["id"]: e for e in d["result"]["assets"]}
assert [e["id"] for e in d["result"]["assets"]] == ["box", "pair", "broken", "set"]
t = d["result"]["totals"]
assert (t["assets"], t["ok"], t["failed"], t["pending"]) == (4, 3, 1, 0), t
assert a["broken"]["status"] == "failed" and a["broken"]["error"].startswith("assets.csv:4: options: a ' is not closed")
assert "\n" not in a["broken"]["error"]
for k in ("box", "pair", "set"):
    assert a[k]["status"] == "ok" and a[k]["exit_status"] == 0 and a[k]["error"] is None, a[k]
box, st = a["box"], a["set"]
assert 0 < box["memory_after_bytes"] <= box["memory_before_bytes"] and 0 <= box["p_detect"] <= 1
assert "builtin/baseColor" in box["decision"] and len(box["chosen"]) == 4
assert 0 < st["memory_after_bytes"] <= st["memory_before_bytes"] and "components" in st["decision"]
assert a["pair"]["memory_before_bytes"] is None and 0 <= a["pair"]["p_detect"] <= 1
assert t["memory_before_bytes"] == box["memory_before_bytes"] + st["memory_before_bytes"]
assert "seconds" not in box
PY

# ---- outputs are exactly what the single command writes ----
"$JND" texres builtin "${TINY[@]}" --samples 1 --anisotropy 1 --no-matrix -o direct --quiet
check "OUT/box holds what jnd texres writes, byte for byte" diff -r direct sharded/box
check "diff's report and heatmap are in OUT/pair" test -s sharded/pair/diff.json -a -s sharded/pair/heatmap.png
check "no work left behind" bash -c "[ -z \"\$(ls sharded/_batch/work)\" ]"

# ---- a rerun recomputes nothing ----
stamp() { stat -c '%i %Y' sharded/box/texres.json sharded/set/pca.json sharded/pair/diff.json sharded/_batch/records/*.json; }
before=$(stamp)
expect_exit 0 "a rerun" "$JND" batch assets.csv -o sharded --json rerun.json
check "the rerun started no command (3 complete, the broken row fails again at once)" python3 - rerun.json <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["result"]
assert (r["assets"], r["ran"], r["skipped"], r["failed"]) == (4, 0, 3, 1), r
PY
check "the rerun says each complete asset was skipped" bash -c "[ \$(grep -c 'complete, skipped' '$T/err.txt') -eq 3 ]"
check "the rerun touched no output and no record" test "$before" = "$(stamp)"
# a changed row runs again; --force runs everything
sed 's/--display phone/--display laptop/' assets.csv >changed.csv
expect_exit 0 "a changed row" "$JND" batch changed.csv -o sharded --json changed.json --quiet
check "only the changed row ran again" python3 -c "import json; r=json.load(open('changed.json'))['result']; assert (r['ran'], r['skipped']) == (1, 2), r"
"$JND" batch merge sharded --no-timings --quiet
check "its new result is merged" grep -q 'pair,3,pairs/reference.png,diff,pairs/test.png --display laptop,ok,0' sharded/summary.csv

# ---- a command that fails: recorded with its exit status and one line; the rest go on ----
cat >fail.csv <<EOF
id,asset,command,options
words,builtin,texres,--views two
fine,pairs/reference.png,diff,pairs/test.png
gone,missing/model.glb,texres,
twice,pairs/reference.png,diff,pairs/test.png
twice,builtin,texres,
what,builtin,lodd,
EOF
expect_exit 0 "failures do not stop the run" "$JND" batch fail.csv -o failing
"$JND" batch merge failing --quiet
check "each failure is one line naming the file and row, or the command's own error" python3 - failing/summary.json <<'PY'
import json, sys
a = {(e["line"]): e for e in json.load(open(sys.argv[1]))["result"]["assets"]}
assert a[2]["status"] == "failed" and a[2]["exit_status"] == 2 and a[2]["error"] == "jnd: --views: 'two' is not an integer", a[2]
assert a[3]["status"] == "ok"
assert a[4]["status"] == "failed" and a[4]["error"] == "fail.csv:4: missing/model.glb: no such file", a[4]
assert a[5]["status"] == "ok"
assert a[6]["status"] == "failed" and a[6]["error"] == "fail.csv:6: duplicate id 'twice' (first on line 5)", a[6]
assert a[7]["status"] == "failed" and a[7]["error"].startswith("fail.csv:7: unknown command 'lodd' (jnd batch runs texres, pca, diff, render, lod")
PY
check "a failed command's stderr is kept in its log" grep -q "'two' is not an integer" failing/_batch/logs/words.log
check "a failed asset leaves no output folder" test ! -e failing/words

# ---- a timeout kills the command; an interrupted run leaves nothing that looks complete ----
SLOW="--views 8 --size 384x384 --map-size 512"
printf 'id,asset,command,options\nslow,builtin,texres,%s\n' "$SLOW" >slow.csv
expect_exit 0 "a run with a timeout" "$JND" batch slow.csv -o timed --timeout 0.5
"$JND" batch merge timed --quiet
check "the timed-out asset failed with the reason" python3 -c "
import json; e=json.load(open('timed/summary.json'))['result']['assets'][0]
assert e['status']=='failed' and e['error']=='timed out after 0.5 s (killed)' and e['exit_status'] is None, e"
setsid "$JND" batch slow.csv -o crashed --quiet &
pid=$!
for _ in $(seq 600); do [ -d crashed/_batch/work/slow/out ] && break; sleep 0.1; done
sleep 0.5
kill -KILL -- "-$pid" 2>/dev/null; wait "$pid" 2>/dev/null
check "the interrupted asset has no output folder and no record" test ! -e crashed/slow -a ! -e crashed/_batch/records/slow.json
"$JND" batch merge crashed --quiet
check "merge calls it pending" grep -q '^slow,2,builtin,texres,.*,pending,' crashed/summary.csv
# the rerun finishes it (at a small size, so the test stays short)
printf 'id,asset,command,options\nslow,builtin,texres,%s\n' "${TINY[*]} --no-matrix" >slow.csv
expect_exit 0 "the rerun after the crash" "$JND" batch slow.csv -o crashed --quiet
check "the rerun cleaned the interrupted work and committed the result" bash -c "[ -s crashed/slow/texres.json ] && [ -z \"\$(ls crashed/_batch/work)\" ]"

# ---- run-wide errors: exit 2, one line, nothing written, nothing lost ----
expect_exit 2 "shard 3/2" "$JND" batch assets.csv -o nothere --shard 3/2
check "shard 3/2: one line" one_line_error
check "shard 3/2: says why" grep -q "index 3 is not below the count 2" "$T/err.txt"
check "shard 3/2: nothing written" test ! -e nothere
expect_exit 2 "a missing manifest" "$JND" batch absent.csv -o nothere
check "a missing manifest: one line" one_line_error
check "a missing manifest: names it" grep -q '^jnd: absent.csv: ' "$T/err.txt"
printf 'id,asset,command,options\nbox,builtin,texres,"--views 2\n' >torn.csv
expect_exit 2 "a torn CSV" "$JND" batch torn.csv -o sharded
check "a torn CSV: one line naming file and line" grep -q '^jnd: torn.csv:2: malformed CSV record' "$T/err.txt"
printf 'name,asset,command\nx,builtin,texres\n' >header.csv
expect_exit 2 "a wrong header" "$JND" batch header.csv -o sharded
check "a wrong header: says which column" grep -q "header.csv:1: unknown column 'name'" "$T/err.txt"
check "results already there are not lost" test "$before" != "" -a -s sharded/box/texres.json -a -s sharded/_batch/records/box.json
expect_exit 2 "--shards without --slurm" "$JND" batch assets.csv -o x --shards 2
expect_exit 2 "an unknown option" "$JND" batch assets.csv -o x --frobnicate
check "an unknown option: one line" one_line_error

# ---- progress on a terminal: a bar with done / total, failures, time; a failure stays above it ----
printf 'id,asset,command,options\none,pairs/reference.png,diff,pairs/test.png\nbad,builtin,texres,--views x\ntwo,pairs/reference.png,diff,pairs/test.png\n' >tty.csv
if command -v script >/dev/null 2>&1; then
  script -qec "'$JND' batch tty.csv -o ttyout" /dev/null >tty.txt 2>&1
  check "on a terminal: a progress bar with done/total, failures, elapsed, estimate" \
    bash -c "grep -q 'batch \[#\{24\}\] 3/3, 1 failed, [0-9]* s, ~0 s left' tty.txt && grep -q 'jnd batch: bad (texres) FAILED: jnd: --views' tty.txt"
  script -qec "'$JND' batch tty.csv -o ttyout --quiet" /dev/null >tty.txt 2>&1
  check "on a terminal, --quiet prints nothing" test ! -s tty.txt
else
  bad "script (util-linux) is missing: the terminal progress is untested"
fi

# ---- a glob with one command; a JSON manifest ----
mkdir -p objs && cp /usr/share/assimp/models/OBJ/box.obj objs/ && cp /usr/share/assimp/models/OBJ/cube_usemtl.{obj,mtl} objs/
expect_exit 0 "a glob" "$JND" batch 'objs/*.obj' --command render --options '--views 1 --size 32x32' -o globbed --quiet
"$JND" batch merge globbed --quiet
check "a glob: one asset per match, ids from the names" bash -c "cut -d, -f1,3,6 globbed/summary.csv | tr '\n' ' ' | grep -qx 'id,asset,status box,objs/box.obj,ok cube_usemtl,objs/cube_usemtl.obj,ok '"
python3 - <<'PY' >assets.json
import csv, json
print(json.dumps({"assets": [dict(r) for r in csv.DictReader(open("assets.csv"))]}))
PY
expect_exit 0 "a JSON manifest" "$JND" batch assets.json -o fromjson --quiet
"$JND" batch merge fromjson --no-timings --quiet
check "the JSON manifest gives the CSV's result" python3 -c "
import json
a, b = (json.load(open(p + '/summary.json'))['result'] for p in ('fromjson', 'single'))
for e in a['assets'] + b['assets']:
    e.pop('line')
    if e['id'] == 'broken': assert e.pop('error').endswith(\"options: a ' is not closed\"), e
assert a == b"

# ---- the report: a page per asset, every picture it names is there ----
"$JND" batch merge single --quiet
expect_exit 0 "jnd report" "$JND" report single
check "the report's index and pages exist and reference only files that exist" python3 - single <<'PY'
import os, re, sys, urllib.parse
out = sys.argv[1]
rep = os.path.join(out, "report")
pages = ["index.html"] + [i + ".html" for i in ("box", "pair", "broken", "set")]
n = 0
for p in pages:
    html = open(os.path.join(rep, p)).read()
    for src in re.findall(r'(?:src|href)="([^"#]+)"', html):
        path = os.path.normpath(os.path.join(rep, urllib.parse.unquote(src)))
        assert os.path.exists(path), (p, src)
        n += src.endswith(".png")
assert n >= 6, n
box = open(os.path.join(rep, "box.html")).read()
assert "worst_view.png" in box and "series.png" in box
assert "not closed" in open(os.path.join(rep, "broken.html")).read()
PY
# ---- lod runs in a batch: triangles and memory before and after, the decision, the Pareto plots ----
LODOPTS="--screens 320x240,640x480 --views 1 --map-size 32 --surface-samples 1024 --no-textures --judge-views 1 --max-px 64 --tolerance 1 --far-coverage 0.1"
printf 'id,asset,command,options\nsphere,builtin:sphere,lod,"%s"\n' "$LODOPTS" >lod.csv
expect_exit 0 "a batch of jnd lod" "$JND" batch lod.csv -o lodbatch --quiet
"$JND" batch merge lodbatch --no-timings --quiet
check "lod's summary: memory before and after, the perceptual levels, the worst P" python3 - lodbatch/summary.json lodbatch/sphere/lod.json <<'PY'
import json, sys
e = json.load(open(sys.argv[1]))["result"]["assets"][0]
r = json.load(open(sys.argv[2]))["result"]
assert e["status"] == "ok" and e["command"] == "lod", e
assert e["memory_before_bytes"] == r["memory"]["before_bytes"] and 0 < e["memory_after_bytes"] <= e["memory_before_bytes"], e
levels = {s["name"]: s["perceptual_level"] for s in r["screens"]}
assert e["chosen"]["perceptual_level"] == levels, (e["chosen"], levels)
assert e["decision"].startswith("320x240 level %d (" % levels["320x240"]) and "640x480 level" in e["decision"], e["decision"]
assert e["p_detect"] == max(s["perceptual_statistic"] for s in r["screens"]), e
PY
expect_exit 0 "jnd report of the lod batch" "$JND" report lodbatch
check "lod's page shows its Pareto plots and the screens' table" python3 - lodbatch <<'PY'
import os, sys
html = open(os.path.join(sys.argv[1], "report", "sphere.html")).read()
assert "pareto_320x240.png" in html and "pareto_640x480.png" in html
assert "perceptual level" in html and "switch distances" in html
PY

# ---- pop: the switch's regions and its switch distances in the summary and the report ----
cat >pop.csv <<EOF
id,asset,command,options
popping,builtin,pop,--size 48x48 --views 1 --map-size 32 --errors 0.02 --speeds 0 --tolerance 0.3
EOF
expect_exit 0 "a pop row runs" "$JND" batch pop.csv -o popping --quiet
"$JND" batch merge popping --quiet
check "its decision and switch distances are in the summary" python3 - popping/summary.json <<'PY'
import json, sys
a = json.load(open(sys.argv[1]))["result"]["assets"][0]
assert a["status"] == "ok" and "detection score" in a["decision"] and "switch distance" in a["decision"], a
assert a["chosen"]["switch"][0]["level"] == 1 and a["chosen"]["switch"][0]["speed_dps"] == 0, a
PY
expect_exit 0 "its report" "$JND" report popping
check "its page shows the regions and the switch plot" bash -c "grep -q regions.png popping/report/popping.html && grep -q switch.png popping/report/popping.html"

# ---- gaze: the table's range of levels in the summary, its picture and grid on the page ----
cat >gaze.csv <<EOF
id,asset,command,options
foveated,builtin:sphere,gaze,"--map-size 32 --orientations 1 --distances 20,80 --eccentricities 0,30 --min-px 48 --max-px 64"
EOF
expect_exit 0 "a gaze row runs" "$JND" batch gaze.csv -o gazing --quiet
"$JND" batch merge gazing --no-timings --quiet
check "its decision is the table's range of levels, from its gaze.json" python3 - gazing/summary.json gazing/foveated/gaze.json <<'PY'
import json, sys
a = json.load(open(sys.argv[1]))["result"]["assets"][0]
r = json.load(open(sys.argv[2]))["result"]
cells = [c for row in r["level"] for c in row]
assert a["status"] == "ok" and a["command"] == "gaze", a
assert (a["chosen"]["finest"], a["chosen"]["coarsest"]) == (min(cells), max(cells)), (a["chosen"], cells)
assert a["decision"] == "levels %d–%d over 2 distances × 2 eccentricities" % (min(cells), max(cells)), a["decision"]
PY
expect_exit 0 "its report" "$JND" report gazing
check "its page shows gaze.png and the grid" python3 - gazing <<'PY'
import os, sys
html = open(os.path.join(sys.argv[1], "report", "foveated.html")).read()
assert "gaze.png" in html and "eccentricities (deg)" in html and "distances (m)" in html, html[:500]
PY
finish
