#!/usr/bin/env bash
# Commit subjects of at most 72 characters, from the commit that added this script on (older
# history is left as it is). Part of the test command's first stage (scripts/test.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
if ! git rev-parse --git-dir >/dev/null 2>&1; then
  echo "check-commits: not a git checkout: nothing to check"
  exit 0
fi
base=$(git log --diff-filter=A --format=%H -- scripts/check-commits.sh | tail -1)
if [ -z "$base" ]; then
  echo "check-commits: this script is not committed yet: nothing to check"
  exit 0
fi
range="$base"
git rev-parse -q --verify "$base^" >/dev/null && range="$base^..HEAD"
bad=$(git log --format='%h %s' "$range" | awk '{ s = substr($0, index($0, " ") + 1); if (length(s) > 72) print }')
if [ -n "$bad" ]; then
  echo "check-commits: subjects over 72 characters (reword them before they land):" >&2
  echo "$bad" >&2
  exit 1
fi
echo "check-commits: $(git rev-list --count "$range") commit subjects of at most 72 characters"
