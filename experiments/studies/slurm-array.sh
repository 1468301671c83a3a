#!/usr/bin/env bash
# A SLURM job array over the shards of one study or suite: task i of N runs `--shard i/N` into
# OUT/shard-i; a requeued or resubmitted task continues its shard (--resume once the shard has
# started). Afterwards `lgvi-testbed merge OUT/merged OUT/shard-*` checks that every shard is
# there and complete, and `--render-only --out OUT/merged` draws the figures, tables and
# statistics (docs/suites.md, "Sharding").
#
#   sbatch --array=0-15 --cpus-per-task=2 experiments/studies/slurm-array.sh study FILE.toml OUT [OPTIONS...]
#   sbatch --array=0-15 experiments/studies/slurm-array.sh suite NAME OUT [OPTIONS...]
#
# OPTIONS are passed on (`--quick`, `--no-plots`, ...). The array must be 0..N-1 (any
# throttle, e.g. --array=0-99%10); N is the array's size. Each task uses --jobs
# $SLURM_CPUS_PER_TASK (1 if unset). The program is $LGVI_TESTBED, by default
# build/lgvi-testbed under the directory sbatch was called from, else lgvi-testbed on the PATH
# (an installed package). On several nodes OUT must lie on a file system every node sees, and
# so must the study file and its scenes.
#SBATCH --job-name=lgvi-shards
#SBATCH --requeue
set -euo pipefail

if [ $# -lt 3 ] || { [ "$1" != study ] && [ "$1" != suite ]; }; then
  echo "usage: sbatch --array=0-(N-1) $0 study FILE.toml|suite NAME OUT [OPTIONS...]" >&2
  exit 2
fi
kind=$1 what=$2 out=$3
shift 3
if [ -z "${SLURM_ARRAY_TASK_ID:-}" ] || [ -z "${SLURM_ARRAY_TASK_COUNT:-}" ]; then
  echo "$0: not a task of a job array (submit with sbatch --array=0-(N-1))" >&2
  exit 2
fi
if [ "${SLURM_ARRAY_TASK_MIN}" -ne 0 ] || [ "${SLURM_ARRAY_TASK_MAX}" -ne $(( SLURM_ARRAY_TASK_COUNT - 1 )) ]; then
  echo "$0: the array must be 0-$(( SLURM_ARRAY_TASK_COUNT - 1 )) without gaps (got ${SLURM_ARRAY_TASK_MIN}-${SLURM_ARRAY_TASK_MAX}, ${SLURM_ARRAY_TASK_COUNT} tasks)" >&2
  exit 2
fi
exe=${LGVI_TESTBED:-${SLURM_SUBMIT_DIR:-.}/build/lgvi-testbed}
if [ -z "${LGVI_TESTBED:-}" ] && [ ! -x "$exe" ] && command -v lgvi-testbed >/dev/null; then
  exe=lgvi-testbed  # an installed package
fi
shard_dir="$out/shard-${SLURM_ARRAY_TASK_ID}"
resume=()
[ -f "$shard_dir/suite-run.json" ] && resume=(--resume)  # a requeued task: finish the shard
exec "$exe" "$kind" "$what" --shard "${SLURM_ARRAY_TASK_ID}/${SLURM_ARRAY_TASK_COUNT}" \
  --jobs "${SLURM_CPUS_PER_TASK:-1}" --out "$shard_dir" "${resume[@]}" "$@"
