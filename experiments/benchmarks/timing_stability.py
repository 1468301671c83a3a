#!/usr/bin/env python3
"""How reproducible are a suite's timings? Runs `lgvi-testbed suite SUITE --quick` N times, each
into its own temporary directory, and reports per case the spread max/min of the measured time
over the runs, then the median and the worst spread over the cases.

Usage (from the repository root; run it while the machine is otherwise quiet, e.g. under
/work/tools/locked on the shared development machine):

    python3 experiments/benchmarks/timing_stability.py [--runs 5] [--suite work-precision] [--jobs 2]
        [--binary build/lgvi-testbed] [--column integrator_seconds_min] [--per-case]

Only cases that completed in every run are compared. A column missing from the summary (an older
binary without repeated timing) falls back to `integrator_seconds`. Python 3 standard library
only. Exit status: 0, or 1 when a run of the suite fails.
"""

import argparse
import csv
import os
import statistics
import subprocess
import sys
import tempfile

DEFAULT_COLUMNS = ["integrator_seconds_min", "integrator_cpu_seconds"]
FALLBACK_COLUMN = "integrator_seconds"


def read_summary(path):
    """The rows of a summary.csv as dicts (the harness writes no quoted cells; the leading
    '# key: value' metadata lines are skipped)."""
    with open(path, newline="") as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def run_suite(binary, suite, jobs, out_dir):
    cmd = [binary, "suite", suite, "--quick", "--no-plots", "--jobs", str(jobs), "--out", out_dir]
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    # Exit status 2 means some case ended unexpectedly: its row is still there, and it is left
    # out below unless it completed in every run.
    if done.returncode not in (0, 2):
        sys.exit(f"timing_stability: {' '.join(cmd)} exited with {done.returncode}: {done.stderr.strip()}")
    return read_summary(os.path.join(out_dir, "summary.csv"))


def number(text):
    try:
        x = float(text)
    except (TypeError, ValueError):
        return None
    return x if x > 0 else None


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--runs", type=int, default=5, help="runs of the suite (default 5)")
    p.add_argument("--suite", default="work-precision", help="suite name (default work-precision)")
    p.add_argument("--jobs", type=int, default=2, help="--jobs of each run (default 2)")
    p.add_argument("--binary", default=os.path.join("build", "lgvi-testbed"), help="the lgvi-testbed executable")
    p.add_argument("--column", action="append",
                   help="summary column(s) to compare (default: integrator_seconds_min and integrator_cpu_seconds)")
    p.add_argument("--per-case", action="store_true", help="print every case's spread, not only the worst ten")
    args = p.parse_args()
    if args.runs < 2:
        p.error("--runs must be at least 2")
    binary = os.path.abspath(args.binary)
    if not os.access(binary, os.X_OK):
        p.error(f"{args.binary}: not an executable (build the lgvi-testbed target first)")

    runs = []
    for i in range(args.runs):
        with tempfile.TemporaryDirectory(prefix="timing-stability-") as out:
            runs.append(run_suite(binary, args.suite, args.jobs, out))
        print(f"run {i + 1}/{args.runs}: {len(runs[-1])} cases", file=sys.stderr)

    header = runs[0][0].keys() if runs[0] else []
    columns = args.column or [c for c in DEFAULT_COLUMNS if c in header] or [FALLBACK_COLUMN]
    for column in columns:
        if column not in header:
            sys.exit(f"timing_stability: no column '{column}' in summary.csv")
    order = [r["case"] for r in runs[0]]
    by_run = [{r["case"]: r for r in rows} for rows in runs]

    for column in columns:
        spreads = []  # (max/min, case, min, max)
        for case in order:
            rows = [run.get(case) for run in by_run]
            if any(r is None or r["status"] != "completed" for r in rows):
                continue
            values = [number(r[column]) for r in rows]
            if any(v is None for v in values):
                continue
            spreads.append((max(values) / min(values), case, min(values), max(values), values))
        if not spreads:
            print(f"{column}: no case completed with a time in every run")
            continue
        ratios = [s[0] for s in spreads]
        shown = spreads if args.per_case else sorted(spreads, reverse=True)[:10]
        print(f"\n{column}: max/min over {args.runs} runs of `suite {args.suite} --quick --jobs {args.jobs}`")
        print(f"{'max/min':>8}  {'min [s]':>10}  {'max [s]':>10}  {'each run / min':<{6 * args.runs}}  case"
              + ("" if args.per_case else "  (worst ten)"))
        for ratio, case, lo, hi, values in shown:
            each = " ".join(f"{v / lo:5.2f}" for v in values)
            print(f"{ratio:8.3f}  {lo:10.3g}  {hi:10.3g}  {each:<{6 * args.runs}}  {case}")
        within = sum(1 for r in ratios if r < 1.2)
        print(f"{column}: {len(ratios)} cases; spread max/min median {statistics.median(ratios):.3f}, "
              f"90th percentile {sorted(ratios)[int(0.9 * (len(ratios) - 1))]:.3f}, worst {max(ratios):.3f} "
              f"({max(spreads, key=lambda s: s[0])[1]}); {within} of {len(ratios)} cases below 1.2")
    return 0


if __name__ == "__main__":
    sys.exit(main())
