#!/usr/bin/env bash
# Size limits of the code (docs/architecture.md): no function in core, graph, filters or apps over
# 120 lines and no source file (code or test) over 600 lines, unless a comment containing "size:"
# says why (a data table, say). The comment goes in the function's body or in the 5 lines above
# it; for a file, in its first 40 lines.
#
#   bash scripts/dev/check_sizes.sh [REPO]      # exit 1 listing every unjustified one, 0 otherwise
#
# Functions are found by Universal Ctags (Debian package universal-ctags).
set -euo pipefail
repo=${1:-$(cd "$(dirname "$0")/../.." && pwd)}
cd "$repo"
max_function=120
max_file=600
command -v ctags >/dev/null || { echo "check_sizes: ctags (universal-ctags) is not installed" >&2; exit 2; }

status=0
# Functions: "end start file name" per function definition.
while read -r end start file name; do
  n=$((end - start + 1))
  ((n > max_function)) || continue
  from=$((start > 5 ? start - 5 : 1))
  # grep reads all its input (no -q): an early exit would SIGPIPE sed, and under pipefail a
  # justified function would then be reported, depending on timing.
  if sed -n "${from},${end}p" "$file" | grep 'size:' >/dev/null; then continue; fi
  echo "$file:$start: function $name is $n lines (> $max_function) with no 'size:' comment saying why"
  status=1
done < <(ctags -R --languages=C++ --kinds-C++=f --fields=+ne -x --_xformat="%{end} %{line} %F %N" \
           core graph filters apps | awk '$1 ~ /^[0-9]+$/')

# Files: code and tests.
while read -r file; do
  n=$(wc -l <"$file")
  ((n > max_file)) || continue
  if head -n 40 "$file" | grep 'size:' >/dev/null; then continue; fi
  echo "$file: $n lines (> $max_file) with no 'size:' comment saying why"
  status=1
done < <(git ls-files core graph filters apps tests bench examples | grep -E '\.(h|hpp|cpp|cc)$')

if ((status == 0)); then echo "check_sizes: every function <= $max_function and file <= $max_file lines, or justified"; fi
exit $status
