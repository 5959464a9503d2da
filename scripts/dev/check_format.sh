#!/usr/bin/env bash
# The C++ sources follow the repository's .clang-format (clang-format 14, Debian package
# clang-format-14 or clang-format): every file of core graph filters apps tests bench examples
# is checked with --dry-run --Werror; nothing is rewritten.
#
#   bash scripts/dev/check_format.sh [REPO]     # exit 1 naming the files that differ, 0 otherwise
#   clang-format-14 -i FILE...              # to format the files you touched
set -euo pipefail
repo=${1:-$(cd "$(dirname "$0")/../.." && pwd)}
cd "$repo"
fmt=$(command -v clang-format-14 || command -v clang-format || true)
[[ -n $fmt ]] || { echo "check_format: clang-format-14 is not installed" >&2; exit 2; }

mapfile -t files < <(git ls-files core graph filters apps tests bench examples | grep -E '\.(h|hpp|cpp|cc)$')
# One clang-format over all files (fast); only when it finds a difference, one per file to name them.
if "$fmt" --style=file --dry-run --Werror "${files[@]}" >/dev/null 2>&1; then
  echo "check_format: all ${#files[@]} files follow .clang-format"
  exit 0
fi
bad=()
for f in "${files[@]}"; do
  "$fmt" --style=file --dry-run --Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if ((${#bad[@]})); then
  printf '%s\n' "${bad[@]}" | sed 's/$/: not formatted as .clang-format says/'
  echo "check_format: ${#bad[@]} of ${#files[@]} files differ from .clang-format" >&2
  exit 1
fi
echo "check_format: all ${#files[@]} files follow .clang-format"
