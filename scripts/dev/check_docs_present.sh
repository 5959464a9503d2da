#!/usr/bin/env bash
# docs/ describes the present (docs/architecture.md, "Tests"): no page outside docs/results/ tells
# what was before. Fails listing every line of README.md or docs/*.md (docs/results/ excluded)
# that speaks of history:
#   - "before the fix", "found and fixed", "previous main", "previous run", "earlier version(s)",
#     "old binary", "used up to";
#   - a commit hash in prose (7-40 hex digits with both a digit and a letter), except in fenced
#     code blocks and on a result's provenance line (starting "Command:" or "Written by"), which
#     may name the commit that wrote it.
# History lives in git log.
#
#   bash scripts/dev/check_docs_present.sh [REPO]   # exit 1 listing each line, 0 otherwise
set -euo pipefail
repo=${1:-$(cd "$(dirname "$0")/../.." && pwd)}
cd "$repo"
phrases='before the fix( [^a]|[.,;:)]|$)|found and fixed|previous main|previous run|earlier versions?|old binary|used up to'
status=0
for f in README.md docs/*.md; do
  hits=$(awk -v phrases="$phrases" '
    /^```/ { fence = !fence; next }
    fence { next }
    {
      line = tolower($0)
      if (line ~ phrases) { printf "%s:%d: history: %s\n", FILENAME, FNR, $0; next }
      if ($0 ~ /^(Command:|Written by)/) next
      rest = $0
      while (match(rest, /[0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f][0-9a-f]+/)) {
        tok = substr(rest, RSTART, RLENGTH)
        before = RSTART > 1 ? substr(rest, RSTART - 1, 1) : " "
        after = substr(rest, RSTART + RLENGTH, 1)
        rest = substr(rest, RSTART + RLENGTH)
        if (before ~ /[0-9A-Za-z_.-]/ || after ~ /[0-9A-Za-z_-]/) continue
        if (tok ~ /[0-9]/ && tok ~ /[a-f]/ && length(tok) <= 40) {
          printf "%s:%d: commit hash %s in prose: %s\n", FILENAME, FNR, tok, $0
          break
        }
      }
    }' "$f")
  if [ -n "$hits" ]; then
    echo "$hits"
    status=1
  fi
done
if ((status == 0)); then echo "check_docs_present: no page outside docs/results/ speaks of what was before"; fi
exit $status
