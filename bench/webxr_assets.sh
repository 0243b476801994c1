# The npm package @webxr-input-profiles/assets (MIT): real controller models
# for bench/bench_render.sh, bench/bench_texres.sh, bench/bench_pca.sh and the
# webxr tests. Pinned to one version, checked against its SHA-256, fetched once
# into a cache outside the build folder by scripts/install-deps.sh (or by
# bench), never by a test: tests only read the cache, so the suite makes no
# network request and parallel tests never race on unpacking.
#
#   webxr_assets         prints the unpacked package folder; 1 when not cached
#   webxr_assets_fetch   fetches the pinned version into the cache unless it is
#                        there; 1 (with a one-line reason on stderr) when it cannot
#   webxr_assets_cache   the cache folder (JND_CACHE, else XDG_CACHE_HOME/jnd,
#                        else ~/.cache/jnd)
WEBXR_ASSETS_VERSION=1.0.20
# sha256 of webxr-input-profiles-assets-1.0.20.tgz; the registry's integrity
# for it is sha512-V/8NB4Ywgm//TBVMgo0TgJ9DtxsBoo0iiaF8AdfiP0F0cgbwkuQycEZAIOsplyd/iZ8L3mrFYNJBC6rzQb4tJA==
WEBXR_ASSETS_SHA256=30df2a2268220fc0d0e034bed1550aabdd7a2500573c5216f64fc70d59c3d91e
WEBXR_ASSETS_CHECK=dist/profiles # a folder the unpacked package has

. "$(dirname "${BASH_SOURCE[0]}")/../scripts/npm_cache.sh"

webxr_assets_cache() { npm_cache_dir @webxr-input-profiles/assets "$WEBXR_ASSETS_VERSION"; }

webxr_assets() { npm_cache_package @webxr-input-profiles/assets "$WEBXR_ASSETS_VERSION" "$WEBXR_ASSETS_CHECK"; }

webxr_assets_fetch() {
  npm_cache_fetch @webxr-input-profiles/assets "$WEBXR_ASSETS_VERSION" "$WEBXR_ASSETS_SHA256" "$WEBXR_ASSETS_CHECK"
}
