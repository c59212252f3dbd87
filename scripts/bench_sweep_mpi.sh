#!/usr/bin/env bash
# Runs per second of `motionblocks sweep --mpi` on 1, 2 and 3 ranks (docs/benchmarks.md, "Sweeps"), after make build:
# the seeded controller sample of diagrams/paper/sweeps/controller_random.json enlarged to RUNS runs (default 320),
# run fresh, REPETITIONS times per rank count; the wall time of the whole mpirun (start-up included, ~0.3 s here).
# With 1 rank, rank 0 runs every run itself; with N > 1, rank 0 only hands out runs and N-1 ranks simulate.
set -euo pipefail
BUILD=${BUILD:-build/release}
RUNS=${RUNS:-320}
REPETITIONS=${REPETITIONS:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The sweep's "diagram" lies outside the copy's folder, which a sweep file may not read from: it is given on the
# command line instead (motionblocks sweep DIAGRAM SWEEP).
python3 - "$PWD/diagrams/paper/sweeps/controller_random.json" "$work/sweep.json" "$RUNS" <<'PY'
import json, sys
sweep = json.load(open(sys.argv[1]))
sweep.pop("diagram")
sweep["random"]["samples"] = int(sys.argv[3])
json.dump(sweep, open(sys.argv[2], "w"))
PY
root=()
if [ "$(id -u)" -eq 0 ]; then root=(--allow-run-as-root); fi
echo "sweep --mpi, $RUNS runs of the conventional loop (3 s each), load: $(cut -d' ' -f1-3 /proc/loadavg)"
for ranks in 1 2 3; do
  for ((r = 0; r < REPETITIONS; r++)); do
    start=$(date +%s.%N)
    mpirun "${root[@]}" --oversubscribe -n "$ranks" "$BUILD/tools/motionblocks" sweep \
      diagrams/paper/conventional.json "$work/sweep.json" --mpi --fresh --quiet --out "$work/out" > /dev/null
    end=$(date +%s.%N)
    awk -v s="$start" -v e="$end" -v n="$RUNS" -v k="$ranks" \
      'BEGIN { printf "%d ranks: %.2f s, %.1f runs/s\n", k, e - s, n / (e - s) }'
  done
done
