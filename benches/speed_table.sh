#!/usr/bin/env bash
# The speed table of docs/benchmarks.md ("The speed table") in one command: linkdyn against the
# hand-written floor (a DOP853 for exactly the reference four-bar's equations, an external
# program) and against SciPy's LSODA (the peer), as ratios measured in one sitting, plus the
# paper's Fig. 6a diagram. Times drift by 2× from one day to the next on shared machines; ratios
# taken minutes apart do not. Run it on an idle machine.
#
#   bash benches/speed_table.sh --floor DIR [--peer PYTHON SCRIPT] [--fig6a] [--rounds N]
#
#   --floor DIR      checkout of the floor program (a Cargo project with the binary rust_limit;
#                    its README gives the command lines used here)
#   --peer PY SCRIPT a Python with numpy and scipy, and the SciPy model of the same four-bar
#                    (fourbar.py, beside the floor); omitted: no LSODA rows
#   --fig6a          also time the Fig. 6a sweep both ways (docs/sweeps.md), about a minute
#   --rounds N       rounds of the ratio rows (default 3); each row reports the median ratio
set -euo pipefail
cd "$(dirname "$0")/.."

floor="" peer_python="" peer_script="" fig6a=0 rounds=3
while [ $# -gt 0 ]; do
  case "$1" in
    --floor) floor=$2; shift 2 ;;
    --peer) peer_python=$2; peer_script=$3; shift 3 ;;
    --fig6a) fig6a=1; shift ;;
    --rounds) rounds=$2; shift 2 ;;
    *) echo "unknown option $1 (see the header of $0)" >&2; exit 2 ;;
  esac
done
[ -n "$floor" ] || { echo "--floor DIR is required (see the header of $0)" >&2; exit 2; }

cargo build --release --quiet
cargo build --release --quiet --manifest-path "$floor/Cargo.toml" --target-dir target/floor
bin=target/release/linkdyn
limit=target/floor/release/rust_limit
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

median() { sort -g | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'; }

# Median wall_time_s of 5 linkdyn runs of farahan2016 (2 turns) with the options given.
linkdyn_time() {
  for _ in 1 2 3 4 5; do
    "$bin" run models/farahan2016.toml --revs 2 --dt 1e-3 "$@" --out "$work/r.csv" >/dev/null 2>&1
    grep -o '"wall_time_s": *[0-9.e+-]*' "$work/r.json" | cut -d: -f2
  done | median
}

# The floor's own median of 5 repetitions.
floor_time() {
  "$limit" "$@" --reps 5 | grep -o '"wall_median_s": *[0-9.e+-]*' | cut -d: -f2
}

# LSODA's in-process solve time (the script prints wall=…s), median of 3.
peer_time() {
  for _ in 1 2 3; do
    "$peer_python" "$peer_script" --rpm 250 --nrev 2 --method LSODA "$@" \
      | grep -o 'wall=[0-9.e+-]*' | cut -d= -f2
  done | median
}

tol=(--rtol 1e-9 --atol 1e-12)
declare -A ratios
for _ in $(seq "$rounds"); do
  fr=$(floor_time --variant tuned --method dop853 "${tol[@]}")
  fd=$(floor_time --dae-run "${tol[@]}")
  lr=$(linkdyn_time --formulation reduced "${tol[@]}")
  ld=$(linkdyn_time --formulation dae "${tol[@]}")
  ratios[reduced]+="$(python3 -c "print($lr / $fr)") "
  ratios[dae]+="$(python3 -c "print($ld / $fd)") "
  ratios[times]="$fr $lr $fd $ld"
done
# | what | compared with | its time | linkdyn's time | ratio text | target |
row() { python3 -c "print('| %s | %s | %.1f ms | %.1f ms | %s | %s |' % ($1))"; }
med() { tr ' ' '\n' <<<"$1" | grep . | median; }
read -r fr lr fd ld <<<"${ratios[times]}"

echo "| case | compared with | its time | linkdyn | ratio | target |"
echo "|---|---|---|---|---|---|"
row "'reduced + DOP853, rtol 1e-9', 'floor DOP853', $fr * 1e3, $lr * 1e3, '%.2f× its time (median of $rounds rounds)' % $(med "${ratios[reduced]}"), '≤ 1.5×'"
row "'DAE + DOP853, rtol 1e-9', 'floor DAE', $fd * 1e3, $ld * 1e3, '%.2f× its time (median of $rounds rounds)' % $(med "${ratios[dae]}"), '≤ 1.3×'"

if [ -n "$peer_python" ]; then
  # Equal error (≤ 1e-8 rad in both body angles over the 2 turns, against a converged run):
  # the tolerances at which each reaches it, from docs/benchmarks.md ("Radau5 against LSODA").
  pl=$(peer_time --rtol 1e-9 --atol 1e-12)
  rr=$(linkdyn_time --formulation reduced --method radau5 --rtol 1e-8 --atol 1e-11)
  rd=$(linkdyn_time --formulation dae --method radau5 --rtol 1e-8 --atol 1e-11)
  row "'reduced + Radau5, 1e-8 rad', 'LSODA, 1e-8 rad', $pl * 1e3, $rr * 1e3, '%.0f× faster' % ($pl / $rr), '≥ 100× faster'"
  row "'DAE + Radau5, 1e-8 rad', 'LSODA, 1e-8 rad', $pl * 1e3, $rd * 1e3, '%.0f× faster' % ($pl / $rd), '≥ 30× faster'"
fi

if [ "$fig6a" = 1 ]; then
  # The diagram of docs/sweeps.md: independent starts with DOP853 and 100 transient turns, and
  # the same diagram with Radau5 and transient detection (independent starts too).
  fig6a() {
    local start end
    start=$(date +%s.%N)
    "$bin" bifurcation models/farahan2016.toml --param joints.B.clearance \
      --from 0.00005 --to 0.0005 --steps 199 --revs 150 --transient 100 \
      --observe coupler.phi --set drivers.motor.speed_rpm=3500 --formulation reduced \
      --rtol 1e-6 --atol 1e-9 --threads 2 "$@" --out "$work/fig6a.csv" >/dev/null 2>&1
    end=$(date +%s.%N)
    python3 -c "print($end - $start)"
  }
  slow=$(fig6a)
  fast=$(fig6a --method radau5 --settle)
  python3 -c "print('| Fig. 6a, 200 clearances × 150 turns, 2 threads: DOP853, independent starts | – | – | %.1f s | – | ≤ 20 s |' % $slow)"
  python3 -c "print('| the same with --method radau5 --settle | – | – | %.1f s | – | ≤ 20 s |' % $fast)"
fi
