#!/usr/bin/env bash
# The sanitizer job of CI (docs/testing.md; run by the test command after the ordinary tests):
#  1. an AddressSanitizer + UndefinedBehaviorSanitizer build (clang, -O1, no recovery: the first
#     report fails the job) of the core, the harness (toml++ compiled in with the same flags,
#     LGVI_COMPILE_TOMLPLUSPLUS), the CLI, test_lgvi and test_experiments, in
#     its own build directory (default build-asan), with Ninja; the three optimal control solver
#     files at -O0 (LGVI_OCP_SOLVER_COMPILE_OPTIONS: half their compile time; the job runs them
#     briefly);
#  2. test_lgvi but its four long sweeps, test_experiments but its quick shooting and soak
#     suites, and CLI runs of every shipped scene, a baseline, a quick suite, two optimal control
#     examples with few iterations, and the hostile scene files of tests/fuzz/regressions;
#  3. a bounded libFuzzer run of the scene parser (tests/fuzz/fuzz_scene.cpp) from the shipped
#     scenes and the regression inputs: FUZZ_RUNS executions (default 500000, ~50 s here) from a
#     fixed seed (FUZZ_SEED, default 1), so that a run explores the same inputs in the same order
#     each time, capped at FUZZ_SECONDS (default 300).
# Usage: bash tests/sanitize.sh [BUILD_DIR]   (env: FUZZ_RUNS, FUZZ_SECONDS, FUZZ_SEED, JOBS)
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${1:-build-asan}
jobs=${JOBS:-2}
fuzz_runs=${FUZZ_RUNS:-500000}
fuzz_seconds=${FUZZ_SECONDS:-300}
sanitize="-fsanitize=address,undefined -fno-sanitize-recover=all"
start=$(date +%s)
stamp() { echo "sanitize.sh: $1 ($(( $(date +%s) - start )) s)"; }

cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only -fno-omit-frame-pointer $sanitize" \
  -DCMAKE_EXE_LINKER_FLAGS="$sanitize" \
  -DLGVI_BUILD_BENCHMARKS=OFF -DLGVI_BUILD_EXAMPLES=OFF -DLGVI_BUILD_PYTHON=OFF -DLGVI_INSTALL=OFF \
  -DLGVI_BUILD_FUZZERS=ON -DLGVI_COMPILE_TOMLPLUSPLUS=ON -DLGVI_OCP_SOLVER_COMPILE_OPTIONS=-O0 >/dev/null
cmake --build "$dir" -j"$jobs" --target test_lgvi test_experiments lgvi-testbed fuzz_scene
stamp "built"

export ASAN_OPTIONS=detect_leaks=1:halt_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# Every test of test_lgvi but the four long sweeps (10^5-10^6 steps of the free body's and the
# pendulum's step, ~65% of the suite's time; ~7 minutes of the sanitized run): their code paths
# are the same steps the other tests take, over fewer steps (the dumbbell's, cart's and connected
# bodies' agreement tests, the order, momentum and reversibility tests).
long_sweeps="FastLgviStep.FreeBodyAgreesWithTheReferenceOver1e5Steps:FastLgviStep.PendulumAgreesWithTheReference"
long_sweeps="$long_sweeps:LgviStructure.PendulumMillionStepsUncontrolled:LgviStructure.PendulumMillionStepsWithSymmetricControl"
# A test program in $jobs shards side by side (GoogleTest's sharding: each test runs in exactly
# one shard); the job fails with the first failed shard.
run_shards() {
  local program=$1
  shift
  local pids=() shard pid
  for ((shard = 0; shard < jobs; ++shard)); do
    GTEST_TOTAL_SHARDS=$jobs GTEST_SHARD_INDEX=$shard "$dir/tests/$program" --gtest_brief=1 "$@" &
    pids+=($!)
  done
  for pid in "${pids[@]}"; do
    wait "$pid" || { echo "sanitize.sh: a $program shard failed" >&2; exit 1; }
  done
  stamp "$program passed"
}
run_shards test_lgvi --gtest_filter="-$long_sweeps"
# Every test of test_experiments (the harness: scenes, studies, suites, resumed and merged runs,
# the output writers, the CLI) but two end-to-end suites: the quick shooting suite solves the
# optimal control examples by continuation with the solvers at -O0 (more than 7 minutes
# sanitized; the ocp CLI runs below take the same solvers through a few iterations), and the
# quick soak suite steps every system 10^5 times (70 s sanitized, one shard's critical path; the
# other suites' tests run the same steps, fewer of them). The rest: ~130 s of test time.
run_shards test_experiments --gtest_filter="-OcpSuiteEndToEnd.QuickShooting*:SuiteEndToEnd.QuickSoak*"

exe="$dir/lgvi-testbed"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Every shipped scene for 20 steps, $jobs at a time (xargs fails when a run fails).
run_scene() {
  "$exe" simulate "$1" --t-final "$(awk -F'= *' '/^h *=/{printf "%.17g", 20*$2; exit}' "$1")" \
    --out "$work/$(basename "$1" .toml).csv" >/dev/null
}
export -f run_scene
export exe work
printf '%s\0' experiments/scenes/*.toml | xargs -0 -n 1 -P "$jobs" bash -c 'run_scene "$1"' run_scene
"$exe" simulate pendulum --t-final 0.5 --method cvode-bdf --model quaternion --out "$work/bdf.csv" >/dev/null
"$exe" suite energy-drift --quick --no-plots --out "$work/suite" >/dev/null
"$exe" ocp pendulum --max-iterations 2 --out "$work/ocp-pendulum" >/dev/null || [ $? -eq 2 ]
"$exe" ocp cart-pendulum --max-iterations 5 --out "$work/ocp-cart" >/dev/null || [ $? -eq 2 ]
# Hostile scene files: each must end with one error line (exit 1) or a named stop (exit 2). The
# dotted key of 100,000 parts (a stack overflow in toml++ before the structure scan) is made here.
{ printf 'system = "free-body"\na'; for _ in $(seq 1000); do printf '.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a.a'; done; printf ' = 1\n'; } >"$work/dotted-key-100000-parts.toml"
for bad in tests/fuzz/regressions/*.toml "$work/dotted-key-100000-parts.toml"; do
  status=0
  "$exe" simulate "$bad" --out "$work/bad.csv" >/dev/null 2>"$work/err" || status=$?
  if [ "$status" -ne 1 ] && [ "$status" -ne 2 ]; then
    echo "sanitize.sh: $bad: exit $status" >&2; cat "$work/err" >&2; exit 1
  fi
  [ "$(wc -l <"$work/err")" -eq 1 ] || { echo "sanitize.sh: $bad: not one error line" >&2; cat "$work/err" >&2; exit 1; }
done
stamp "CLI runs passed"

corpus="$work/corpus"
mkdir -p "$corpus"
cp experiments/scenes/*.toml tests/fuzz/regressions/* "$corpus/"
# A fixed number of executions from a fixed seed: the same inputs on every machine, however
# fast (a time limit would explore more on a fast machine than on a loaded one); the time limit
# only caps a very slow machine, which then runs a prefix of the same sequence.
"$dir/fuzz_scene" -seed="${FUZZ_SEED:-1}" -runs="$fuzz_runs" -max_total_time="$fuzz_seconds" -max_len=4096 \
  -timeout=10 -rss_limit_mb=2048 \
  -print_final_stats=1 "$corpus" 2>"$work/fuzz.log" || { tail -n 60 "$work/fuzz.log" >&2; exit 1; }
grep -E "stat::number_of_executed_units|Done" "$work/fuzz.log" || true
stamp "fuzzing passed"
