#!/usr/bin/env python3
"""Checks of the engine protocol's records (tests/protocol/protocol_test.sh).

same RESULTS A B: every run of configuration B equals the run of A on the same scenario, field by
field, apart from the configuration's name, what follows from the name (its known failures: the
verdict and expectation) and the timings (wall_s, engine_s). B must carry engine_s, A must not.

lies RESULTS: every run of a fake-* configuration (but the disks of those that lie about cars
only) is an error whose message is one line naming the
configuration and what went wrong; every run of ode passes."""
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from same_records import expand_references, first_difference  # noqa: E402  (the one comparison of records)

NAMED = {"engine", "verdict", "as_expected", "expectation"}
TIMING = {"wall_s", "engine_s"}


def same(results, a, b):
    runs = expand_references(json.load(open(results)))["runs"]
    by = {(r["scenario"], r["engine"]): r for r in runs}
    scenarios = sorted({r["scenario"] for r in runs})
    cars = disks = 0
    for s in scenarios:
        ra, rb = by[(s, a)], by[(s, b)]
        assert "engine_s" not in ra, f"{s}: {a} is in process, its record has no engine_s"
        if rb["status"] != "skip":
            assert rb.get("engine_s", 0) > 0, f"{s}: {b} reports no engine_s"
        assert ra["status"] != "error", f"{s} on {a}: {ra['message']}"
        strip = lambda r: {k: v for k, v in r.items() if k not in NAMED | TIMING}
        d = first_difference(strip(ra), strip(rb), s)
        assert d is None, f"{a} and {b} differ: {d}"
        cars += ra["vehicle"] == "car"
        disks += ra["vehicle"] == "disks"
    assert cars >= 9 and disks >= 9, f"only {cars} car and {disks} disk scenarios compared"
    print(f"same records: {a} and {b} on {cars} car and {disks} disk scenarios")


EXPECT = {
    "fake-version": "speaks protocol 1, liftcheck speaks 3",
    "fake-malformed": "a reply that is not one JSON object",
    "fake-nan": "non-finite number",
    "fake-missing": "the reply has no field '",
    "fake-die": "exited with status 7",
    "fake-hang": "no reply within",
    "fake-flood": "longer than 1 MiB",
    "fake-badrole": "role 'solver_iterations' needs an integer setting",
    "fake-nullforce": "field 'ground_force_W' is not an array of 3 numbers",
    "fake-chassisgone": "reported the chassis velocity at the drive's start",
    "fake-badservo": "not the law of docs/protocol.md",
}
CAR_ONLY = {"fake-nullforce", "fake-chassisgone", "fake-badservo"}  # their disks break nothing: not an error


def lies(results):
    runs = expand_references(json.load(open(results)))["runs"]
    seen = set()
    for r in runs:
        e = r["engine"]
        if e == "ode":
            assert r["status"] == "pass", f"{r['scenario']} on ode: {r['status']} {r['message']}"
            continue
        seen.add(e)
        m = r["message"]
        if e in CAR_ONLY and r["vehicle"] == "disks":
            assert r["status"] != "error", f"{r['scenario']} on {e}: an error from an honest disk reply: {m!r}"
            continue
        assert r["status"] == "error", f"{r['scenario']} on {e}: {r['status']} (expected an error record)"
        assert "\n" not in m and len(m) < 600, f"{r['scenario']} on {e}: not one short line: {m!r}"
        named = e == "fake-chassisgone" or f"engine '{e}'" in m  # the load book's error: the record names it
        assert named and EXPECT[e] in m, f"{r['scenario']} on {e}: {m!r} does not say '{EXPECT[e]}'"
        if e == "fake-die":
            assert "giving up" in m, f"{e}: the message does not quote its stderr: {m!r}"
        if e in ("fake-malformed",):
            assert "step done" in m, f"{e}: the message does not quote what it sent last: {m!r}"
    assert seen == set(EXPECT), f"runs of {sorted(seen)}, expected {sorted(EXPECT)}"
    print(f"lies: {len(seen)} lying adapters, each an error record with its reason; ode passes beside them")


if __name__ == "__main__":
    {"same": same, "lies": lies}[sys.argv[1]](*sys.argv[2:])
