# Shared by bench/bench_render.sh and tests/e2e/render_webxr.sh:
# webxr_assets CACHE_DIR prints the folder of the unpacked npm package
# @webxr-input-profiles/assets (MIT), fetching it with `npm pack` into
# CACHE_DIR the first time. Returns 1 when npm or the network is missing.
webxr_assets() {
  local cache=$1
  if [ -d "$cache/package/dist/profiles" ]; then echo "$cache/package"; return 0; fi
  command -v npm >/dev/null 2>&1 || return 1
  mkdir -p "$cache" || return 1
  local tgz
  tgz=$(cd "$cache" && timeout 120 npm pack --silent --fetch-retries=1 --fetch-timeout=30000 @webxr-input-profiles/assets 2>/dev/null | tail -1) || return 1
  [ -n "$tgz" ] && [ -f "$cache/$tgz" ] || return 1
  tar -xzf "$cache/$tgz" -C "$cache" || return 1
  [ -d "$cache/package/dist/profiles" ] || return 1
  echo "$cache/package"
}
