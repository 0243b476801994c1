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

webxr_assets_cache() {
  echo "${JND_CACHE:-${XDG_CACHE_HOME:-${HOME:-/tmp}/.cache}/jnd}/webxr-input-profiles-assets-$WEBXR_ASSETS_VERSION"
}

webxr_assets() {
  local d
  d="$(webxr_assets_cache)/package"
  [ -d "$d/dist/profiles" ] || return 1
  echo "$d"
}

# npm pack into a temporary folder beside the cache, check the tarball,
# unpack there, then one rename puts the complete package in place: a reader
# sees either no cache or a whole one, and of two concurrent fetches the
# second's rename fails harmlessly and its copy is removed.
webxr_assets_fetch() {
  local dest parent tmp tgz sum
  dest=$(webxr_assets_cache)
  [ -d "$dest/package/dist/profiles" ] && return 0
  command -v npm >/dev/null 2>&1 || { echo "webxr assets: npm is not installed" >&2; return 1; }
  parent=$(dirname "$dest")
  mkdir -p "$parent" || { echo "webxr assets: cannot create $parent" >&2; return 1; }
  tmp=$(mktemp -d "$parent/.fetch-webxr.XXXXXX") || return 1
  tgz=$(cd "$tmp" && timeout 600 npm pack --silent --fetch-retries=2 --fetch-timeout=60000 \
        "@webxr-input-profiles/assets@$WEBXR_ASSETS_VERSION" 2>/dev/null | tail -1)
  if [ -z "$tgz" ] || [ ! -f "$tmp/$tgz" ]; then
    rm -rf "$tmp"
    echo "webxr assets: npm pack @webxr-input-profiles/assets@$WEBXR_ASSETS_VERSION failed (no network?)" >&2
    return 1
  fi
  sum=$(sha256sum "$tmp/$tgz" | cut -c1-64)
  if [ "$sum" != "$WEBXR_ASSETS_SHA256" ]; then
    rm -rf "$tmp"
    echo "webxr assets: $tgz has sha256 $sum, not the pinned $WEBXR_ASSETS_SHA256" >&2
    return 1
  fi
  if ! tar -xzf "$tmp/$tgz" -C "$tmp" || [ ! -d "$tmp/package/dist/profiles" ]; then
    rm -rf "$tmp"
    echo "webxr assets: $tgz does not unpack to package/dist/profiles" >&2
    return 1
  fi
  rm -f "$tmp/$tgz"
  chmod 755 "$tmp" # mktemp made it private
  mv -T "$tmp" "$dest" 2>/dev/null || rm -rf "$tmp"
  [ -d "$dest/package/dist/profiles" ]
}
