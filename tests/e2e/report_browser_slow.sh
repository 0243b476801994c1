#!/usr/bin/env bash
# jnd report in a real browser (issue 14): Debian's chromium, headless, driven
# by playwright-core from the npm cache that scripts/install-deps.sh fills
# (pinned in tests/browser/playwright.sh; this test never reaches the network).
# A small batch (texres, pca, diff, render, a malformed row) is run, merged and
# reported; tests/browser/report.js checks the pages from file://.
set -uo pipefail
. "$(dirname "$0")/lib.bash"
need_renderer
cd "$T" || exit 1
SRC=${JND_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
command -v node >/dev/null 2>&1 || skip "node is not installed (scripts/install-deps.sh installs npm)"
[ -x /usr/bin/chromium ] || skip "Debian's chromium is not installed (scripts/install-deps.sh installs it)"
. "$SRC/tests/browser/playwright.sh"
PW=$(playwright_core) ||
  skip "playwright-core $PLAYWRIGHT_CORE_VERSION is not in $(npm_cache_dir playwright-core "$PLAYWRIGHT_CORE_VERSION") (scripts/install-deps.sh fetches it)"

"$JND" example -o pairs --size 96x64 >/dev/null 2>&1
TINY="--views 2 --size 64x64 --map-size 64"
cat >assets.csv <<EOF2
id,asset,command,options
box,builtin,texres,$TINY --samples 1 --anisotropy 1
sphere,builtin:sphere,texres,$TINY --samples 1 --anisotropy 1 --no-matrix --coverage 0.5
pair,pairs/reference.png,diff,pairs/test.png --display phone
set,builtin,pca,--material builtin $TINY --no-bc
views,builtin,render,--views 2 --size 48x48 --map-size 64
broken,builtin,texres,--views two
EOF2
expect_exit 0 "the batch runs" "$JND" batch assets.csv -o out --jobs 2 --quiet
expect_exit 0 "merge" "$JND" batch merge out --quiet
expect_exit 0 "report" "$JND" report out --quiet
timeout 300 node "$SRC/tests/browser/report.js" "$PW" out index.png >browser.txt 2>&1
rc=$?
cat browser.txt
check "the report passes in chromium (console, images, numbers, sorting, filter, pages)" test $rc -eq 0
check "the index's screenshot is a PNG" bash -c "head -c 8 index.png | od -An -c | grep -q 'P   N   G'"
# the same driver must fail on a report whose numbers are wrong
sed -i 's/data-value="\([0-9]\)/data-value="9\1/' out/report/index.html
timeout 300 node "$SRC/tests/browser/report.js" "$PW" out wrong.png >wrong.txt 2>&1
check "a wrong number in the index is caught" bash -c "grep -q 'FAIL total assets' wrong.txt && grep -q 'FAIL box p_detect: data-value 9' wrong.txt"
# and on an image that does not load
"$JND" report out --quiet && rm out/report/box/series.png
timeout 300 node "$SRC/tests/browser/report.js" "$PW" out broken.png >broken.txt 2>&1
check "a picture that does not load is caught" grep -q 'FAIL box: 1 of .* images did not load: box/series.png' broken.txt
finish
