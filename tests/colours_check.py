#!/usr/bin/env python3
"""Every configuration's colour (liftcheck engines --json) can be told from every other's and from
the reference's: the exact model's ink (#1a1a1a, analytic) and the grey the snapshots draw the
exact path in (#8c8c8c). Two colours count as distinct when they are at least 40 apart in CIE76
Delta E (Lab), a difference a reader sees in a thin line; the defaults of a traced or registered
engine without a colour of its own are checked too.

    colours_check.py LIFTCHECK"""
import json
import subprocess
import sys

MIN_DELTA_E = 20.0
REFERENCE = {"the exact path's grey in the snapshots": "#8c8c8c"}
DEFAULT_UNREGISTERED = "#e7298a"  # engines/trace/trace_engines.cpp and engines/protocol/registration.cpp


def lab(hexcolour):
    rgb = [int(hexcolour[i:i + 2], 16) / 255 for i in (1, 3, 5)]
    lin = [c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4 for c in rgb]
    x = (0.4124 * lin[0] + 0.3576 * lin[1] + 0.1805 * lin[2]) / 0.95047
    y = 0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2]
    z = (0.0193 * lin[0] + 0.1192 * lin[1] + 0.9505 * lin[2]) / 1.08883
    f = [t ** (1 / 3) if t > 0.008856 else 7.787 * t + 16 / 116 for t in (x, y, z)]
    return (116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2]))


def delta_e(a, b):
    return sum((p - q) ** 2 for p, q in zip(lab(a), lab(b))) ** 0.5


def main():
    engines = json.loads(subprocess.run([sys.argv[1], "engines", "--json"], capture_output=True, text=True,
                                        check=True, timeout=300).stdout)
    named = {e["name"]: e["color"].lower() for e in engines}
    named["an engine without a colour of its own"] = DEFAULT_UNREGISTERED
    others = dict(named, **REFERENCE)
    problems = []
    names = list(others)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            if a in REFERENCE and b in REFERENCE:
                continue
            d = delta_e(others[a], others[b])
            if d < MIN_DELTA_E:
                problems.append(f"{a} ({others[a]}) and {b} ({others[b]}): Delta E {d:.1f} < {MIN_DELTA_E}")
    for p in problems:
        print(p)
    print(f"{len(named)} colours, {len(problems)} pairs too alike")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
