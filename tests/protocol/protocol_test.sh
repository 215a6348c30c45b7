#!/bin/sh
# The engine protocol end to end (docs/protocol.md), with liftcheck's own engine on the other side
# and with adapters that lie:
#  1. `ode` served over the protocol (`liftcheck serve ode`, registered from a temporary folder as
#     `ode-protocol`) gives the same records as `ode` compiled in, on every car and disk scenario
#     of the default catalogue (check_records.py: field by field, the configuration's name, its
#     expectations and the timings aside);
#  2. each lying adapter (tests/protocol/fake_adapter.py) gives error records with a one-line
#     reason naming what went wrong, and the suite goes on (ode's runs beside them pass).
set -eu
LIFTCHECK=$1
HERE=$(cd "$(dirname "$0")" && pwd)
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

mkdir "$TMP/reg"
python3 - "$LIFTCHECK" "$TMP/reg/ode-protocol.json" <<'PY'
import json, os, sys
json.dump({"name": "ode-protocol", "command": [os.path.abspath(sys.argv[1]), "serve", "ode"],
           "description": "ode served over the engine protocol by liftcheck serve", "color": "#aec7e8"}, open(sys.argv[2], "w"))
PY

# The registration is listed without starting it; `engines` reads its hello.
"$LIFTCHECK" --engine-dir "$TMP/reg" list | grep -q "ode-protocol"
"$LIFTCHECK" engines --engine-dir "$TMP/reg" | grep -q "^ode-protocol  \[ODE "
# Its knobs are validated like a compiled-in configuration's.
if "$LIFTCHECK" run car.circle --engine ode-protocol --engine-dir "$TMP/reg" --set iterations=5 2>"$TMP/err"; then exit 1; else test $? -eq 2; fi
grep -q "has no setting 'iterations'" "$TMP/err"
if "$LIFTCHECK" run car.circle --engine ode-protocol --engine-dir "$TMP/reg" --set wheel=square 2>"$TMP/err"; then exit 1; else test $? -eq 2; fi
test "$(wc -l < "$TMP/err")" -eq 1

# A registration whose command cannot start is reported, not a crash: `engines` says why, its
# runs are error records (exit 1).
printf '{"name": "no-node", "command": ["no-such-command-for-liftcheck", "x.mjs"], "description": "missing", "color": "#000000"}\n' > "$TMP/reg/no-node.json"
"$LIFTCHECK" engines --engine-dir "$TMP/reg" | grep -A2 "^no-node  \[unavailable" | grep -q "cannot start 'no-such-command-for-liftcheck'"
if "$LIFTCHECK" run car.circle --engine no-node --engine-dir "$TMP/reg" >"$TMP/out"; then exit 1; else test $? -eq 1; fi
grep -q "error (engine 'no-node': cannot start" "$TMP/out"
rm "$TMP/reg/no-node.json"
# A malformed registration is bad input: one line, exit 2.
mkdir "$TMP/bad" && printf '{"name": "Bad Name", "command": []}\n' > "$TMP/bad/bad.json"
if "$LIFTCHECK" list --engine-dir "$TMP/bad" >/dev/null 2>"$TMP/err"; then exit 1; else test $? -eq 2; fi
test "$(wc -l < "$TMP/err")" -eq 1 && grep -q "bad.json" "$TMP/err"
printf '{"name": "bad", "command": ["x"], "color": "#000000", "points": "some"}\n' > "$TMP/bad/bad.json"
if "$LIFTCHECK" list --engine-dir "$TMP/bad" >/dev/null 2>"$TMP/err"; then exit 1; else test $? -eq 2; fi
grep -q "'points' must be \"all\", \"map\" or \"runs\"" "$TMP/err"

# "points": "map": the configuration's runs and map points, no sweep or outcome points; "runs": its
# runs only, its default run its one point of the map (all of them with --all-points).
mkdir "$TMP/map"
python3 - "$LIFTCHECK" "$TMP/map" <<'PY'
import json, os, sys
for points in ["map", "runs"]:
    json.dump({"name": f"ode-{points}", "command": [os.path.abspath(sys.argv[1]), "serve", "ode"], "color": "#aec7e8", "points": points},
              open(f"{sys.argv[2]}/ode-{points}.json", "w"))
PY
for all in "" --all-points; do
  status=0
  "$LIFTCHECK" validate --engine-dir "$TMP/map" --engines ode,ode-map,ode-runs --filter 'car.circle,car.cycle' $all --no-report --out "$TMP/map-out" >"$TMP/map.log" || status=$?
  test "$status" -le 1 || { cat "$TMP/map.log"; exit 1; }
  python3 - "$TMP/map-out/results.json" "$all" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
swept = {e["engine"] for s in r["sweeps"] for e in s["engines"]}
curves = {c["engine"]: c["points"] for p in r["maps"][0]["panels"] for c in p["curves"]}
parts = {e: r["simulated"]["by_configuration"][e]["by_part"] for e in ["ode-map", "ode-runs"]}
assert "ode" in swept and "ode-map" in curves and "ode-runs" in curves, (swept, list(curves))
if sys.argv[2]:
    for e in ["ode-map", "ode-runs"]:
        assert e in swept and any(k.startswith("sweep/") for k in parts[e]) and len(curves[e]) > 1, (e, swept, parts[e])
else:
    assert "ode-map" not in swept and sorted(parts["ode-map"]) == ["map/speed_accuracy", "runs"], (swept, parts)
    assert "ode-runs" not in swept and sorted(parts["ode-runs"]) == ["runs"], (swept, parts)
    # Its one point is its default run: the run's own cost and error, nothing stepped for it.
    assert [p["knob"] for p in curves["ode-runs"]] == ["default"] and curves["ode-runs"][0]["error"] is not None, curves["ode-runs"]
PY
done

# 1. The same records.
status=0
"$LIFTCHECK" validate --engine-dir "$TMP/reg" --engines ode,ode-protocol --no-sweeps --no-report --out "$TMP/same" >"$TMP/same.log" || status=$?
test "$status" -le 1 || { cat "$TMP/same.log"; exit 1; }
python3 "$HERE/check_records.py" same "$TMP/same/results.json" ode ode-protocol

# MuJoCo builds its motors' limits into its model: served, it must build with the request's
# limits (the brake's among them), so the braked slide and the locked slide match the compiled-in runs.
mkdir "$TMP/mjreg"
python3 - "$LIFTCHECK" "$TMP/mjreg/mujoco-protocol.json" <<'PY'
import json, os, sys
json.dump({"name": "mujoco-protocol", "command": [os.path.abspath(sys.argv[1]), "serve", "mujoco"],
           "description": "mujoco served over the engine protocol by liftcheck serve", "color": "#aec7e8"}, open(sys.argv[2], "w"))
PY
status=0
"$LIFTCHECK" validate --engine-dir "$TMP/mjreg" --engines mujoco,mujoco-protocol --filter 'car.coulomb,car.yawed-slide' \
  --no-sweeps --no-report --out "$TMP/mj" >"$TMP/mj.log" || status=$?
test "$status" -le 1 || { cat "$TMP/mj.log"; exit 1; }
python3 - "$TMP/mj/results.json" <<'PY'
import json, sys
runs = {(r["scenario"], r["engine"]): r for r in json.load(open(sys.argv[1]))["runs"]}
for s in ("car.coulomb", "car.yawed-slide"):
    a, b = runs[(s, "mujoco")]["metrics"], runs[(s, "mujoco-protocol")]["metrics"]
    for k in ("slide_accel", "slide_accel_across", "heading_change", "brake_hold"):
        if k in a:
            assert a[k]["measured"] == b[k]["measured"], f"{s} {k}: compiled-in {a[k]['measured']} served {b[k]['measured']}"
print("mujoco served: the same slides")
PY

# 2. Adapters that lie: error records, one line each, and the suite goes on. Each is registered
# with the Python running this test (no wrapper script to start on a loaded machine).
mkdir "$TMP/fakes"
python3 - "$HERE/fake_adapter.py" "$TMP/fakes" <<'PY'
import json, sys
for mode in ["version", "malformed", "nan", "missing", "die", "hang", "flood", "badrole", "nullforce", "chassisgone", "badservo"]:
    json.dump({"name": f"fake-{mode}", "command": [sys.executable, sys.argv[1], mode],
               "description": f"an adapter that lies ({mode})", "color": "#7f7f7f"}, open(f"{sys.argv[2]}/fake-{mode}.json", "w"))
PY
status=0
"$LIFTCHECK" validate --engine-dir "$TMP/fakes" --engines ode,fake-version,fake-malformed,fake-nan,fake-missing,fake-die,fake-hang,fake-flood,fake-badrole,fake-nullforce,fake-chassisgone,fake-badservo \
  --filter 'car.circle,disks.linear' --no-sweeps --no-report --timeout 20 --jobs 2 --out "$TMP/lies" >"$TMP/lies.log" || status=$?
test "$status" -eq 1 || { cat "$TMP/lies.log"; exit 1; }
python3 "$HERE/check_records.py" lies "$TMP/lies/results.json"
# The tricycle's steps planned in runs ("steps", the adapter applying liftcheck's servo law) and
# stepped one request at a time (LIFTCHECK_SERVO_STEPS=0): the same records, number for number.
for planned in 1 0; do
  status=0
  LIFTCHECK_SERVO_STEPS=$planned "$LIFTCHECK" validate --engines cannon --filter 'car.circle,car.slope,car.coulomb' \
    --no-sweeps --no-report --out "$TMP/planned-$planned" >"$TMP/planned.log" || status=$?
  test "$status" -le 1 || { cat "$TMP/planned.log"; exit 1; }
done
python3 "$HERE/../tools/same_records.py" "$TMP/planned-1/results.json" "$TMP/planned-0/results.json"
python3 - "$TMP/planned-1/results.json" <<'PY'
import json, sys
runs = json.load(open(sys.argv[1]))["runs"]
assert len(runs) == 3 and all(r["status"] != "error" and r.get("engine_s", 0) > 0 for r in runs), [(r["scenario"], r["status"], r["message"]) for r in runs]
PY
echo "protocol: ok"
