#!/usr/bin/env python3
"""liftcheck tune end to end on a compiled-in configuration: ode-quick misses car.circle at its
defaults; tune must find an iteration count that passes, its answer must pass again when run with
`liftcheck run --set` (with the same figures: runs are deterministic), its model cost must be one plus
its iteration count over the default's (no clock is asserted: the machine may be busy), no run may change a
scenario parameter but dt, a second search must give the same walk and answer, and --out must hold
tune.json and the plot.  Usage: tune_test.py LIFTCHECK"""
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
    defaults = walked[0]["record"]["params"]
    changed = sorted({k for s in walked for k, v in s["record"]["params"].items() if defaults.get(k) != v})
    check(set(changed) <= {"dt"}, f"no run changes a scenario parameter but dt (changed: {changed})")
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
    own = 1e3 * rec.get("engine_s", rec["wall_s"]) / rec["simulated_s"]
    check(abs(a["cost_ms_per_s"] - own) <= 1e-9 * own, f"its reported cost {a['cost_ms_per_s']:.6g} ms/s is its record's {own:.6g}")
    check(again["simulated_s"] == rec["simulated_s"], "the re-run simulates the same seconds")
    # The cost that ranks the passes is the model, (1 + iterations) over the default's, not a clock.
    it0 = int(walked[0]["record"]["settings"]["iterations"])
    model = (1 + int(a["change"]["iterations"])) / (1 + it0)
    check(abs(a["model_cost"] - model) <= 1e-12 * model,
          f"its model cost {a['model_cost']} is (1 + its iterations) over (1 + the default's {it0})")
    p2 = subprocess.run([exe, "tune", "car.circle", "--engine", "ode-quick", "--budget", "30", "--jobs", "2", "--json"],
                        capture_output=True, text=True, timeout=900)
    doc2 = json.loads(p2.stdout)
    same = [(s["change"], s["pass"]) for s in doc2["walked"]] == [(s["change"], s["pass"]) for s in walked]
    check(same and doc2["answer"] == doc["answer"], "a second search makes the same runs with the same verdicts and answer")
    for args, what in [(["car.circle", "--engine", "ode-quick", "--budget", "0"], "--budget 0"),
                       (["car.circle", "--engine", "analytic"], "the reference"),
                       (["car.coulomb", "--engine", "ode", "--set-nothing"], "an unknown option")]:
        bad = subprocess.run([exe, "tune"] + args, capture_output=True, text=True, timeout=120)
        check(bad.returncode == 2 and bad.stderr.count("\n") == 1, f"{what}: one line of error and exit 2 ({bad.stderr.strip()})")
    # A default run that errors (here: out of CPU time) stops the search: no other setting can be judged
    # against tolerances it never had, so no longer step "passes" on its own looser ones.
    p3 = subprocess.run([exe, "tune", "car.circle", "--engine", "ode", "--timeout", "0.01", "--json"],
                        capture_output=True, text=True, timeout=300)
    doc3 = json.loads(p3.stdout)
    check(p3.returncode == 1 and doc3["stopped"] == "error" and len(doc3["walked"]) == 1 and doc3["answer"] is None,
          f"a default run that errors stops the search (exit {p3.returncode}, {len(doc3['walked'])} runs)")

print(f"{len(failures)} failed")
sys.exit(1 if failures else 0)
