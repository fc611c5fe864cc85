#!/usr/bin/env bash
# Browser test of `limbfuse report` (issue 17 item 3, docs/REPORT.md).
#
# Installs Debian's chromium when it is missing (the CI machine runs as
# root), writes reports of short simulated trials (walking with five segment
# estimates, knee-FES with sdre/ekf/rmx, knee-selfalign and knee-gyro-axis, B-SLIP with
# imm-bslip, gait-events and lowback-speed on the walk), opens each in headless Chromium through the DevTools protocol
# (scripts/report_browser_check.py, Python standard library only) and fails
# on any console error, uncaught exception, network request, missing element
# or undrawn plot. With --screenshot it also writes docs/figures/report.png
# (the walking report).
#
# usage: scripts/report-browser-test.sh [--screenshot]
# env:   LIMBFUSE=path/to/limbfuse  (default: built with `cargo build --profile test`,
#        the profile `cargo test` builds the binary with, so after the Rust tests
#        nothing is recompiled)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

shot=""
if [[ "${1:-}" == "--screenshot" ]]; then shot="$root/docs/figures/report.png"; fi

chromium=$(command -v chromium || true)
if [[ -z "$chromium" ]]; then
  echo "report-browser-test: installing Debian's chromium"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
  chromium=$(command -v chromium)
fi

if [[ -z "${LIMBFUSE:-}" ]]; then
  cargo build --quiet --profile test -p limbfuse-cli --bin limbfuse
  LIMBFUSE="${CARGO_TARGET_DIR:-$root/target}/debug/limbfuse"
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
lf() { "$LIMBFUSE" "$@" >/dev/null 2>&1 || { echo "failed: limbfuse $*" >&2; "$LIMBFUSE" "$@"; exit 1; }; }

# Walking: every segment method (seed 1, 20 s). The estimates are named as
# a user names them (trial, seed, method): the legends are long enough to
# wrap, which the check requires to happen between entries, not inside one.
lf simulate walking --duration 20 --seed 1 -o walk.csv
walk_est=()
for m in gyro-integration accel-inclination local mjls global; do
  # (the paper filters started on the first sample, the start before
  # 2026-12-06: their trunk starts off, and that transient is clipped out of
  # the trunk plot's y range, clip-note-trunk; the default start has no such
  # transient)
  params=()
  if [[ $m == local || $m == mjls || $m == global ]]; then params=(--params "$root/docs/params/segment-first-sample-start.toml"); fi
  lf estimate --method "$m" "${params[@]}" walk.csv -o "walk-seed1-$m.csv"
  walk_est+=("walk-seed1-$m.csv")
done
lf report walk.csv "${walk_est[@]}" -o walk.html
walk_ids="window-controls,win-start,win-end,rmse-table,error-table,evaluate-notes,clip-note-trunk,gait-events,command-list"
for c in trunk thigh shank foot hip knee ankle; do walk_ids+=",plot-angle-$c,plot-cycle-$c"; done

# Knee-FES (paper 004): stimulation panel and the sdre/ekf uncertainty.
lf simulate knee-fes --duration 10 -o fes.csv
for m in sdre ekf rmx; do lf estimate --method "$m" fes.csv -o "fes-$m.csv"; done
# (scored with evaluate's options: the scoring note and evaluate's notes)
lf report fes.csv fes-sdre.csv fes-ekf.csv fes-rmx.csv -o fes.html --window 1: --offset-free --max-lag 2
fes_ids="plot-angle-knee,plot-angle-shank,rmse-table,scoring,evaluate-notes,panel-fes,plot-fes-stimulation,plot-fes-sd"

# Self-aligning knee (paper 002): knee-axis convergence, of knee-selfalign
# and of knee-gyro-axis (its inner knee-selfalign's axes, review 27).
lf simulate knee --duration 20 -o knee.csv
lf estimate --method knee-selfalign knee.csv -o knee-est.csv
lf estimate --method knee-gyro-axis knee.csv -o knee-gyro.csv
lf report knee.csv knee-est.csv knee-gyro.csv -o knee.html
knee_ids="plot-angle-knee,plot-cycle-knee"
for k in 0 1; do knee_ids+=",panel-knee-$k,plot-knee-axis-thigh-$k,plot-knee-axis-shank-$k,plot-knee-axis-change-$k"; done

# B-SLIP gait (paper 003): IMM weights per gait and phase.
lf gait-library build --speeds 0.6:0.8:0.1 -o lib.json
lf simulate bslip --library lib.json --speed 0.7 --duration 4 -o bslip.csv
lf estimate --method imm-bslip --library lib.json bslip.csv -o bslip-est.csv
lf report bslip.csv bslip-est.csv -o bslip.html
bslip_ids="gait-table,panel-imm-0,plot-imm-gait-0,plot-imm-phase-0,plot-imm-speed-0,plot-imm-phase-track-0"

# Gait events and walking speed (issue 19): the foot IMU and the trunk IMU of the walk.
lf estimate --method gait-events walk.csv -o walk-events.csv
lf estimate --method lowback-speed walk.csv -o walk-lowback.csv
lf report walk.csv walk-events.csv walk-lowback.csv -o events.html
events_ids="panel-events,plot-contact-right,plot-initial-contacts,plot-speed,strides-0,strides-table-0,strides-1,strides-table-1"

python3 "$root/scripts/report_browser_check.py" "$chromium" "$shot" \
  "walk.html:$walk_ids" "fes.html:$fes_ids" "knee.html:$knee_ids" "bslip.html:$bslip_ids" \
  "events.html:$events_ids"
echo "report-browser-test: OK"
