#!/usr/bin/env bash
# Uniform changes are visible (issue 10, the model's baseband): a frame that
# turns from white to black, and a grey field that changes by 12 codes, are
# caught by jnd diff and fail --fail-above; a one-code change of a 512² grey
# field is near threshold; identical fields are invisible.
. "$(dirname "$0")/lib.bash"
command -v python3 >/dev/null || skip "needs python3"
# flat 512x512 8-bit RGB PNGs
python3 - "$T" <<'PY'
import struct, sys, zlib
def png(path, v, w=512, h=512):
    raw = b"".join(b"\x00" + bytes([v]) * (3 * w) for _ in range(h))
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    ihdr = struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
for v in (0, 128, 129, 140, 255):
    png(f"{sys.argv[1]}/flat{v}.png", v)
PY
expect_exit 1 white_to_black_fails_the_gate "$JND" diff "$T/flat255.png" "$T/flat0.png" --fail-above 0.2 --json "$T/wb.json" --quiet
check white_to_black_is_certainly_seen jq -e '.result.p_detect > 0.99' "$T/wb.json"
expect_exit 1 grey_128_to_140_fails_the_gate "$JND" diff "$T/flat128.png" "$T/flat140.png" --fail-above 0.2 --json "$T/g12.json" --quiet
check grey_128_to_140_is_seen jq -e '.result.p_detect > 0.95' "$T/g12.json"
expect_exit 0 one_code_step_runs "$JND" diff "$T/flat128.png" "$T/flat129.png" --json "$T/g1.json" --quiet
check one_code_is_less_visible_than_twelve jq -e --slurpfile b "$T/g12.json" '.result.jnd_max < $b[0].result.jnd_max / 4' "$T/g1.json"
expect_exit 0 identical_fields_pass_the_gate "$JND" diff "$T/flat128.png" "$T/flat128.png" --fail-above 0.2 --json "$T/same.json" --quiet
check identical_fields_are_invisible jq -e '.result.p_detect == 0 and .result.jnd_max == 0' "$T/same.json"
finish
