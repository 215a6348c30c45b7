#!/usr/bin/env bash
# Builds a small report (a parking cycle and a forced collision on every engine) and checks it.
set -u
bin="$1"
check="$2"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$bin" validate --filter 'car.cycle,car.covariance,disks.forced' --no-sweeps --out "$tmp/report" >"$tmp/log" 2>&1 || { cat "$tmp/log"; echo "0 passed, 1 failed"; exit 1; }
python3 "$check" "$tmp/report" || exit 1
# Every run has its snapshots, the cycle its strip, the collision its contact snapshot.
ls "$tmp/report/snapshots" | grep -q 'car_cycle__ode__strip.png' || { echo "FAIL no strip"; exit 1; }
ls "$tmp/report/snapshots" | grep -q 'disks_forced__bullet__contact.png' || { echo "FAIL no contact snapshot"; exit 1; }
grep -q 'id="matrix"' "$tmp/report/index.html" || { echo "FAIL no summary matrix"; exit 1; }
