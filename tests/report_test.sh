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
# The first screen read in the browser: the matrix fits 1366 px with every configuration, and a
# matrix made too wide on purpose fails the same check (when Chromium is there to read it).
layout="${3:-}"
if [ -n "$layout" ] && command -v chromium >/dev/null; then
  python3 "$layout" "$tmp/report" "$tmp/shot.png" >"$tmp/layout" || { cat "$tmp/layout"; echo "FAIL layout"; exit 1; }
  python3 "$layout" "$tmp/report" "$tmp/shot2.png" --inject-css 'table.matrix td{min-width:500px}' >"$tmp/layout2" \
    && { cat "$tmp/layout2"; echo "FAIL a matrix wider than the window passed the layout check"; exit 1; }
  grep -q "^FAIL matrix .* px wide" "$tmp/layout2" || { cat "$tmp/layout2"; echo "FAIL the wide matrix was not named"; exit 1; }
  # Every failure painted one colour whatever its multiple fails the colour scale's check.
  python3 "$layout" "$tmp/report" "$tmp/shot3.png" --inject-css 'table.matrix td.c{background:#fc8 !important}' >"$tmp/layout3" \
    && { cat "$tmp/layout3"; echo "FAIL a matrix of one colour passed the layout check"; exit 1; }
  grep -q "look alike" "$tmp/layout3" || { cat "$tmp/layout3"; echo "FAIL one colour for every multiple was not named"; exit 1; }
fi
# A run that fails on purpose (3 solver iterations) names its failing metric with its figure in
# its cell, in "not as expected" at the top and on its scenario page, with the setting applied.
"$bin" validate --engines ode-quick --filter car.circle --no-sweeps --set iterations=3 --out "$tmp/fail" >"$tmp/log" 2>&1
[ $? -eq 1 ] || { cat "$tmp/log"; echo "FAIL iterations=3 did not fail"; exit 1; }
python3 - "$tmp/fail" <<'PY' || exit 1
import html, json, re, sys
d = sys.argv[1]
r = json.load(open(d + "/results.json"))["runs"][0]
failing = sorted((m["rel_error" if m["tolerance_kind"] == "rel" else "abs_error"] / m["tolerance"], k)
                 for k, m in r["metrics"].items() if not m["pass"] and not m.get("informational"))
assert r["verdict"] == "fail" and failing, r["verdict"]
worst = failing[-1][1]
index = open(d + "/index.html").read()
cell = re.search(r'<td class="c fail[^"]*"[^>]*>.*?</td>', index, re.S).group(0)
assert worst in cell, ("the cell does not name", worst, cell)
# its figure: the failing metric's error as a multiple of its tolerance, as results.json has it
shown = re.search(re.escape(worst) + r"\s*([0-9.]+(?:e[+-]?[0-9]+)?)\s*×\s*tol", html.unescape(re.sub(r"<[^>]+>", " ", cell)))
assert shown and abs(float(shown.group(1)) / failing[-1][0] - 1) < 0.06, ("the cell's figure is not the metric's", failing[-1][0], cell)
top = index[:index.index('id="map"')] if 'id="map"' in index else index
section = top[top.index('id="unexpected"'):]
assert worst + ": measured" in section and "iterations=3" in section, "not as expected lacks the metric or the setting"
measured = re.search(re.escape(worst) + r": measured\s*([-0-9.]+(?:e[+-]?[0-9]+)?)", re.sub(r"<[^>]+>", " ", section))
assert measured and abs(float(measured.group(1)) - r["metrics"][worst]["measured"]) <= 1e-3 * abs(r["metrics"][worst]["measured"]), \
    ("not as expected does not give the measured figure", r["metrics"][worst]["measured"])
page = open(d + "/scenario-car_circle.html").read()
assert "iterations=3" in page and worst in page and "FAIL" in page, "the scenario page lacks the setting or the metric"
print("PASS failing run named:", worst)
PY
