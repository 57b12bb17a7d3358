#!/usr/bin/env bash
# Instruction counts of the reference runs and the share of the impact log's peak search, as a
# Markdown table (docs/benchmarks.md, "The impact log's true peaks"). Counts, unlike times, do
# not depend on the machine's load. Needs valgrind (callgrind_annotate comes with it).
#
#   bash benches/instructions.sh [path/to/linkdyn]      (default: target/release/linkdyn)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-target/release/linkdyn}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "| formulation, method, speed | run (M instructions) | peak search (M) | share |"
echo "|---|---|---|---|"
for rpm in 250 3500; do
  for method in dop853 radau5; do
    for formulation in reduced dae; do
      out="$work/cg.out"
      valgrind --tool=callgrind --callgrind-out-file="$out" "$bin" run models/farahan2016.toml \
        --formulation "$formulation" --method "$method" --revs 2 --dt 1e-3 \
        --set "drivers.motor.speed_rpm=$rpm" --out "$work/r.csv" >/dev/null 2>&1
      annotated=$(callgrind_annotate --inclusive=yes "$out" 2>/dev/null)
      # The whole simulation, and the sink's step hook (the peak search) under it; with the
      # hook inlined into its caller, its calls are listed as "=> ...::on_step".
      run=$(grep -m1 'Simulation::run \[' <<<"$annotated" | awk '{gsub(",","",$1); print $1}')
      hook=$(grep -m1 -E 'Sink<F>>::on_step( \[|.*\([0-9,]+x\))' <<<"$annotated" \
        | awk '{gsub(",","",$1); print $1}')
      python3 -c "print('| %s, %s, %s rpm | %.1f | %.1f | %.1f %% |' % ('$formulation', '$method', '$rpm', $run / 1e6, ${hook:-0} / 1e6, 100 * ${hook:-0} / $run))"
    done
  done
done
