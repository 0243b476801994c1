#!/bin/bash
# Packs a built jnd, the Debian libraries it links, Mesa's EGL + llvmpipe and
# the bench assets into .gpu/ (ignored by git) for a GPU machine that has the
# NVIDIA driver but none of Debian's -dev packages and no network, so that
# bench/device/timings.sh there can time the vendor's EGL device beside
# llvmpipe on the same cores (docs/gpu.md).
#   bench/device/bundle.sh [BUILD]     (BUILD defaults to build)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$root/build}
shared=${JND_SHARED:-$root/../shared}
stage=$(mktemp -d); trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/bin" "$stage/lib" "$stage/mesa/dri" "$stage/assets"
# the C library and the loader stay the machine's own; everything else travels
system='^(linux-vdso|libc\.so|libm\.so|libpthread\.so|libdl\.so|librt\.so|ld-linux)'
deps() { ldd "$@" | awk '$3 ~ /^\// {print $3}' | sort -u; }
cp "$build/jnd" "$stage/bin/"
for l in $(deps "$build/jnd"); do basename "$l" | grep -Eq "$system" || cp -L "$l" "$stage/lib/"; done
gl=/usr/lib/x86_64-linux-gnu
for l in libEGL.so.1 libGLdispatch.so.0 libOpenGL.so.0; do cp -L "$gl/$l" "$stage/lib/"; done
cp -L "$gl/dri/swrast_dri.so" "$stage/mesa/dri/"
cp -L "$gl/libEGL_mesa.so.0" "$stage/mesa/"
cp /usr/share/glvnd/egl_vendor.d/50_mesa.json "$stage/mesa/"
for l in $(deps "$gl/dri/swrast_dri.so" "$gl/libEGL_mesa.so.0"); do
  b=$(basename "$l"); echo "$b" | grep -Eq "$system" || [ -e "$stage/lib/$b" ] || cp -L "$l" "$stage/mesa/"
done
. "$root/scripts/npm_cache.sh"; . "$root/bench/webxr_assets.sh"
cp "$(webxr_assets)/dist/profiles/hp-mixed-reality/left.glb" "$stage/assets/hp-left.glb"
python3 "$root/bench/subdivide_obj.py" "$shared/data/meshes/teapot.obj" "$stage/assets/teapot_100k.obj" 2
mkdir -p "$root/.gpu"
grep -qx '/.gpu/' "$root/.git/info/exclude" 2>/dev/null || echo '/.gpu/' >>"$root/.git/info/exclude"
(cd "$stage" && tar cf - bin lib assets | xz -T2 -6 >"$root/.gpu/jnd.tar.xz")
(cd "$stage" && tar cf - mesa | xz -T2 -6 >"$root/.gpu/mesa.tar.xz")
cp "$root/bench/device/timings.sh" "$root/.gpu/run.sh"
du -sh "$root/.gpu"
