#!/usr/bin/env bash
# ctest can_fuzz_node (tests/fuzz/CMakeLists.txt): build the libFuzzer
# harnesses, then run each for a bounded time on a temporary copy of its seed
# corpus; fails on any crash, sanitizer report or invariant violation (the
# reproducer is kept in <fuzz build dir>/artifacts/).
# usage: run_fuzz.sh CMAKE BUILD_DIR FUZZ_BIN_DIR CORPUS_DIR SECONDS HARNESS...
#        run_fuzz.sh --skip REASON   (exit 77: ctest reports the test skipped)
set -euo pipefail
if [[ "${1:-}" == "--skip" ]]; then
  echo "can_fuzz_node skipped: ${2:-no fuzzing compiler}"
  exit 77
fi
cmake=$1 build=$2 bin=$3 corpus=$4 seconds=$5
shift 5
"$cmake" --build "$build" --target mc_can_fuzzers --parallel 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$bin/artifacts"
status=0
for h in "$@"; do
  mkdir -p "$tmp/$h"
  cp "$corpus/$h"/* "$tmp/$h/"
  log="$bin/fuzz_$h.log"
  echo "== fuzz_$h: ${seconds} s on $(ls "$tmp/$h" | wc -l) seed inputs (log: $log)"
  if ! "$bin/fuzz_$h" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
      -print_final_stats=1 -artifact_prefix="$bin/artifacts/${h}-" "$tmp/$h" >"$log" 2>&1; then
    echo "fuzz_$h FAILED:"
    tail -n 60 "$log"
    status=1
    continue
  fi
  grep -E '^(INFO: Seed|#[0-9]+ +DONE|stat::number_of_executed_units|stat::average_exec_per_sec|stat::new_units_added|stat::peak_rss_mb)' "$log" || true
  echo "corpus after the run: $(ls "$tmp/$h" | wc -l) inputs"
done
exit $status
