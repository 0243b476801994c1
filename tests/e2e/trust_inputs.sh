#!/usr/bin/env bash
# Inputs are never written, and a run is all or nothing (issue 25,
# docs/outputs.md). For every command that writes files, an output pointed
# at an input — directly, through a symlink, as `-o .` in the input's folder,
# and at a file the asset references (a glTF's .bin and texture, an OBJ's
# .mtl and texture) — is refused before any work: exit 2, one line naming
# both paths, every input byte-identical, nothing written (the folder's
# listing, with sizes and times, the same before and after). Then runs that
# fail midway leave nothing behind, and an earlier output stays as it was.
. "$(dirname "$0")/lib.bash"
command -v python3 >/dev/null || skip "needs python3"

W=$T/w
mkdir -p "$W/asset" "$W/obj" "$W/pics"
"$JND" example -o "$W/pics" >/dev/null 2>&1 || { bad "jnd example writes the pair"; finish; }
python3 - "$W" <<'PY'
import json, struct, sys, zlib
d = sys.argv[1]
def png(w, h):
    raw = b"".join(b"\0" + bytes(v for x in range(w) for v in (x * 40 % 256, y * 60 % 256, 128)) for y in range(h))
    def chunk(t, b): return struct.pack(">I", len(b)) + t + b + struct.pack(">I", zlib.crc32(t + b) & 0xffffffff)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
quad = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0) + struct.pack("<8f", 0, 1, 1, 1, 1, 0, 0, 0) \
       + struct.pack("<6I", 0, 1, 2, 0, 2, 3)
open(f"{d}/asset/quad.bin", "wb").write(quad)
open(f"{d}/asset/tex.png", "wb").write(png(8, 8))
json.dump({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
           "buffers": [{"uri": "quad.bin", "byteLength": len(quad)}],
           "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                           {"buffer": 0, "byteOffset": 80, "byteLength": 24}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                         {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                         {"bufferView": 2, "componentType": 5125, "count": 6, "type": "SCALAR"}],
           "images": [{"uri": "tex.png"}], "textures": [{"source": 0}],
           "materials": [{"name": "m", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}]},
          open(f"{d}/asset/quad.gltf", "w"))
open(f"{d}/obj/tex.png", "wb").write(png(8, 8))
open(f"{d}/obj/quad.mtl", "w").write("newmtl m\nmap_Kd tex.png\n")
open(f"{d}/obj/quad.obj", "w").write("mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                     "usemtl m\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n")
open(f"{d}/rates.csv", "w").write("scene,model,map,resolution,rate\na,asset/quad.gltf,m/baseColor,8,0.1\n"
                                  "a,asset/quad.gltf,m/baseColor,4,0.9\n")
open(f"{d}/assets.csv", "w").write("id,asset,command,options\npair,pics/reference.png,diff,pics/test.png\n")
open(f"{d}/model.csv", "w").write("id,asset,command,options\nq,asset/quad.gltf,render,--views 1 --size 16x16\n")
PY
ln -s pics/reference.png "$W/link.png"
mkdir -p "$W/seq" && cp "$W/pics/reference.png" "$W/seq/f0.png" && cp "$W/pics/test.png" "$W/seq/g0.png"
ln -s asset "$W/assetlink"
A=pics/reference.png B=pics/test.png G=asset/quad.gltf O=obj/quad.obj

# every entry, and each file's size, time and bytes (a folder's time changes
# when staging comes and goes beside an output: its entries are what count)
snap() { (cd "$W" && find . \( -type f -printf '%p %s %T@\n' \) -o \( ! -type f -printf '%y %p\n' \) | LC_ALL=C sort &&
  find . -type f -print0 | LC_ALL=C sort -z | xargs -0 sha256sum); }
# refuse_in DIR NAME ARGS... : `jnd ARGS` run in DIR is refused before any
# work, for what it would write over (not for a bad option)
refuse_in() {
  local dir=$1 name=$2; shift 2
  local before; before=$(snap)
  expect_exit 2 "$name: exit 2" env -C "$dir" "$JND" "$@"
  check "$name: one line naming an input or another output" \
    bash -c "[ \$(wc -l <'$T/err.txt') -eq 1 ] && grep -Eq '^jnd: .*(is the input|holds the input|is also the output)' '$T/err.txt'"
  check "$name: every input and the folder as they were" [ "$before" = "$(snap)" ]
}
refuse() { refuse_in "$W" "$@"; }

# ---- diff ----
for opt in --heatmap --json --map; do
  refuse "diff $opt REF" diff $A $B $opt $A
  refuse "diff $opt TEST" diff $A $B $opt $B
  refuse "diff $opt through a symlink" diff $A $B $opt link.png
  refuse "diff $opt ./x/../REF" diff $A $B $opt pics/../$A
done
refuse "diff: two outputs on one file" diff $A $B --heatmap h.png --json h.png
check "the message names both paths" grep -q "h.png.*h.png" "$T/err.txt"
refuse "diff: an input named after a good output" diff $A $B --heatmap ok.png --json $A

# ---- commands that take an asset and an output folder (budget came after issue 25: the same rule) ----
for cmd in render texres lod gaze budget; do
  refuse_in "$W/asset" "$cmd -o . in the asset's folder" $cmd quad.gltf -o .
  refuse_in "$W/obj" "$cmd -o . in the OBJ's folder" $cmd quad.obj -o .
  refuse "$cmd -o the asset" $cmd $G -o $G
  refuse "$cmd -o the asset's folder" $cmd $G -o asset
  refuse "$cmd -o the asset's folder through a symlink" $cmd $G -o assetlink
  refuse "$cmd --json the glTF's buffer" $cmd $G -o out --json asset/quad.bin
  refuse "$cmd --json the glTF's texture" $cmd $G -o out --json assetlink/tex.png
  refuse "$cmd --json the OBJ's material library" $cmd $O -o out --json obj/quad.mtl
  refuse "$cmd --json the OBJ's texture" $cmd $O -o out --json obj/tex.png
done

# ---- pca, pop, calibrate, batch ----
refuse "pca -o the maps' folder" pca $A $B -o pics
refuse_in "$W/pics" "pca -o . beside the maps" pca reference.png test.png -o .
refuse "pca -o a map" pca $A $B -o $B
refuse "pca --json a map through a symlink" pca $A $B -o out --json link.png
refuse "pca --model: --json the glTF's buffer" pca --model $G --material m -o out --json asset/quad.bin
refuse "pca --model: -o the asset's folder through a symlink" pca --model $G --material m -o assetlink
refuse "pop -o the NEW frame" pop $A $B -o $A
refuse "pop -o the frames' folder" pop $A $B -o pics
refuse "pop --json the EXPECTED frame" pop $A $B -o out --json $B
refuse "pop --json the REF frame through a symlink" pop $A $B -o out --json link.png
refuse_in "$W/pics" "pop -o . in the frames' folder" pop reference.png test.png -o .
refuse "pop: a sequence's frame" pop seq/f%d.png seq/g%d.png --frames 0,0 -o out --json seq/g0.png
refuse "pop MODEL -o the asset's folder" pop $G -o asset
refuse "pop MODEL --json the glTF's buffer" pop $G -o out --json asset/quad.bin
refuse "calibrate -o the table" calibrate rates.csv -o rates.csv
refuse "calibrate -o a model the table names" calibrate rates.csv -o $G
refuse "calibrate --histogram a texture the model references" calibrate rates.csv -o cal.json --histogram asset/tex.png
refuse "calibrate -o that texture through a symlink" calibrate rates.csv -o assetlink/tex.png
refuse "batch -o the manifest's folder" batch assets.csv -o .
refuse "batch -o a folder holding an asset" batch assets.csv -o pics
refuse "batch --json the manifest" batch assets.csv -o out --json assets.csv
refuse "batch --json an asset through a symlink" batch assets.csv -o out --json link.png
refuse "batch --json the buffer a glTF asset references" batch model.csv -o out --json asset/quad.bin
refuse "batch -o a glTF asset's folder through a symlink" batch model.csv -o assetlink
refuse "gaze fit --json the data" gaze fit rates.csv --json rates.csv
refuse "csf -o the thresholds" csf rates.csv -o rates.csv
# report: OUT/report made a symlink to an asset's folder, which holds the
# report it reads
expect_exit 0 "a batch to report on" env -C "$W" "$JND" batch assets.csv -o bo --quiet
expect_exit 0 "its merge" env -C "$W" "$JND" batch merge bo
ln -s pair "$W/bo/report"
refuse "report into an asset's folder through a symlink" report bo
rm "$W/bo/report"
expect_exit 0 "report runs" env -C "$W" "$JND" report bo --quiet
check "  its files are published, no staging left" bash -c "[ -f '$W/bo/report/index.html' ] && ! ls -d '$W'/bo/report.jnd-partial-* 2>/dev/null"

# ---- failing midway leaves nothing ----
before=$(snap)
expect_exit 2 "an unwritable folder (under a file) is found before any work" env -C "$W" "$JND" lod $G -o rates.csv/l
check "  one line" one_line_error
check "  nothing written" [ "$before" = "$(snap)" ]
expect_exit 2 "a bad --maps found after the output folder is staged" env -C "$W" "$JND" texres builtin -o fresh/out --maps nope/baseColor --views 1
check "  one line" one_line_error
check "  no folder, no staging left" [ "$before" = "$(snap)" ]
expect_exit 2 "diff: frames of different sizes, found after staging" env -C "$W" "$JND" diff $A asset/tex.png --heatmap new/h.png --json new/h.json
check "  nothing written, no folder left" [ "$before" = "$(snap)" ]
# an earlier run's output survives a failed rerun
expect_exit 0 "a first run" env -C "$W" "$JND" diff $A $B --heatmap keep/h.png --json keep/h.json --quiet
before=$(snap)
expect_exit 2 "a failed rerun" env -C "$W" "$JND" diff $A asset/tex.png --heatmap keep/h.png --json keep/h.json
check "  the earlier output untouched" [ "$before" = "$(snap)" ]
finish
