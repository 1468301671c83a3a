#!/usr/bin/env bash
# The sanitizer job of CI (docs/testing.md; run by the test command after the ordinary tests):
#  1. an AddressSanitizer + UndefinedBehaviorSanitizer build (clang, -O1, no recovery: the first
#     report fails the job) of the core, the harness (toml++ compiled in with the same flags,
#     LGVI_COMPILE_TOMLPLUSPLUS), the CLI, every test program, the Python module and the libFuzzer
#     targets, in its own build directory (default build-asan), with Ninja; the optimal control
#     solver files at -O0 (LGVI_OCP_SOLVER_COMPILE_OPTIONS: half their compile time; the job runs
#     them briefly);
#  2. every test program, each without its slow tests (listed below with what they cost): test_lgvi,
#     test_experiments, test_baselines, test_ocp, test_validation; then the Python tests with the
#     module built sanitized and the interpreter given ASan's runtime (LD_PRELOAD);
#  3. CLI runs of every shipped scene, a baseline, a quick suite, two optimal control examples
#     with few iterations, and the hostile scene files of tests/fuzz/regressions;
#  4. bounded libFuzzer runs of the five input readers (tests/fuzz: scene files, [ocp] tables,
#     study files, control sample CSVs, the command line) from their seeds and regression inputs:
#     a fixed number of executions each from a fixed seed (FUZZ_SEED, default 1), so that a run
#     explores the same inputs in the same order each time, capped at FUZZ_SECONDS each (default
#     300); FUZZ_RUNS replaces every target's number of executions (-1: until FUZZ_SECONDS).
# Usage: bash tests/sanitize.sh [BUILD_DIR]   (env: FUZZ_RUNS, FUZZ_SECONDS, FUZZ_SEED, JOBS)
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${1:-build-asan}
jobs=${JOBS:-2}
fuzz_seconds=${FUZZ_SECONDS:-300}
sanitize="-fsanitize=address,undefined -fno-sanitize-recover=all"
start=$(date +%s)
stamp() { echo "sanitize.sh: $1 ($(( $(date +%s) - start )) s)"; }

cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only -fno-omit-frame-pointer $sanitize" \
  -DCMAKE_EXE_LINKER_FLAGS="$sanitize" \
  -DLGVI_BUILD_BENCHMARKS=OFF -DLGVI_BUILD_EXAMPLES=OFF -DLGVI_BUILD_PYTHON=ON -DLGVI_INSTALL=OFF \
  -DLGVI_BUILD_FUZZERS=ON -DLGVI_COMPILE_TOMLPLUSPLUS=ON -DLGVI_OCP_SOLVER_COMPILE_OPTIONS=-O0 >/dev/null
fuzzers="fuzz_scene fuzz_ocp fuzz_study fuzz_controls fuzz_cli"
cmake --build "$dir" -j"$jobs" --target test_lgvi test_experiments test_baselines test_ocp test_validation \
  lgvi-testbed lgvi_python $fuzzers
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
# Every test of test_baselines (the continuous-time baselines: models, solvers, splittings,
# Pontryagin shooting, the baseline CLI) but its 27 slowest, 5 s or more each sanitized (bar one
# parameter of a group; 712 of its 802 s of test time): the 10^6-step energy sweeps of the splittings and RATTLE, the
# connected bodies' and the cart's agreement with gsl-rk4imp, the dumbbell's Pontryagin shooting,
# the dense output and output grid comparisons, ... Their code paths run in the other 456 tests,
# over fewer steps (90 s of test time).
baselines_slow="SplittingSymplecticity.*Over1e6Steps:DumbbellPontryagin.ShootingStopsAtTheResidualsNoiseFloor"
baselines_slow="$baselines_slow:All/MultibodyAgreementAll.ConnectedBodiesWithControl/gsl_rk4imp*"
baselines_slow="$baselines_slow:All/MultibodyAgreementAll.CartPendulumWithControl/gsl_rk4imp*"
baselines_slow="$baselines_slow:DenseOutput.TheOutputGridDoesNotChangeTheRun:CliBaselines.TheOutputGridDoesNotChangeTheRun"
baselines_slow="$baselines_slow:Pontryagin.FullJacobianIsRankDeficient:MultibodyDrift.*QuaternionNormGrows"
baselines_slow="$baselines_slow:Pontryagin.ViolationFollowsTheIntegrationTolerance:GaussLegendre.ConservesQuadraticInvariantsToItsNewtonTolerance"
baselines_slow="$baselines_slow:LieGroupGeometry.AttitudeStaysOnSO3For1e5Steps:Pontryagin.ConvergesAndAgreesWithTheDiscreteOptimum"
baselines_slow="$baselines_slow:CliBaselines.BadCombinationsAreOneLineErrors:DenseOutput.InterpolatedSamplesKeepTheSolversPromise"
baselines_slow="$baselines_slow:CliBaselines.MultibodyScenesWriteTheLgviColumnsAndMotion:DenseOutput.HermiteSamplesAreWithinALocalErrorOfTheSteps"
baselines_slow="$baselines_slow:Sensitivity.CorrectorsAndRightHandSidesAgree"
run_shards test_baselines --gtest_filter="-$baselines_slow"
# Every test of test_ocp (the optimal control solvers, their scenes and CLI) but the 12 that solve
# a problem to convergence with the solvers at -O0 (6 to 302 s each sanitized, 790 of its 812 s):
# the other 77 take the same solvers through their Jacobians, first iterations, bad input and the
# CLI (22 s), and the CLI runs below solve two examples for a few iterations.
ocp_slow="Shooting.DumbbellContinuation*:DirectSolve.ConnectedBodiesPaperExampleFromOneStart"
ocp_slow="$ocp_slow:MultipleShooting.CartPendulumExactHessianConvergesToAFeasiblePoint:DirectSolve.FiniteDifferenceGradientsAgreeOnAShortHorizon"
ocp_slow="$ocp_slow:Shooting.DumbbellConvergesByLevenbergMarquardt:MultipleShooting.ConnectedBodiesFromOneStart:Shooting.DumbbellConverges"
ocp_slow="$ocp_slow:DirectSolve.CartPendulumPaperExample:OcpCli.CartPendulumDirectWritesHistoryTrajectoryAndSummary"
ocp_slow="$ocp_slow:Shooting.PendulumConvergesWithDecomposition:OcpCli.PendulumWritesHistoryTrajectoryAndSummary"
ocp_slow="$ocp_slow:OcpScenes.FreeBodySlewConvergesWithTheShippedAndAUsersW"
run_shards test_ocp --gtest_filter="-$ocp_slow"
# Every test of test_validation (the regression gate) but the two that compute its metrics: the
# degraded rotation update's whole validate run (220 s sanitized) and a suite run twice for
# --check-against (57 s); the judging, the accepted file and the CLI's refusals run (under 1 s).
run_shards test_validation --gtest_filter="-ValidateCli.DegradedRotationUpdateRegressesAndExitsFour:SuiteCheckAgainst.*"

exe="$dir/lgvi-testbed"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The Python tests (python/tests) with the module built sanitized: the interpreter is not, so
# ASan's runtime comes first through LD_PRELOAD (clang's shared one), and leak detection is off
# (CPython keeps its interned objects and module state until exit by design: every run would
# report them). The CLI the tests compare with runs without the preload (a wrapper), as the
# sanitized lgvi-testbed carries its own static runtime. The interpreter is the one ctest runs
# the python_tests with (python/CMakeLists.txt: one with numpy and pytest).
python=$(ctest --test-dir "$dir" -R '^python_tests$' --show-only=json-v1 |
  python3 -c 'import json, sys; print(json.load(sys.stdin)["tests"][0]["command"][0])')
printf '#!/bin/sh\nunset LD_PRELOAD\nexec %q "$@"\n' "$PWD/$exe" >"$work/lgvi-testbed"
chmod +x "$work/lgvi-testbed"
LD_PRELOAD="$(clang++ -print-file-name=libclang_rt.asan-x86_64.so)" ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=0" \
  PYTHONPATH="$dir/python" LGVI_TESTBED_EXE="$work/lgvi-testbed" LGVI_SOURCE_DIR="$PWD" \
  "$python" -m pytest -q -p no:cacheprovider python/tests >"$work/pytest.log" 2>&1 || {
  tail -n 60 "$work/pytest.log" >&2
  echo "sanitize.sh: the Python tests failed" >&2
  exit 1
}
echo "python: $(tail -n 1 "$work/pytest.log")"
stamp "Python tests passed"
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

# The fuzz targets, $jobs at a time, each with its executions (about 40 s each here), its
# -max_len (the largest seed fits) and its seed corpus, copied into a directory of its own
# (libFuzzer adds the inputs it keeps to it): the shipped files of its kind and its regression
# inputs. A fixed number of executions from a fixed seed: the same inputs on every machine,
# however fast (a time limit would explore more on a fast machine than on a loaded one); the time
# limit only caps a very slow machine, which then runs a prefix of the same sequence. A finding's
# input is kept as $dir/fuzz-findings/TARGET-crash-* (docs/testing.md: make it a regression file).
fuzz_target() {
  local name=$1 runs max_len corpus="$work/corpus-$1" log="$work/fuzz-$1.log"
  mkdir -p "$corpus" "$dir/fuzz-findings"
  case $name in
    scene) runs=220000 max_len=4096; cp experiments/scenes/*.toml tests/fuzz/regressions/*.toml "$corpus/" ;;
    ocp) runs=220000 max_len=4096; cp experiments/scenes/ocp-*.toml "$corpus/" ;;
    study) runs=30000 max_len=6144; cp experiments/studies/*.toml "$corpus/" ;;
    controls) runs=250000 max_len=4096; cp tests/fuzz/seeds/controls/* "$corpus/" ;;
    cli) runs=15000 max_len=1024
      python3 tests/fuzz/cli_seeds.py "$corpus" README.md docs/*.md experiments/*/README.md >/dev/null ;;
  esac
  if [ -d "tests/fuzz/regressions/$name" ]; then cp -r "tests/fuzz/regressions/$name/." "$corpus/"; fi
  "$dir/fuzz_$name" -seed="${FUZZ_SEED:-1}" -runs="${FUZZ_RUNS:-$runs}" -max_total_time="$fuzz_seconds" \
    -max_len="$max_len" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$dir/fuzz-findings/$name-" "$corpus" >"$log" 2>&1 || {
    tail -n 60 "$log" >&2
    echo "sanitize.sh: fuzz_$name failed (its input in $dir/fuzz-findings/)" >&2
    return 1
  }
  echo "fuzz_$name: $(grep -E "^#[0-9]+" "$log" | tail -n 1 | cut -f 1,2) ($(ls "$corpus" | wc -l) inputs in the corpus)"
}
export -f fuzz_target
export dir work fuzz_seconds
printf '%s\n' scene ocp study controls cli | xargs -P "$jobs" -I '{}' bash -c 'fuzz_target {}' ||
  { echo "sanitize.sh: a fuzz target failed" >&2; exit 1; }
stamp "fuzzing passed"
