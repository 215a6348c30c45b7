#!/usr/bin/env bash
# The default suite with --jobs 1 and then --jobs N (default 2) back to back, on the same machine
# in the same minutes: the wall clock of each, the CPU they took, and the speed-up. Each writes
# its own report folder under a temporary directory (removed at the end).
#
#   tests/tools/jobs_speedup.sh [BUILD_DIR] [N]
set -euo pipefail
build=${1:-build}
jobs=${2:-2}
bin="$build/liftcheck"
[ -x "$bin" ] || { echo "jobs_speedup.sh: no $bin (make build first)" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

one() {
  local n=$1 t0 t1
  t0=$(date +%s.%N)
  /usr/bin/time -f "%U %S" -o "$tmp/cpu-$n" "$bin" validate --jobs "$n" --out "$tmp/out-$n" >"$tmp/log-$n" 2>&1 || true
  t1=$(date +%s.%N)
  python3 - "$n" "$t0" "$t1" "$tmp/cpu-$n" "$tmp/out-$n/results.json" <<'PY'
import json, sys
n, t0, t1 = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3])
user, sys_s = (float(x) for x in open(sys.argv[4]).read().split()[-2:])
c = json.load(open(sys.argv[5]))["context"]
idle = n * c["wall_s"] - c["worker_s"]
print(f"--jobs {n}: {t1 - t0:.1f} s wall ({c['wall_s']:.1f} s of runs and points, {c['worker_s']:.1f} worker seconds, "
      f"{idle:.1f} core seconds idle), {user + sys_s:.1f} s of CPU")
open(sys.argv[4] + ".wall", "w").write(f"{t1 - t0}\n")
PY
}

one 1
one "$jobs"
python3 -c "import sys; a, b = (float(open(f).read()) for f in sys.argv[1:3]); print(f'speed-up of --jobs {sys.argv[3]} over --jobs 1: {a / b:.2f}x')" \
  "$tmp/cpu-1.wall" "$tmp/cpu-$jobs.wall" "$jobs"
