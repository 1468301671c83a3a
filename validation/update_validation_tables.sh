#!/usr/bin/env bash
# Regenerates the validation tables from `lgvi-testbed validate --quick` (the same report its
# --json writes): validation/validation-table.md (every metric) and the table of the
# metrics the paper reports in docs/validate.md (between the validation-table markers). Run from the source tree
# after `--accept`, with the binary given as $1 (default ./build/lgvi-testbed).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-./build/lgvi-testbed}
"$bin" validate --quick --json validation/validation-report.json --markdown validation/validation-table.md >/dev/null
part=$(awk '/<!-- all metrics -->/{exit} {print}' validation/validation-table.md)
awk -v part="$part" '
  /<!-- validation-table:begin -->/ {print; print part; skip=1; next}
  /<!-- validation-table:end -->/ {skip=0}
  !skip {print}' docs/validate.md > docs/validate.md.tmp && mv docs/validate.md.tmp docs/validate.md
echo "updated docs/validate.md and validation/validation-table.md"
