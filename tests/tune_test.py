#!/usr/bin/env python3
"""liftcheck tune end to end on a compiled-in configuration: ode-quick misses car.circle at its
defaults; tune must find an iteration count that passes, its answer must pass again when run with
`liftcheck run --set` (with the same figures: runs are deterministic), its reported cost must be
its own record's (the engine's time per simulated second), and --out must hold tune.json and the
plot.  Usage: tune_test.py LIFTCHECK"""
import json
import os
import subprocess
import sys
import tempfile

exe = sys.argv[1]
failures = []


def check(ok, what):
    print(("PASS " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


with tempfile.TemporaryDirectory() as tmp:
    out = os.path.join(tmp, "tune")
    p = subprocess.run([exe, "tune", "car.circle", "--engine", "ode-quick", "--budget", "30", "--jobs", "2",
                        "--out", out, "--json"], capture_output=True, text=True, timeout=900)
    check(p.returncode == 0, f"tune exits 0 when a setting passes (got {p.returncode}: {p.stderr.strip()[:300]})")
    doc = json.loads(p.stdout)
    walked = doc["walked"]
    check(len(walked) <= 30, f"{len(walked)} runs within the budget of 30")
    check(walked[0]["change"] == {} and not walked[0]["pass"], "the default run comes first and fails")
    check(doc["answer"] is not None, "an answer")
    a = walked[doc["answer"]]
    check(list(a["change"]) == ["iterations"], f"the answer changes the iteration count only: {a['change']}")
    rec = a["record"]
    check(rec["settings"].get("iterations") == a["change"]["iterations"],
          "the answer's record is the run of that setting")
    cost = 1e3 * rec["wall_s"] / rec["simulated_s"]
    check(abs(a["cost_ms_per_s"] - cost) <= 1e-9 * cost, f"its reported cost {a['cost_ms_per_s']} is its run's {cost}")
    cheaper = [s for s in walked if s["pass"] and "iterations" in s["change"] and len(s["change"]) == 1
               and int(s["change"]["iterations"]) < int(a["change"]["iterations"])]
    check(not cheaper, "no passing run with fewer iterations")
    check(os.path.isfile(os.path.join(out, "tune.json")) and os.path.getsize(os.path.join(out, "plots", "tune.svg")) > 1000,
          "--out holds tune.json and plots/tune.svg")
    r = subprocess.run([exe, "run", "car.circle", "--engine", "ode-quick", "--set", f"iterations={a['change']['iterations']}",
                        "--json"], capture_output=True, text=True, timeout=600)
    again = json.loads(r.stdout)
    check(again["status"] == "pass", f"run --set iterations={a['change']['iterations']} passes")
    check(again["worst_ratio"] == rec["worst_ratio"], f"with the same worst ratio ({again['worst_ratio']} and {rec['worst_ratio']})")
    bad = subprocess.run([exe, "tune", "car.circle", "--engine", "ode-quick", "--budget", "0"], capture_output=True, text=True)
    check(bad.returncode == 2 and bad.stderr.count("\n") == 1, "--budget 0 is one line of error and exit 2")

print(f"{len(failures)} failed")
sys.exit(1 if failures else 0)
