#!/bin/bash
# A bifurcation sweep as a Slurm job array: each array task runs one shard, then a job that
# depends on the whole array merges the shard files (and their .verdicts.csv files).
#
# Submit from the repository root (with linkdyn on PATH, e.g. `cargo install --path .`):
#     sbatch docs/slurm_bifurcation.sh            # submits the array and the merge job
# Change the sweep below; SHARDS must match the --array range. A task that was killed (time limit,
# pre-emption) is re-run with the same command: --resume keeps its finished points.
#
#SBATCH --job-name=linkdyn-sweep
#SBATCH --array=1-8
#SBATCH --cpus-per-task=4
#SBATCH --time=01:00:00
#SBATCH --output=sweep_%A_%a.log

set -euo pipefail

SHARDS=8
MODEL=models/farahan2016.toml
OUT=results/fig6a
SWEEP=(--param joints.B.clearance --from 0.00005 --to 0.0005 --steps 199
       --revs 150 --transient 100 --observe coupler.phi
       --set drivers.motor.speed_rpm=3500 --formulation reduced)

mkdir -p "$(dirname "$OUT")"

if [[ "${1:-}" == "merge" ]]; then
    # The merge job: checks that every point is there exactly once, then joins.
    shards=()
    for i in $(seq 1 "$SHARDS"); do shards+=("${OUT}.shard${i}.csv"); done
    linkdyn merge "${shards[@]}" --out "${OUT}.csv"
    exit 0
fi

if [[ -z "${SLURM_ARRAY_TASK_ID:-}" ]]; then
    # Not inside the array: submit the array, then the merge after all its tasks succeed.
    array=$(sbatch --parsable "$0")
    sbatch --dependency=afterok:"${array}" --job-name=linkdyn-merge \
        --output=merge_%j.log --wrap="bash $0 merge"
    exit 0
fi

status=0
linkdyn bifurcation "$MODEL" "${SWEEP[@]}" \
    --shard "$((SLURM_ARRAY_TASK_ID))/${SLURM_ARRAY_TASK_COUNT}" \
    --threads "${SLURM_CPUS_PER_TASK:-1}" --resume \
    --out "${OUT}.shard${SLURM_ARRAY_TASK_ID}.csv" || status=$?
# Exit 5: the shard finished, but some points failed; they are in its files (verdict "failed",
# NaN rows, the message), so the merge may run. Re-running this task (--resume) retries them.
if [[ $status -eq 5 ]]; then
    echo "shard ${SLURM_ARRAY_TASK_ID}: finished with failed points (see the message above)" >&2
    exit 0
fi
exit "$status"
