#!/usr/bin/env bash
# Bit-identity check for refactors (issue 13): runs every method of the
# `limbfuse` binary given as $1 (default target/release/limbfuse) over seeded
# simulated trials and the shared data, and prints one sha256 per output file.
# Compare two builds with:
#   scripts/refactor-check.sh OLD_BIN > old.txt; scripts/refactor-check.sh NEW_BIN > new.txt; diff old.txt new.txt
set -euo pipefail
BIN=${1:-target/release/limbfuse}
BIN=$(realpath "$BIN")
SHARED=$(realpath "$(dirname "$0")/../../shared/data" 2>/dev/null || true)
W=$(mktemp -d)
trap 'rm -rf "$W"' EXIT
cd "$W"
q() { "$BIN" "$@" >/dev/null 2>&1; }
q simulate walking --duration 20 --seed 3 -o walk.csv
q simulate walking --duration 20 --seed 4 --speed 1.5 --mounting random -o raw.csv
q align raw.csv -o aligned.csv
q align --hinge raw.csv -o aligned-hinge.csv
q simulate knee --duration 30 --seed 3 -o knee.csv
q simulate knee-fes --subject P2-R --duration 10 -o fes.csv
q simulate fixed-hip --duration 8 -o hip.csv
for m in gyro-integration accel-inclination local mjls global chain; do
  q estimate --method $m walk.csv -o $m.csv
  q estimate --method $m aligned.csv -o al-$m.csv
  "$BIN" evaluate walk.csv $m.csv --json > ev-$m.json 2>/dev/null
  "$BIN" evaluate aligned.csv al-$m.csv --json --offset-free --max-lag 2 > ev-al-$m.json 2>/dev/null
done
q tune --method global walk.csv --window 0:8 --budget 40 --starts 3 -o global.toml
q estimate --method global --params global.toml walk.csv -o tuned-global.csv
"$BIN" evaluate walk.csv --method mjls --window 0:10 --starts 3 --json > proto-mjls.json 2>/dev/null
q estimate --method knee-selfalign --window 300 --order 4 knee.csv -o ksa.csv
q align --joint-axis knee.csv -o axes.toml
for m in sdre ekf rmx; do
  q estimate --method $m fes.csv -o fes-$m.csv
  q estimate --method $m hip.csv -o hip-$m.csv
  "$BIN" evaluate fes.csv fes-$m.csv --json > ev-fes-$m.json 2>/dev/null
done
q gait-library build --speeds 0.6:0.8:0.1 -o lib.json
q simulate bslip --speed 0.7 --library lib.json --duration 3 -o bslip.csv
q estimate --method imm-bslip --library lib.json bslip.csv -o imm.csv
q estimate --method imm-bslip --library lib.json --imm-weights recursive --imm-touchdown mixed bslip.csv -o imm2.csv
"$BIN" evaluate bslip.csv imm.csv --json > ev-imm.json 2>/dev/null || true
q resample walk.csv --rate 50 -o walk50.csv
q simulate walking --duration 20 --seed 5 --gait-reference -o gait.csv
for m in gait-events lowback-speed; do
  q estimate --method $m gait.csv -o gait-$m.csv
  "$BIN" evaluate gait.csv gait-$m.csv --json > ev-gait-$m.json 2>/dev/null
done
if [ -d "$SHARED" ]; then
  q import --format gaittoolbox "$SHARED/gaittoolbox-s02-walk" -o s02.csv
  q align s02.csv -o s02al.csv
  q estimate --method global s02al.csv -o s02-global.csv
  for f in "$SHARED"/independent-sim/walk-v1.2-s301.csv; do
    q estimate --method mjls "$f" -o ind-mjls.csv
    q estimate --method knee-selfalign "$f" -o ind-ksa.csv
    q estimate --method knee-gyro-axis "$f" -o ind-kga.csv
    q estimate --method gait-events "$f" -o ind-ge.csv
  done
  q estimate --method gait-events "$SHARED/gaitmap-foot-walk/trial.csv" -o gm-ge.csv
  "$BIN" evaluate "$SHARED/gaitmap-foot-walk/trial.csv" gm-ge.csv --json > ev-gm-ge.json 2>/dev/null
  q estimate --method lowback-speed "$SHARED/mobgap-lowerback/HA001-test11-trial1.csv" -o ha-lb.csv
  "$BIN" evaluate "$SHARED/mobgap-lowerback/HA001-test11-trial1.csv" ha-lb.csv --json > ev-ha-lb.json 2>/dev/null
fi
sha256sum -- * | sort -k2
