#!/usr/bin/env bash
# A sweep as a Slurm job array: one shard per array task, then one merge (docs/sweeps.md).
#   sbatch docs/cluster/slurm_sweep.sh                                  # 16 shards
#   sbatch --dependency=afterok:<job id> --wrap "motionblocks sweep-merge out/robustness/shard_* --out out/robustness/all"
# The array must be numbered 0 to N-1: --shard auto takes K = SLURM_ARRAY_TASK_ID, N = SLURM_ARRAY_TASK_COUNT.
# A task that was preempted or timed out is resubmitted as is (sbatch --array=<K> …): its shard resumes.
#SBATCH --job-name=mb-sweep
#SBATCH --array=0-15
#SBATCH --cpus-per-task=4
#SBATCH --time=02:00:00
#SBATCH --output=out/robustness/slurm-%A_%a.log
set -euo pipefail
SWEEP=${SWEEP:-diagrams/paper/sweeps/controller_random.json}
OUT=${OUT:-out/robustness}
motionblocks sweep "$SWEEP" --shard auto --jobs "${SLURM_CPUS_PER_TASK:-1}" --quiet \
  --out "$OUT/shard_${SLURM_ARRAY_TASK_ID}"
