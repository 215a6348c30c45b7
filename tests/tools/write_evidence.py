#!/usr/bin/env python3
"""Measures the experiments behind known-failure reasons and writes them into harness/expectations.json.

A reason that names a cause is a claim; its evidence is an experiment: the listed run, and the same
run with one change (a setting or a scenario parameter, as --set takes it), which moves a failing
figure (a listed run that ends in an error: the change lets it finish, "from": "error"). The plan lists the experiments to make:

    [{"scenario": "car.circle", "engine": "jolt", "change": {"velocity_steps": "100"}, "metric": "front_radius"},
     {"sweep": "error_vs_dt", "engine": "ode", "x": 0.01, "change": {"speed": "1"}, "metric": "heading_residual"}, ...]

(a run listing with "params" names them too, as the listing does). Each experiment is run by
`liftcheck explain --measure` (two runs: as listed and changed), its compared errors printed, and with
--write stored in its listing as {"change", "metric", "from", "to"[, "x"]}, replacing an earlier
experiment with the same change and metric. An experiment whose change moves the figure by less
than twice is printed and not written: it shows no cause.

    write_evidence.py PLAN.json [--liftcheck build/liftcheck] [--jobs 2] [--write]
"""
import argparse
import json
import math
import subprocess
import sys
import tempfile

EXPECT = "harness/expectations.json"
MOVE = 2.0


def measure_all(a, plan):
    """Every experiment's figures, measured by `liftcheck explain --measure` (the runs as explain makes them)."""
    with tempfile.NamedTemporaryFile("w", suffix=".json") as fh:
        json.dump(plan, fh)
        fh.flush()
        p = subprocess.run([a.liftcheck, "explain", "--measure", fh.name, "--json", "--jobs", str(a.jobs)],
                           capture_output=True, text=True, timeout=3600)
    if p.returncode not in (0, 1):
        raise SystemExit(f"write_evidence: explain failed: {p.stderr.strip()}")
    return [json.loads(line) for line in p.stdout.splitlines() if line.startswith("{")]


def listing_of(exp, e):
    """The expectations entry (and its sweep scenario) an experiment belongs to."""
    if "sweep" in e:
        for l in exp["sweep_points"]:
            if l["sweep"] == e["sweep"] and e["engine"] in l["engines"] and (
                    not l.get("points") or any(p["x"] == e["x"] for p in l["points"]) or e["x"] in l.get("x", [])):
                return l
    else:
        for l in exp["runs"]:
            if l["scenario"] == e["scenario"] and e["engine"] in l["engines"] and l.get("params", {}) == e.get("params", {}):
                return l
    raise SystemExit(f"write_evidence: no listing for {json.dumps(e)}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("plan")
    ap.add_argument("--liftcheck", default="build/liftcheck")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--write", action="store_true")
    a = ap.parse_args()
    plan = json.load(open(a.plan))
    exp = json.load(open(EXPECT))
    figures = measure_all(a, plan)
    if len(figures) != len(plan):
        raise SystemExit(f"write_evidence: explain measured {len(figures)} of {len(plan)} experiments")
    weak = 0
    for e, m in zip(plan, figures):
        f, t, tol = (math.nan if m[k] is None else m[k] for k in ("from", "to", "tolerance"))
        if math.isnan(tol):
            tol = 0.0
        where = (f"sweep {e['sweep']} x={e['x']:g}" if "sweep" in e else e["scenario"]) + f" on {e['engine']}"
        change = ", ".join(f"{k}={v}" for k, v in e["change"].items())
        from_error = m.get("from_error", False)
        moved = math.isfinite(t) and (from_error or (math.isfinite(f) and f > tol and (t * MOVE <= f or t >= MOVE * f)))
        print(f"{where}: {change}: {e['metric']} {f:.3g} -> {t:.3g} (tolerance {tol:.3g}){'' if moved else '  NOT MOVED 2x'}")
        if not moved:
            weak += 1
            continue
        listing = listing_of(exp, e)
        ev = {"change": e["change"], "metric": e["metric"], "from": "error" if from_error else float(f"{f:.3g}"), "to": float(f"{t:.3g}")}
        if "sweep" in e:
            ev["x"] = e["x"]
        kept = [x for x in listing.get("evidence", []) if not (x["change"] == ev["change"] and x["metric"] == ev["metric"]
                                                                 and x.get("x") == ev.get("x"))]
        listing["evidence"] = kept + [ev]
    if a.write:
        with open(EXPECT, "w") as fh:
            json.dump(exp, fh, indent=2, ensure_ascii=False)
            fh.write("\n")
    print(f"{len(plan)} experiments, {len(plan) - weak} moved their figure {MOVE:g}x or more" + ("; written" if a.write else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
