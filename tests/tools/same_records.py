#!/usr/bin/env python3
"""Exit 0 when two results.json files hold the same records, timings aside: the runs, the sweeps
(points, fits, gates), the outcome sweep, the map and the summary. Wall-clock fields, the map's
cost per simulated second and the Pareto front drawn from it are measurements of the machine, not
of the engine, and are left out (an outside engine's own stepping seconds, engine_s, too). Prints
the first difference otherwise."""
import json
import sys

TIMING = {"wall_s", "engine_s", "cost_s_per_s", "pareto"}


def strip(x):
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items() if k not in TIMING}
    if isinstance(x, list):
        return [strip(v) for v in x]
    return x


def first_difference(a, b, where):
    if type(a) is not type(b):
        return f"{where}: {json.dumps(a)[:200]} against {json.dumps(b)[:200]}"
    if isinstance(a, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                return f"{where}.{k}: only in {'the first' if k in a else 'the second'}"
            d = first_difference(a[k], b[k], f"{where}.{k}")
            if d:
                return d
        return None
    if isinstance(a, list):
        if len(a) != len(b):
            return f"{where}: {len(a)} items against {len(b)}"
        for i, (x, y) in enumerate(zip(a, b)):
            d = first_difference(x, y, f"{where}[{i}]")
            if d:
                return d
        return None
    return None if a == b else f"{where}: {a!r} against {b!r}"


def expand_references(results):
    """A run's details.reference {"shared": k} as the trace shared_references[k] (how results.json
    keeps each exact lift once)."""
    shared = results.pop("shared_references", [])
    for run in results.get("runs", []):
        ref = run.get("details", {}).get("reference") if isinstance(run.get("details"), dict) else None
        if isinstance(ref, dict) and "shared" in ref:
            run["details"]["reference"] = shared[ref["shared"]]
    return results


def main():
    a, b = (expand_references(json.load(open(p))) for p in sys.argv[1:3])
    parts = sys.argv[3].split(",") if len(sys.argv) > 3 else ["runs", "sweeps", "maps", "summary", "scenarios"]
    for part in parts:
        d = first_difference(strip(a.get(part)), strip(b.get(part)), part)
        if d:
            print("differs:", d)
            return 1
    if not a.get("runs"):
        print("no runs to compare")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
