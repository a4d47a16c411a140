#!/usr/bin/env bash
# Outputs of the gear-train commands of two geardyn binaries, compared file by file (figures and
# run records aside): scripts/compare-trains.sh OLD_BINARY NEW_BINARY [DIR]
set -euo pipefail
old=$1 new=$2 dir=${3:-/tmp/compare-trains}
rm -rf "$dir"
for side in old new; do
  g=${!side}
  o="$dir/$side"
  mkdir -p "$o"
  "$g" modes --out "$o/modes-planetary" > /dev/null
  "$g" modes --preset two-stage --out "$o/modes-two-stage" > /dev/null
  "$g" simulate --preset planetary --set xi=0.1 --set omega=1.4 --out "$o/sim-planetary" > /dev/null
  "$g" simulate --preset two-stage --periods 20 --out "$o/sim-two-stage" > /dev/null
  "$g" bifurcation --preset planetary --range 0.5:1.5:8 --set xi=0.1 --out "$o/bif-planetary" > /dev/null
done
# (summary.json holds the wall time)
diff -rq "$dir/old" "$dir/new" -x '*.png' -x '*.svg' -x run.json -x summary.json || true
for f in "$dir"/old/*/summary.json; do
  diff -q <(grep -v wall_s "$f") <(grep -v wall_s "${f/old/new}") > /dev/null || echo "differs: ${f#$dir/old/}"
done
