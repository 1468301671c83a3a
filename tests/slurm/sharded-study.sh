#!/usr/bin/env bash
# CI's proof that a study spreads over a SLURM job array unchanged (DESIGN.md, "Beyond one
# machine"): on a private single-node cluster (single-node.sh) the shipped job script
# experiments/studies/slurm-array.sh runs STUDY's quick form as a 3-task array, then the same
# array again (each task finds its shard finished and resumes it: nothing is re-run); `merge`
# joins the shards and `--render-only` draws them. The merged summary.csv and summary.jsonl must
# equal a single-process run of the same study, timings aside (the fields whose names contain
# "seconds" or "timing", or end in "detail", which quotes the time), and so must every
# statistics table the two renderings write (NAME-statistics.csv; its rows of timed metrics
# aside).
# If the cluster cannot start here, the reason is printed and the job script's tasks run
# through xargs -P instead, given the variables SLURM would set (what the GNU parallel recipe of
# docs/suites.md does), so that the sharding and the job script are still checked; LGVI_REQUIRE_SLURM=1 makes that a failure. KEEP=1 keeps the work directory.
#
#   bash tests/slurm/sharded-study.sh [BUILD_DIR] [STUDY.toml]   (default build-test, ensemble-bodies.toml)
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
build=$(realpath "${1:-build-test}")
study=$(realpath "${2:-experiments/studies/ensemble-bodies.toml}")
exe="$build/lgvi-testbed"
shards=3
[ -x "$exe" ] || { echo "sharded-study.sh: $exe not built" >&2; exit 1; }
work=$(mktemp -d /tmp/lgvi-slurm.XXXXXX)
cluster="$work/cluster"
cleanup() { bash "$root/tests/slurm/single-node.sh" stop "$cluster" >/dev/null 2>&1 || true; rm -rf "$work"; }
trap cleanup EXIT
[ -n "${KEEP:-}" ] && trap "bash $root/tests/slurm/single-node.sh stop $cluster" EXIT
start=$(date +%s)
stamp() { echo "sharded-study.sh: $1 ($(( $(date +%s) - start )) s)"; }

run_array() {  # every shard of the array through SLURM, or through xargs when SLURM is not up
  if [ -n "${SLURM_CONF:-}" ]; then
    # sbatch --wait polls every few seconds; squeue every 0.2 s, then each task's final state.
    local job
    job=$(LGVI_TESTBED="$exe" sbatch --parsable --array=0-$(( shards - 1 )) --chdir="$work" \
      --output="$work/task-%a.log" "$root/experiments/studies/slurm-array.sh" study "$study" "$work/out" --quick)
    while [ -n "$(squeue -h -j "$job" 2>/dev/null)" ]; do sleep 0.2; done
    local states
    states=$(scontrol -o show job "$job" | grep -o 'JobState=[A-Z_]* .*ExitCode=[0-9:]*' | sed 's/ .*ExitCode=/ /')
    if [ "$(grep -c '^JobState=COMPLETED 0:0$' <<< "$states")" -ne "$shards" ]; then
      echo "sharded-study.sh: job $job's tasks ended: $(tr '\n' ';' <<< "$states")" >&2
      tail -n 20 "$work"/task-*.log >&2
      return 1
    fi
  else
    # the same job script, given the variables SLURM would set for task {}
    seq 0 $(( shards - 1 )) | LGVI_TESTBED="$exe" SLURM_ARRAY_TASK_COUNT=$shards SLURM_ARRAY_TASK_MIN=0 \
      SLURM_ARRAY_TASK_MAX=$(( shards - 1 )) xargs -P 2 -I{} env SLURM_ARRAY_TASK_ID={} \
      bash "$root/experiments/studies/slurm-array.sh" study "$study" "$work/out" --quick
  fi
}

if slurm_env=$(bash tests/slurm/single-node.sh start "$cluster"); then
  eval "$slurm_env"
  stamp "single-node SLURM up: $(sinfo -h -o '%P %D %T %C')"
else
  [ "${LGVI_REQUIRE_SLURM:-0}" = 1 ] && { echo "sharded-study.sh: SLURM did not start (above)" >&2; exit 1; }
  echo "sharded-study.sh: SLURM did not start (above): running the shards through xargs -P instead" >&2
  unset SLURM_CONF
fi
run_array
stamp "$shards shards run"
run_array  # again: every task resumes its finished shard
stamp "$shards shards resumed"
"$exe" merge "$work/out/merged" $(seq -f "$work/out/shard-%g" 0 $(( shards - 1 )))
"$exe" study "$study" --quick --render-only --out "$work/out/merged" > /dev/null
"$exe" study "$study" --quick --out "$work/whole" > /dev/null
stamp "merged, rendered and run in one process"

python3 - "$work/out/merged" "$work/whole" <<'PY'
import csv, json, pathlib, sys
merged, whole = map(pathlib.Path, sys.argv[1:])
def timed(name): return "seconds" in name or "timing" in name or name.endswith("detail")
def untimed_csv(path):
    lines = path.read_text().splitlines()
    meta = [l for l in lines if l.startswith("#")]
    rows = list(csv.reader(l for l in lines if not l.startswith("#")))
    keep = [j for j, n in enumerate(rows[0]) if not timed(n)] if rows else []
    # the statistics' long form: one row per metric, named in the column `metric`
    metric = rows[0].index("metric") if rows and "metric" in rows[0] else None
    rows = [r for r in rows if metric is None or r is rows[0] or not timed(r[metric])]
    return meta, [[r[j] if j < len(r) else None for j in keep] for r in rows]
def untimed_jsonl(path):
    return [{k: v for k, v in json.loads(l).items() if not timed(k)} for l in path.read_text().splitlines()]
checked = ["summary.csv", "summary.jsonl"] + sorted(p.name for p in whole.glob("*-statistics.csv"))
for name in checked:
    a, b = merged / name, whole / name
    if not a.exists():
        sys.exit(f"sharded-study.sh: the merged run has no {name}")
    same = untimed_jsonl(a) == untimed_jsonl(b) if name.endswith(".jsonl") else untimed_csv(a) == untimed_csv(b)
    if not same:
        sys.exit(f"sharded-study.sh: {name} of the merged shards differs from the single-process run's (timings aside)")
rows = len(untimed_jsonl(whole / "summary.jsonl"))
print(f"sharded-study.sh: merged = single process for {', '.join(checked)} ({rows} cases)")
PY
stamp "passed"
