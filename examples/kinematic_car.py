#!/usr/bin/env python3
"""A stand-in for a simulator outside liftcheck: reads the commanded path of a car scenario
(`liftcheck path SCENARIO > path.csv`), drives a tricycle that rolls without slipping through it
with its own integrator, and writes the trace that `liftcheck score SCENARIO --trace trace.csv`
scores. Replace the integration with your simulator's step; keep the two CSV formats.

Usage: kinematic_car.py path.csv trace.csv [--dt 0.001] [--slip 0.0]

The model: the front-axle centre moves along the front wheel's heading phi + beta at R dalpha/dt,
and the heading turns at R dalpha/dt sin(beta) / l (Fecko, (4.1)). --slip makes the car travel that
fraction farther than its wheel rolled (a broken simulator, to see liftcheck fail it).
"""
import argparse
import math
import sys


def read_path(name):
    params, start, rows, header = {}, {}, [], None
    with open(name) as f:
        for line in f:
            line = line.strip()
            if not line:
                continue
            if line.startswith("#"):
                words = line[1:].split()
                if len(words) >= 4 and words[0] in ("param", "start") and words[2] == "=":
                    (params if words[0] == "param" else start)[words[1]] = words[3]
                continue
            if header is None:
                header = line.split(",")
                continue
            rows.append(dict(zip(header, map(float, line.split(",")))))
    if header != ["t", "alpha", "beta"]:
        sys.exit(f"{name}: not a car path (header {header})")
    return params, {k: float(v) for k, v in start.items()}, rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("path")
    ap.add_argument("trace")
    ap.add_argument("--dt", type=float, default=0.001, help="integration step, s")
    ap.add_argument("--slip", type=float, default=0.0, help="travel this fraction farther than the wheel rolled")
    a = ap.parse_args()
    params, start, rows = read_path(a.path)
    R, l = float(params["R"]), float(params["l"])
    x, y, phi = start["x"], start["y"], start["phi"]
    out = [(rows[0]["t"], rows[0]["alpha"], rows[0]["beta"], x, y, phi)]
    for r0, r1 in zip(rows, rows[1:]):
        h = r1["t"] - r0["t"]
        n = max(1, round(h / a.dt))
        for k in range(n):
            # The path is linear between its samples; midpoint rule on each sub-step.
            s = (k + 0.5) / n
            beta = r0["beta"] + s * (r1["beta"] - r0["beta"])
            ds = (1.0 + a.slip) * R * (r1["alpha"] - r0["alpha"]) / n  # front-wheel travel
            phi_mid = phi + 0.5 * ds * math.sin(beta) / l
            x += ds * math.cos(phi_mid + beta)
            y += ds * math.sin(phi_mid + beta)
            phi += ds * math.sin(beta) / l
        out.append((r1["t"], r1["alpha"], r1["beta"], x, y, phi))
    with open(a.trace, "w") as f:
        f.write("# written by examples/kinematic_car.py\nt,alpha,beta,x,y,phi\n")
        for row in out:
            f.write(",".join(f"{v:.17g}" for v in row) + "\n")


if __name__ == "__main__":
    main()
