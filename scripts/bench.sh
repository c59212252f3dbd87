#!/usr/bin/env bash
# make bench (after make build): every Google Benchmark program of the Release build, results as JSON in out/bench/ and a
# one-line summary per benchmark on the terminal. Compare CPU time across machines (docs/benchmarks.md).
set -euo pipefail
BUILD=${BUILD:-build/release}
OUT=${OUT:-out/bench}
mkdir -p "$OUT"
for program in "$BUILD"/tests/benchmarks/*_benchmark; do
  name=$(basename "$program")
  echo "== $name"
  "$program" --benchmark_repetitions="${REPETITIONS:-3}" --benchmark_report_aggregates_only=true \
    --benchmark_out="$OUT/$name.json" --benchmark_out_format=json
done
echo "results: $OUT/*.json (machine load at the time: $(cut -d' ' -f1-3 /proc/loadavg))"
