#!/usr/bin/env bash
# The sanitizer job's runs beyond ctest (docs/testing.md), the last part of the test command:
# the test command configures its build (default build-test) with -DLGVI_SANITIZE=ON, so that
# every program it builds carries AddressSanitizer and UndefinedBehaviorSanitizer (clang, -O2,
# no recovery: the first report fails) and ctest has run every test program, the Python tests
# and the installed-package examples under them. This script then runs, in that build:
#  1. the CLI on every shipped scene, a baseline, a quick suite, two optimal control examples
#     with few iterations, and the hostile scene files of tests/fuzz/regressions;
#  2. bounded libFuzzer runs of the five input readers (tests/fuzz: scene files, [ocp] tables,
#     study files, control sample CSVs, the command line) from their seeds and regression inputs:
#     a fixed number of executions each from a fixed seed (FUZZ_SEED, default 1), so that a run
#     explores the same inputs in the same order each time, capped at FUZZ_SECONDS each (default
#     300); FUZZ_RUNS replaces every target's number of executions (-1: until FUZZ_SECONDS).
# A build directory not configured yet is configured so; one configured otherwise is refused.
# Usage: bash tests/sanitize.sh [BUILD_DIR]   (env: FUZZ_RUNS, FUZZ_SECONDS, FUZZ_SEED, JOBS)
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${1:-build-test}
jobs=${JOBS:-2}
fuzz_seconds=${FUZZ_SECONDS:-300}
start=$(date +%s)
stamp() { echo "sanitize.sh: $1 ($(( $(date +%s) - start )) s)"; }

if [ ! -f "$dir/CMakeCache.txt" ]; then
  cmake -S . -B "$dir" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DLGVI_SANITIZE=ON >/dev/null
elif ! grep -q '^LGVI_SANITIZE:BOOL=ON$' "$dir/CMakeCache.txt"; then
  echo "sanitize.sh: $dir is not configured with -DLGVI_SANITIZE=ON (the test command's build; another directory?)" >&2
  exit 1
fi
cmake --build "$dir" -j"$jobs" --target lgvi-testbed fuzz_scene fuzz_ocp fuzz_study fuzz_controls fuzz_cli
stamp "built"

export ASAN_OPTIONS=detect_leaks=1:halt_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
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

# The fuzz targets, $jobs at a time, each with its executions (about 25 s each here), its
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
    scene) runs=130000 max_len=4096; cp experiments/scenes/*.toml tests/fuzz/regressions/*.toml "$corpus/" ;;
    ocp) runs=130000 max_len=4096; cp experiments/scenes/ocp-*.toml "$corpus/" ;;
    study) runs=18000 max_len=6144; cp experiments/studies/*.toml "$corpus/" ;;
    controls) runs=150000 max_len=4096; cp tests/fuzz/seeds/controls/* "$corpus/" ;;
    cli) runs=9000 max_len=1024
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
