#!/usr/bin/env python3
"""Re-measures harness/expectations.json from a validate's results.json.

Every listed known failure of a configuration the results hold gets its ceilings from this run:
twice the error measured, rounded up to two significant digits (the margin the README states), and
a 'measured' text with the errors against their tolerances. The reasons are kept. A run or sweep
point that fails but is not listed is added only with a reason from --reasons (a JSON object
{"SCENARIO ENGINE": "reason", "sweep:NAME ENGINE": "reason"}); without one the tool names it and
exits 1, so that no known failure is written without a reviewed reason. A listed case that now
passes is dropped and named.

    remeasure_expectations.py RESULTS.json [--reasons FILE] [--engines a,b] [--write]
"""
import argparse
import json
import math
import sys

EXPECT = "harness/expectations.json"


def ceil2(x):
    """2x, rounded up to two significant digits."""
    v = 2.0 * x
    if v <= 0 or not math.isfinite(v):
        return v
    e = math.floor(math.log10(v)) - 1
    c = math.ceil(v / 10 ** e - 1e-9) * 10 ** e
    return float(f"{c:.2g}")


def run_failures(run):
    out = {}
    for name, m in run["metrics"].items():
        if m.get("pass", True) or m.get("informational"):
            continue
        err = m["rel_error"] if m.get("tolerance_kind") == "rel" else m["abs_error"]
        out[name] = (err if err is not None else math.inf, m.get("tolerance"), m.get("tolerance_kind"))
    return out


def measured_text(fails):
    parts = []
    for name, (err, tol, kind) in sorted(fails.items()):
        parts.append(f"{name} {'relative ' if kind == 'rel' else ''}error {err:.3g} (tolerance {tol:.3g})")
    return "validate at the defaults: " + "; ".join(parts)


def points_text(points, total=None):
    """'N of M points fail; worst NAME v, ...' over the failing points' errors (M: total, or len(points))."""
    worst = {}
    for p in points:
        for n, v in p["errors"].items():
            worst[n] = max(worst.get(n, 0.0), v)
    failing = sum(1 for p in points if p["status"] == "fail" and p["errors"])
    return f"{failing} of {total or len(points)} points fail; worst " + ", ".join(f"{n} {v:.2g}" for n, v in sorted(worst.items()))


def key_of(entry):
    return (entry["scenario"], entry["engines"][0], json.dumps(entry.get("params", {}), sort_keys=True))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("results")
    ap.add_argument("--reasons", default=None)
    ap.add_argument("--engines", default=None, help="only these configurations (default: every one the results hold)")
    ap.add_argument("--only", choices=["runs", "sweeps"], default=None, help="re-measure only the runs or only the sweep points")
    ap.add_argument("--sweep", default=None, help="re-measure only this sweep's points")
    ap.add_argument("--write", action="store_true")
    a = ap.parse_args()
    res = json.load(open(a.results))
    exp = json.load(open(EXPECT))
    reasons = json.load(open(a.reasons)) if a.reasons else {}
    engines = set(a.engines.split(",")) if a.engines else {r["engine"] for r in res["runs"]}
    missing, dropped = [], []

    # Runs at the defaults (entries with "params" are runs of other suites: kept as they are).
    runs = {(r["scenario"], r["engine"]): r for r in res["runs"]}
    new_runs = []
    listed = set()
    for e in exp["runs"]:
        eng = e["engines"][0]
        if eng not in engines or e.get("params") or a.only == "sweeps":
            new_runs.append(e)
            continue
        r = runs.get((e["scenario"], eng))
        if r is None:
            new_runs.append(e)
            continue
        listed.add((e["scenario"], eng))
        if f"{e['scenario']} {eng}" in reasons:
            e["reason"] = reasons[f"{e['scenario']} {eng}"]
        if "error" in e:
            if r["status"] != "error":
                dropped.append(f"{e['scenario']} on {eng}: no longer an error")
                continue
            e["measured"] = "validate at the defaults: " + r["message"]
            new_runs.append(e)
            continue
        fails = run_failures(r)
        if not fails:
            dropped.append(f"{e['scenario']} on {eng}: passes now")
            continue
        e["metrics"] = {n: ceil2(v[0]) for n, v in sorted(fails.items())}
        e["measured"] = measured_text(fails)
        new_runs.append(e)
    for (scen, eng), r in sorted(runs.items()):
        if eng not in engines or (scen, eng) in listed or r["status"] not in ("fail", "error") or a.only == "sweeps":
            continue
        fails = run_failures(r)
        reason = reasons.get(f"{scen} {eng}")
        if not reason:
            missing.append(f"{scen} {eng}: {r['status']} {', '.join(sorted(fails))}")
            continue
        if r["status"] == "error":  # a run the engine cannot finish: listed by the start of its message
            new_runs.append({"scenario": scen, "engines": [eng], "error": r["message"].split(" (")[0],
                             "reason": reason, "measured": "validate at the defaults: " + r["message"]})
            continue
        new_runs.append({"scenario": scen, "engines": [eng], "metrics": {n: ceil2(v[0]) for n, v in sorted(fails.items())},
                         "reason": reason, "measured": measured_text(fails)})
    exp["runs"] = new_runs

    # Sweep points.
    sweeps = {(s["name"], e["engine"]): e for s in res["sweeps"] if s.get("kind") != "outcomes" and s["name"] != "disk_outcomes" for e in s["engines"]}
    new_sp, listed_sp = [], set()
    # A sweep may be listed for one configuration in more than one entry (each with its own reason and
    # points): each keeps the points it lists; a failing point no entry lists goes to the first.
    claimed = {}
    for e in exp["sweep_points"]:
        if "points" in e:
            claimed.setdefault((e["sweep"], e["engines"][0]), set()).update(p["x"] for p in e["points"])
    for e in exp["sweep_points"]:
        eng = e["engines"][0]
        if eng not in engines or e["sweep"] == "disk_outcomes" or (e["sweep"], eng) not in sweeps or a.only == "runs" or (a.sweep and e["sweep"] != a.sweep):
            new_sp.append(e)
            continue
        first = (e["sweep"], eng) not in listed_sp
        listed_sp.add((e["sweep"], eng))
        if "points" not in e:  # a gate-level listing (the grip limit's slide): kept as written
            new_sp.append(e)
            continue
        own = {p["x"] for p in e["points"]}
        mine = [p for p in sweeps[(e["sweep"], eng)]["points"]
                if p["status"] == "fail" and p["errors"] and (p["x"] in own or (first and p["x"] not in claimed[(e["sweep"], eng)]))]
        pts = [{"x": p["x"], "metrics": {n: ceil2(v) for n, v in sorted(p["errors"].items())}} for p in mine]
        if not pts:
            dropped.append(f"sweep {e['sweep']} on {eng}: every point passes now")
            continue
        if pts == e["points"]:  # the same figures: the reviewed text stays
            new_sp.append(e)
            continue
        e["points"] = pts
        e["measured"] = points_text(mine, len(sweeps[(e["sweep"], eng)]["points"]))
        new_sp.append(e)
    for (name, eng), s in sorted(sweeps.items()):
        if eng not in engines or (name, eng) in listed_sp or a.only == "runs" or (a.sweep and name != a.sweep):
            continue
        pts = [{"x": p["x"], "metrics": {n: ceil2(v) for n, v in sorted(p["errors"].items())}} for p in s["points"] if p["status"] == "fail" and p["errors"]]
        if not pts:
            continue
        reason = reasons.get(f"sweep:{name} {eng}")
        if not reason:
            missing.append(f"sweep:{name} {eng}: {len(pts)} points")
            continue
        new_sp.append({"sweep": name, "engines": [eng], "points": pts, "reason": reason, "measured": points_text(s["points"])})
    exp["sweep_points"] = new_sp

    for d in dropped:
        print("dropped:", d)
    for m in missing:
        print("no reason:", m)
    if a.write:
        with open(EXPECT, "w") as f:
            json.dump(exp, f, indent=2, ensure_ascii=False)
            f.write("\n")
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main())
