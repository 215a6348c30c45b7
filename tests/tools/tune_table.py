#!/usr/bin/env python3
"""The table of `liftcheck tune` answers: every configuration on the scenarios that carry the
README's headline figures, each pair's answer (the cheapest passing settings and their cost against
the default's) or closest approach, written to data/tune/table.json with a fingerprint of what the
answer was searched over (the configuration's settings for the vehicle, the scenario's parameters,
the budget), so that tests/tune_table_check.py can tell a stale table. `make tune-table` runs it.

    tune_table.py [--liftcheck build/liftcheck] [--budget 16] [--timeout 30] [--jobs 2] [--only SCEN:ENGINE,...|stale] [--check] [--markdown]

It writes docs/tune.md and the README engine table's last column from the table too (--markdown:
that only).

--check writes nothing: it exits 1 naming every pair missing from the table or whose fingerprint
changed (what the ctest tune_table runs).
"""
import argparse
import hashlib
import json
import os
import re
import subprocess
import sys

TABLE = "data/tune/table.json"
DOC = "docs/tune.md"
SCENARIOS = ["car.circle", "car.cycle", "car.slope", "car.coulomb", "disks.oblique"]


def catalogue(exe):
    engines = json.loads(subprocess.run([exe, "engines", "--json"], capture_output=True, text=True, check=True).stdout)
    scenarios = json.loads(subprocess.run([exe, "list", "--json"], capture_output=True, text=True, check=True).stdout)
    return engines, {s["name"]: s for s in scenarios}


def vehicle_of(scenario):
    return "disks" if scenario.startswith("disks.") else "car"


def applies(engine, scenario):
    """The pair has a run in the default suite on an engine with settings to tune: the engine builds the
    vehicle and is not the analytic reference (exact by construction)."""
    return vehicle_of(scenario) in engine["vehicles"] and not engine.get("is_reference")


def fingerprint(engine, scenario, budget):
    knobs = [k for k in engine["knobs"] if k["vehicle"] == scenario["vehicle"]]
    params = {p["key"]: p.get("default") for p in scenario.get("params", [])}
    text = json.dumps({"knobs": knobs, "params": params, "metrics": scenario.get("metrics"), "budget": budget,
                       "engine": [engine.get("library"), engine.get("version"), engine.get("settings")]},
                      sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def pairs(engines, scenarios):
    for name in SCENARIOS:
        for e in engines:
            if applies(e, name):
                yield name, e, scenarios[name]


def entry_of(doc, budget, fp):
    walked = doc["walked"]
    base = walked[0]["cost_ms_per_s"]
    e = {"budget": budget, "fingerprint": fp, "runs": len(walked),
         "default_passes": bool(walked[0]["pass"]), "default_cost_ms_per_s": base}
    pick = doc["answer"] if doc["answer"] is not None else doc["closest"]
    s = walked[pick]
    e.update({"passes": doc["answer"] is not None, "change": s["change"], "worst_ratio": s["worst_ratio"],
              "cost_ms_per_s": s["cost_ms_per_s"], "model_cost": s.get("model_cost"),
              "cost_ratio": s["cost_ms_per_s"] / base if base and s["cost_ms_per_s"] is not None else None,
              "unmade": doc.get("unmade", 0)})
    return e


def num(v):
    return "?" if v is None else f"{v:.2g}"


def cut_short(e):
    """A search the budget cut short says so: a cheaper pass, or any pass, may lie in its unmade runs."""
    return f" [{e['unmade']} run{'' if e['unmade'] == 1 else 's'} unmade]" if e.get("unmade") else ""


def cell(e):
    change = ", ".join(f"{k}={v}" for k, v in sorted(e["change"].items())) or "defaults"
    if e["passes"]:
        return f"{change} ({num(e['cost_ratio'])}×){cut_short(e)}"
    return f"none; closest {change}: {num(e['worst_ratio'])}× tol. ({num(e['cost_ratio'])}×){cut_short(e)}"


README = "README.md"
README_HEADER = "tuned: car.circle passes at (cost); headline scenarios passing"


def readme_cell(table, name):
    """The README's engine table: what tune found for car.circle, and how many of the headline scenarios
    pass at some setting tried (docs/tune.md has every cell)."""
    mine = [table["entries"].get(f"{s} {name}") for s in SCENARIOS]
    mine = [e for e in mine if e]
    if not mine:
        return "–"
    circle = table["entries"].get(f"car.circle {name}")
    head = "–" if circle is None else short_cell(circle)
    return f"{head}; {sum(e['passes'] for e in mine)} of {len(mine)}"


def short_cell(e):
    change = ", ".join(f"{k}={v}" for k, v in sorted(e["change"].items())) or "defaults"
    if e["passes"]:
        return f"{change} ({num(e['cost_ratio'])}×){cut_short(e)}"
    return f"none (closest {num(e['worst_ratio'])}× tol. at {change}){cut_short(e)}"


def readme_rows(table, text):
    """README.md with its engine table's last column (README_HEADER) written from the table; the other
    columns are left as they are. Returns the new text and the configurations whose cell changed."""
    out, changed, in_table = [], [], False
    for line in text.split("\n"):
        if line.startswith("| configuration |") and README_HEADER in line:
            in_table = True
        elif in_table and not line.startswith("|"):
            in_table = False
        m = re.match(r"\| `([^`]+)` \|", line) if in_table else None
        if m:
            cells = line.rstrip(" |").split(" | ")
            want = readme_cell(table, m.group(1))
            if cells[-1] != want:
                changed.append(m.group(1))
                cells[-1] = want
            line = " | ".join(cells) + " |"
        out.append(line)
    return "\n".join(out), changed


def write_markdown(table, engines):
    """docs/tune.md: the table as a reader sees it, configurations as rows."""
    lines = ["# What it takes to pass", "",
             "`liftcheck tune SCENARIO --engine NAME` searches a configuration's declared settings and the step",
             "`dt` for the cheapest that pass (docs/cli.md says how). This is its committed table",
             f"([`{TABLE}`](../{TABLE}), written by `make tune-table` at a budget of "
             f"{next(iter(table['entries'].values()))['budget']} runs a pair; the ctest `tune_table` fails when",
             "a configuration's settings or a scenario's parameters changed since, or the README's column differs). Each cell: the settings that",
             "pass, judged against the default run's tolerances, and their measured cost against the defaults'",
             "(the engine's time per simulated second), or, where nothing tried passed, the closest run, its",
             "worst error over the default run's tolerance and its cost. A search cut short by its budget is",
             "marked with its unmade runs (`[N runs unmade]`): a cheaper pass, or a pass where it says none, may",
             "lie there (`liftcheck tune` at its default budget of 40 makes them).",
             "Costs are measured on the 2-core machine of docs/performance.md, both cores busy.", "",
             "| configuration | " + " | ".join(SCENARIOS) + " |", "|---|" + "---|" * len(SCENARIOS)]
    for e in engines:
        cells = [cell(table["entries"][f"{s} {e['name']}"]) if f"{s} {e['name']}" in table["entries"] else "–"
                 for s in SCENARIOS]
        lines.append(f"| `{e['name']}` | " + " | ".join(cells) + " |")
    with open(DOC, "w") as f:
        f.write("\n".join(lines) + "\n")
    text, _ = readme_rows(table, open(README).read())
    with open(README, "w") as f:
        f.write(text)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--liftcheck", default="build/liftcheck")
    ap.add_argument("--budget", type=int, default=16)
    ap.add_argument("--timeout", type=float, default=30.0, help="CPU seconds a run may take (beyond: an error)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", default="")
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--markdown", action="store_true", help="only write docs/tune.md from the table")
    a = ap.parse_args()
    engines, scenarios = catalogue(a.liftcheck)
    table = json.load(open(TABLE)) if os.path.exists(TABLE) else {"entries": {}}
    if a.check:
        stale = []
        wanted = set()
        for name, e, s in pairs(engines, scenarios):
            key = f"{name} {e['name']}"
            wanted.add(key)
            have = table["entries"].get(key)
            budget = have["budget"] if have else a.budget
            if not have:
                stale.append(f"{key}: not in the table")
            elif have["fingerprint"] != fingerprint(e, s, budget):
                stale.append(f"{key}: its settings, their defaults or ranges, or the scenario's parameters changed")
        stale += [f"{k}: no such pair in the catalogue" for k in table["entries"] if k not in wanted]
        readme = open(README).read()
        if README_HEADER not in readme:
            stale.append(f"{README}: its engine table has no column '{README_HEADER}'")
        stale += [f"{README}: {n}'s cell '{README_HEADER}' differs from the table" for n in readme_rows(table, readme)[1]]
        for line in stale:
            print(line)
        print(f"{TABLE}: {len(wanted)} pairs, {len(stale)} stale (make tune-table writes them again)")
        return 1 if stale else 0
    if a.markdown:
        write_markdown(table, engines)
        return 0
    only = set(x for x in a.only.split(",") if x)
    for name, e, s in pairs(engines, scenarios):
        key = f"{name} {e['name']}"
        if "stale" in only:
            have = table["entries"].get(key)
            if have and have["fingerprint"] == fingerprint(e, s, have["budget"]):
                continue
        elif only and f"{name}:{e['name']}" not in only:
            continue
        p = subprocess.run([a.liftcheck, "tune", name, "--engine", e["name"], "--budget", str(a.budget), "--jobs",
                            str(a.jobs), "--timeout", str(a.timeout), "--json"], capture_output=True, text=True, timeout=7200)
        if p.returncode not in (0, 1):
            sys.exit(f"tune {name} --engine {e['name']} failed: {p.stderr.strip()}")
        table["entries"][key] = entry_of(json.loads(p.stdout), a.budget, fingerprint(e, s, a.budget))
        en = table["entries"][key]
        print(f"{key}: {'passes at' if en['passes'] else 'closest'} {en['change'] or 'defaults'}, "
              f"worst {num(en['worst_ratio'])} x tol, cost x{num(en['cost_ratio'])}, {en['runs']} runs", flush=True)
        table["about"] = ("liftcheck tune's answers (tests/tools/tune_table.py, make tune-table): per pair "
                          "'SCENARIO CONFIGURATION', the cheapest passing settings found (passes) or the closest "
                          "approach, its worst error over its tolerance, its cost in ms of the engine per simulated "
                          "second and against the default's, the runs it took of its budget; fingerprint: what was "
                          "searched (the ctest tune_table runs this script with --check)")
        table["entries"] = dict(sorted(table["entries"].items()))
        os.makedirs(os.path.dirname(TABLE), exist_ok=True)
        with open(TABLE + ".tmp", "w") as f:
            json.dump(table, f, indent=1, sort_keys=True)
            f.write("\n")
        os.replace(TABLE + ".tmp", TABLE)
    write_markdown(table, engines)
    return 0


if __name__ == "__main__":
    sys.exit(main())
