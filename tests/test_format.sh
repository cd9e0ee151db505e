#!/usr/bin/env bash
# Every C, C++ and OpenCL source is laid out as .clang-format says (clang-format 14, the version of the CI image;
# another major version lays some lines out differently, so the check is skipped there, exit 77, saying why).
# Usage: test_format.sh REPO_ROOT
set -euo pipefail
src=$1
command -v clang-format > /dev/null || { echo "format: no clang-format (scripts/install-deps.sh installs it): skipped"; exit 77; }
major=$(clang-format --version | grep -oE 'version [0-9]+' | grep -oE '[0-9]+')
[ "$major" = 14 ] || { echo "format: clang-format $major, not 14: skipped"; exit 77; }
cd "$src"
mapfile -t files < <(git ls-files '*.c' '*.h' '*.cc' '*.cpp' '*.hpp' '*.cl' '*.cu' 2> /dev/null ||
  find . -path './build*' -prune -o -path './.git' -prune -o -type f \( -name '*.c' -o -name '*.h' -o -name '*.cc' \
    -o -name '*.cpp' -o -name '*.hpp' -o -name '*.cl' -o -name '*.cu' \) -print)
[ "${#files[@]}" -gt 100 ] || { echo "FAIL: only ${#files[@]} source files found under $src"; exit 1; }
log=$(mktemp); trap 'rm -f "$log"' EXIT
if ! clang-format --dry-run --Werror "${files[@]}" 2> "$log"; then
  grep -E '^[^ ].*: error:' "$log" | cut -d: -f1,2 | head -20 || true
  echo "FAIL: $(grep -cE ': error:' "$log") lines not as .clang-format lays them out (clang-format -i FILE)"
  exit 1
fi
echo "format: ${#files[@]} files ok"
