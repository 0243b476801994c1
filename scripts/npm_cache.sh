# Pinned npm packages in a cache outside the build folder: scripts/install-deps.sh
# (and bench/) fetch them, tests only read them, so the suite makes no network
# request and parallel tests never race on unpacking. Source this file.
#
#   npm_cache_dir NAME VERSION        the package's cache folder (the unpacked
#                                     package is its package/), under JND_CACHE,
#                                     else XDG_CACHE_HOME/jnd, else ~/.cache/jnd
#   npm_cache_package NAME VERSION CHECK
#                                     prints the unpacked package folder when
#                                     package/CHECK is there; 1 when not cached
#   npm_cache_fetch NAME VERSION SHA256 CHECK
#                                     fetches NAME@VERSION unless package/CHECK is
#                                     there; 1 (with a one-line reason on stderr)
#                                     when it cannot
#   npm_cache_install NAME VERSION SHA256 CHECK WITHOUT
#                                     scripts/install-deps.sh's step: fetches it
#                                     unless cached (offline: nothing to do), saying
#                                     so; when it cannot, warns "without it WITHOUT"
# Each pinned package (bench/webxr_assets.sh, tests/browser/playwright.sh,
# scripts/gltf_validator.sh) states its name, version, SHA-256 and CHECK file
# once and calls these; none repeats the fetch.
npm_cache_dir() {
  local name=${1#@}
  echo "${JND_CACHE:-${XDG_CACHE_HOME:-${HOME:-/tmp}/.cache}/jnd}/${name//\//-}-$2"
}

npm_cache_package() {
  local d
  d="$(npm_cache_dir "$1" "$2")/package"
  [ -e "$d/$3" ] || return 1
  echo "$d"
}

# npm pack into a temporary folder beside the cache, check the tarball's
# sha256, unpack there, then one rename puts the complete package in place: a
# reader sees either no cache or a whole one, and of two concurrent fetches the
# second's rename fails harmlessly and its copy is removed.
npm_cache_fetch() {
  local name=$1 version=$2 sha=$3 check=$4 dest parent tmp tgz sum
  dest=$(npm_cache_dir "$name" "$version")
  [ -e "$dest/package/$check" ] && return 0
  command -v npm >/dev/null 2>&1 || { echo "$name: npm is not installed" >&2; return 1; }
  parent=$(dirname "$dest")
  mkdir -p "$parent" || { echo "$name: cannot create $parent" >&2; return 1; }
  tmp=$(mktemp -d "$parent/.fetch.XXXXXX") || return 1
  tgz=$(cd "$tmp" && timeout 600 npm pack --silent --fetch-retries=2 --fetch-timeout=60000 \
        "$name@$version" 2>/dev/null | tail -1)
  if [ -z "$tgz" ] || [ ! -f "$tmp/$tgz" ]; then
    rm -rf "$tmp"
    echo "$name: npm pack $name@$version failed (no network?)" >&2
    return 1
  fi
  sum=$(sha256sum "$tmp/$tgz" | cut -c1-64)
  if [ "$sum" != "$sha" ]; then
    rm -rf "$tmp"
    echo "$name: $tgz has sha256 $sum, not the pinned $sha" >&2
    return 1
  fi
  if ! tar -xzf "$tmp/$tgz" -C "$tmp" || [ ! -e "$tmp/package/$check" ]; then
    rm -rf "$tmp"
    echo "$name: $tgz does not unpack to package/$check" >&2
    return 1
  fi
  rm -f "$tmp/$tgz"
  chmod 755 "$tmp" # mktemp made it private
  mv -T "$tmp" "$dest" 2>/dev/null || rm -rf "$tmp"
  [ -e "$dest/package/$check" ]
}

npm_cache_install() {
  local name=$1 version=$2 sha=$3 check=$4 without=$5
  npm_cache_package "$name" "$version" "$check" >/dev/null && return 0
  echo "install-deps: fetching $name@$version into $(npm_cache_dir "$name" "$version")" >&2
  npm_cache_fetch "$name" "$version" "$sha" "$check" || echo "install-deps: warning: without it $without" >&2
}
