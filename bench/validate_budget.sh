#!/usr/bin/env bash
# The Khronos glTF-Validator (scripts/gltf_validator.sh: the pinned npm
# package, cached by scripts/install-deps.sh) on every model jnd budget wrote
# under DIR (default: bench_budget.sh's output, BENCH_OUT/budget): per model
# its errors, warnings, infos and hints, and each error. Issue 27 asks for 0
# errors. Called at the end of bench_budget.sh; runs alone too.
#
#   usage: bench/validate_budget.sh [DIR]
# Exit 0 when every model has no error (or there is none to check), 1 when
# one has, 2 without the validator's cache or node.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../scripts/gltf_validator.sh"
dir=${1:-${BENCH_OUT:-$here/out}/budget}
if ! gltf_validator >/dev/null || ! command -v node >/dev/null; then
  echo "   glTF-Validator skipped: gltf-validator@$GLTF_VALIDATOR_VERSION is not cached or node is missing (scripts/install-deps.sh)"
  exit 2
fi
models=()
while IFS= read -r -d '' f; do models+=("$f"); done < <(find "$dir" -path '*/model/*' \( -name '*.glb' -o -name '*.gltf' \) -print0 2>/dev/null | sort -z)
if [ ${#models[@]} -eq 0 ]; then
  echo "   glTF-Validator: no model written under $dir"
  exit 0
fi
echo "   glTF-Validator $GLTF_VALIDATOR_VERSION on the written models:"
status=0
for f in "${models[@]}"; do
  # its first line "FILE: N errors, N warnings, N infos, N hints", then one line per error
  gltf_validator_run "$f" | sed -e "s|^  |       |" -e "s|^$dir/|     |"
  [ "${PIPESTATUS[0]}" -eq 0 ] || status=1
done
exit $status
