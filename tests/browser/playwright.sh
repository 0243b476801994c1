# The npm package playwright-core (Apache-2.0): the driver of Debian's chromium
# in tests/e2e/report_browser_slow.sh. Pinned to one version, checked against
# its SHA-256, fetched once into the npm cache (scripts/npm_cache.sh) by
# scripts/install-deps.sh, never by a test. 1.61 is the last release that
# runs on Debian 12's Node 18.
#
#   playwright_core        prints the unpacked package folder; 1 when not cached
#   playwright_core_fetch  fetches the pinned version unless it is cached
PLAYWRIGHT_CORE_VERSION=1.61.1
# sha256 of playwright-core-1.61.1.tgz; the registry's integrity for it is
# sha512-h7Qlt6m4REp25qvIdvbDtVmD4LqVXfpRxhORv9L0jzETM05p4fuPJ3dKyuSXQxDSbXnmS79HAgi9589lGSpLkg==
PLAYWRIGHT_CORE_SHA256=3740bba3a3e93b4c7bd7c0f6e3c0e5f8cdce498bef13511e4d534cc99a8ce198
PLAYWRIGHT_CORE_CHECK=package.json # a file the unpacked package has

. "$(dirname "${BASH_SOURCE[0]}")/../../scripts/npm_cache.sh"

playwright_core() { npm_cache_package playwright-core "$PLAYWRIGHT_CORE_VERSION" "$PLAYWRIGHT_CORE_CHECK"; }

playwright_core_fetch() {
  npm_cache_fetch playwright-core "$PLAYWRIGHT_CORE_VERSION" "$PLAYWRIGHT_CORE_SHA256" "$PLAYWRIGHT_CORE_CHECK"
}
