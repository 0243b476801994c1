#!/usr/bin/env bash
# Uniform changes are visible (issue 10, the model's baseband): a frame that
# turns from white to black, and a grey field that changes by 12 codes, are
# caught by jnd diff and fail --fail-above; a one-code change of a 512² grey
# field is near threshold; identical fields are invisible. The viewing task
# (docs/model.md "Viewing task"): the report names it, side by side is the
# default, a uniform colour change is never more visible side by side than
# flickered, and an unknown task is bad input.
. "$(dirname "$0")/lib.bash"
command -v python3 >/dev/null || skip "needs python3"
# flat 512x512 8-bit RGB PNGs
python3 - "$T" <<'PY'
import struct, sys, zlib
def png(path, v, w=512, h=512):
    rgb = bytes(v) if isinstance(v, tuple) else bytes([v]) * 3
    raw = b"".join(b"\x00" + rgb * w for _ in range(h))
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    ihdr = struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
for v in (0, 128, 129, 140, 255):
    png(f"{sys.argv[1]}/flat{v}.png", v)
png(f"{sys.argv[1]}/green2.png", (128, 130, 128))
PY
expect_exit 1 white_to_black_fails_the_gate "$JND" diff "$T/flat255.png" "$T/flat0.png" --fail-above 0.2 --json "$T/wb.json" --quiet
check white_to_black_is_certainly_seen jq -e '.result.p_detect > 0.99' "$T/wb.json"
expect_exit 1 grey_128_to_140_fails_the_gate "$JND" diff "$T/flat128.png" "$T/flat140.png" --fail-above 0.2 --json "$T/g12.json" --quiet
check grey_128_to_140_is_seen jq -e '.result.p_detect > 0.95' "$T/g12.json"
expect_exit 0 one_code_step_runs "$JND" diff "$T/flat128.png" "$T/flat129.png" --json "$T/g1.json" --quiet
check one_code_is_less_visible_than_twelve jq -e --slurpfile b "$T/g12.json" '.result.jnd_max < $b[0].result.jnd_max / 4' "$T/g1.json"
expect_exit 0 identical_fields_pass_the_gate "$JND" diff "$T/flat128.png" "$T/flat128.png" --fail-above 0.2 --json "$T/same.json" --quiet
check identical_fields_are_invisible jq -e '.result.p_detect == 0 and .result.jnd_max == 0' "$T/same.json"
expect_exit 0 green_shift_runs_side_by_side "$JND" diff "$T/flat128.png" "$T/green2.png" --json "$T/sbs.json" --quiet
expect_exit 0 green_shift_runs_flickered "$JND" diff "$T/flat128.png" "$T/green2.png" --task flicker --json "$T/fl.json" --quiet
check the_default_task_is_side_by_side jq -e '.parameters.display.task == "side-by-side"' "$T/sbs.json"
check the_report_names_the_flicker_task jq -e '.parameters.display.task == "flicker"' "$T/fl.json"
check side_by_side_is_never_more_visible_than_flicker jq -e --slurpfile f "$T/fl.json" '.result.jnd_p93 <= $f[0].result.jnd_p93 and .result.jnd_p93 > 0' "$T/sbs.json"
expect_exit 2 an_unknown_task_is_bad_input "$JND" diff "$T/flat128.png" "$T/green2.png" --task toggle --quiet
finish
