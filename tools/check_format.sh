#!/usr/bin/env bash
# Fails (listing the files) when a tracked C file differs from what
# clang-format makes of it with the project's .clang-format files.
# usage: tools/check_format.sh [CLANG_FORMAT]
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
clang_format=${1:-clang-format}
cd "$repo"
mapfile -t files < <(git ls-files '*.c' '*.h')
if ! report=$("$clang_format" --dry-run --Werror "${files[@]}" 2>&1); then
  echo "check_format: files not formatted (run: clang-format -i FILE):" >&2
  grep -o '^[^:]*\.[ch]:' <<<"$report" | sort -u | sed 's/:$//; s/^/  /' >&2
  exit 1
fi
echo "check_format: ${#files[@]} files formatted"
