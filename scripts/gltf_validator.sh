# The npm package gltf-validator (Apache-2.0): the Khronos glTF-Validator
# compiled to JavaScript, no dependencies, run by Node. tests/e2e/budget.sh
# checks the GLB that `jnd budget` writes with it (0 errors). Pinned to one
# version, checked against its SHA-256, fetched once into the npm cache
# (scripts/npm_cache.sh) by scripts/install-deps.sh, never by a test.
#
#   gltf_validator        prints the unpacked package folder; 1 when not cached
#   gltf_validator_fetch  fetches the pinned version unless it is cached
#   gltf_validator_run F  validates F (glTF or GLB): prints the numbers of
#                         errors, warnings, infos and hints and every error;
#                         0 when it has no error, 1 otherwise, 2 without the
#                         cache or node
GLTF_VALIDATOR_VERSION=2.0.0-dev.3.10
# sha256 of gltf-validator-2.0.0-dev.3.10.tgz; the registry's integrity for it is
# sha512-odJ4k0tRkGXiDGn78yDBg+fBbAIvBnXxh3RwAta0emSxGtyagFE8B4xELB1oYe3S5RD8Ci3uZAsZaascH2LAEQ==
GLTF_VALIDATOR_SHA256=4e03dbdc3bc0d1342afd5d2d7ae341a7e3474502ccb872b02dbbaddaee0fdec6
GLTF_VALIDATOR_CHECK=gltf_validator.dart.js # a file the unpacked package has

. "$(dirname "${BASH_SOURCE[0]}")/npm_cache.sh"

gltf_validator() { npm_cache_package gltf-validator "$GLTF_VALIDATOR_VERSION" "$GLTF_VALIDATOR_CHECK"; }

gltf_validator_fetch() {
  npm_cache_fetch gltf-validator "$GLTF_VALIDATOR_VERSION" "$GLTF_VALIDATOR_SHA256" "$GLTF_VALIDATOR_CHECK"
}

gltf_validator_run() {
  local d
  d=$(gltf_validator) && command -v node >/dev/null 2>&1 || return 2
  node - "$d" "$1" <<'JS'
const [dir, file] = process.argv.slice(2);
const validator = require(dir + "/index.js");
const data = new Uint8Array(require("fs").readFileSync(file));
validator.validateBytes(data, { uri: file, maxIssues: 1000 }).then((r) => {
  const i = r.issues;
  console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints`);
  for (const m of i.messages) if (m.severity === 0) console.log(`  ${m.code} ${m.pointer || ""}: ${m.message}`);
  process.exit(i.numErrors === 0 ? 0 : 1);
}, (e) => { console.log(`${file}: the validator failed: ${e}`); process.exit(1); });
JS
}
