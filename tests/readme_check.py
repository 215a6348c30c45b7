#!/usr/bin/env python3
"""What the README shows is what the binary does. Its "One run" block must be, line for line, what
`liftcheck run car.circle --engine ode` prints; its table's counts (runs passed / reviewed known
failures / skipped per configuration) and the suite's run and configuration counts above it must
be the committed baseline's. With --write (`make readme`) the block and the counts are rewritten
from the current build and baseline instead, and the tune sentence from `liftcheck tune car.circle
--engine ode-quick` (its default budget).

    readme_check.py LIFTCHECK README.md BASELINE.json [--write]
"""
import json
import re
import subprocess
import sys

RUN = ["run", "car.circle", "--engine", "ode"]
BLOCK = re.compile(r"(```console\n\$ build/liftcheck run car\.circle --engine ode\n)(.*?)(```)", re.S)
ROW = re.compile(r"^\| `([a-z0-9-]+)` \| (\d+) / (\d+) / (\d+) \|", re.M)
SUITE = re.compile(r"(`validate --jobs 2`: )(\d+) runs over (\d+) configurations")
TUNE = re.compile(r"(`tune car\.circle --engine ode-quick` finds that )(\d+) iterations pass \((\d+) runs, "
                  r"([0-9.]+)× the default's cost in the cost model\)")


def printed(exe, args):
    p = subprocess.run([exe] + args, capture_output=True, text=True, timeout=900, env={"NO_COLOR": "1", "PATH": "/usr/bin:/bin"})
    if p.returncode not in (0, 1):
        raise SystemExit(f"readme_check: liftcheck {' '.join(args)} exited {p.returncode}: {p.stderr.strip()[:300]}")
    return p.stdout


def counts(baseline):
    """{configuration: (pass, known, skip)} and the number of runs, from the baseline's records."""
    by = {}
    runs = json.load(open(baseline))["runs"]
    for r in runs:
        c = by.setdefault(r["engine"], [0, 0, 0])
        if r["verdict"] == "pass":
            c[0] += 1
        elif r["verdict"] == "known failure":
            c[1] += 1
        elif r["verdict"] == "skip":
            c[2] += 1
    return {k: tuple(v) for k, v in by.items()}, len(runs)


def tune_sentence(exe):
    doc = json.loads(printed(exe, ["tune", "car.circle", "--engine", "ode-quick", "--jobs", "2", "--json"]))
    a = doc["walked"][doc["answer"]]
    return a["change"]["iterations"], len(doc["walked"]), a["model_cost"]


def main():
    exe, readme, baseline = sys.argv[1:4]
    write = "--write" in sys.argv[4:]
    text = open(readme).read()
    problems = []
    block = BLOCK.search(text)
    if not block:
        raise SystemExit("readme_check: README has no console block of `build/liftcheck run car.circle --engine ode`")
    now = printed(exe, RUN)
    if block.group(2) != now:
        problems.append("the run block differs from what `liftcheck run car.circle --engine ode` prints:\n" + now)
    text = text[:block.start(2)] + now + text[block.end(2):]
    by, runs = counts(baseline)
    suite = SUITE.search(text)
    if not suite or (int(suite.group(2)), int(suite.group(3))) != (runs, len(by)):
        problems.append(f"the suite sentence should say {runs} runs over {len(by)} configurations")
    if suite:
        text = text[:suite.start(2)] + f"{runs} runs over {len(by)}" + text[suite.end(3):]
    seen = set()
    for m in reversed(list(ROW.finditer(text))):
        name, shown = m.group(1), tuple(int(m.group(i)) for i in (2, 3, 4))
        seen.add(name)
        want = by.get(name)
        if want is None:
            problems.append(f"the table names `{name}`, which the baseline has no runs of")
            continue
        if shown != want:
            problems.append(f"`{name}`: the table says {shown}, the baseline {want}")
        text = text[:m.start(2)] + "{} / {} / {}".format(*want) + text[m.end(4):]
    for name in sorted(set(by) - seen):
        problems.append(f"the table has no row for `{name}`")
    if write:
        tune = TUNE.search(text)
        if tune:
            it, n, cost = tune_sentence(exe)
            text = text[:tune.start(2)] + f"{it} iterations pass ({n} runs, {cost:.2f}× the default's cost in the cost model)" + text[tune.end():]
        else:
            print("readme_check: no tune sentence to rewrite", file=sys.stderr)
        open(readme, "w").write(text)
        return 0
    for p in problems:
        print("FAIL " + p)
    print(f"{len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
