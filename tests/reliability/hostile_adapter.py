#!/usr/bin/env python3
"""An adapter that misbehaves, for tests/reliability/reliability_test.sh: it speaks the engine
protocol (docs/protocol.md: every reply carries its request's "id") like an honest one
(a car that stands where it was put, disks that stay put) except in the way its mode names:

bytes (issue #37, item 1; item 10: NUL)
  latin1-start     writes a Latin-1 error on stderr and exits 1 before its hello
  latin1-hello     its hello names the engine in Latin-1 (a byte that is not UTF-8)
  latin1-knob      its hello's setting help is Latin-1
  latin1-step      at the first step: Latin-1 on stderr, then a reply with a Latin-1 byte in it
  latin1-die       at the first step: a Latin-1 line on stderr, then exits 3
  nul-error        at the first step: {"ok": false, "error": "before\\u0000after the NUL"}
  nul-raw          at the first step: a reply line with a raw NUL byte in it
framing (item 3)
  extra-build      after each build reply, one more line shaped like a step reply (every later
                   reply would answer the request before it)
  extra-hello      its hello reply twice
  no-id            no "id" in any reply (an adapter written to the old framing)
  wrong-id         at the first step, a reply numbered one more than the request
  string-id        at the first step, the request's number as a string
processes and time (items 5, 6)
  grandchild       at the first step, starts `sleep 300` holding its standard output (its pid
                   in the file argv[2]) and exits 5
  grandchild-setsid  the same, the grandchild in a session of its own (setsid)
  slow-hello       sleeps 300 s before its hello
"""
import json
import os
import subprocess
import sys
import time

mode = sys.argv[1]
out = sys.stdout.buffer


def send(obj):
    out.write(json.dumps(obj).encode() + b"\n")
    out.flush()


def raw(data):
    out.write(data + b"\n")
    out.flush()


def car_state(req):
    R, q0 = req["car"]["R_m"], req["q0"]
    wheel = {"v_hub_W": [0, 0, 0], "omega_W": [0, 0, 0], "axle_W": [0, 1, 0], "hub_z_m": R}
    return {"spin_joint_rad": [0, 0], "steer_rad": [q0["beta_rad"], q0["beta_rad"]], "x_m": q0["x_m"], "y_m": q0["y_m"],
            "z_m": R, "phi_rad": q0["phi_rad"], "rear_z_m": R, "wheels": [wheel] * req["car"]["wheels"]}


def hello(rid, protocol):
    knob = {"key": "iterations", "vehicle": "car", "kind": "integer", "min": 1, "max": 9, "default": "4", "help": "iterations"}
    reply = {"ok": True, "id": rid, "protocol": protocol, "engine": "Hostile", "version": "0", "precision": "float64",
             "vehicles": ["car", "disks"], "settings": [knob], "fixed": [["misbehaves", mode]]}
    if rid is None:
        del reply["id"]
    text = json.dumps(reply).encode()
    if mode == "latin1-hello":
        text = text.replace(b'"Hostile"', b'"Gr\xf6\xdfe Fehler"')
    if mode == "latin1-knob":
        text = text.replace(b'"help": "iterations"', b'"help": "Iterationen f\xfcr den L\xf6ser"')
    raw(text)
    if mode == "extra-hello":
        raw(text)


def first_step(rid, state):
    """The misbehaviour at the first step; False when this mode steps honestly."""
    if mode == "latin1-step":
        sys.stderr.buffer.write(b"Fehler: Gr\xf6\xdfe des Schritts\n")
        sys.stderr.flush()
        raw(b'{"ok": false, "id": %d, "error": "Schritt fehlgeschlagen: \xe4\xf6\xfc"}' % rid)
    elif mode == "latin1-die":
        sys.stderr.buffer.write(b"Fehler: L\xf6ser abgest\xfcrzt\n")
        sys.stderr.flush()
        sys.exit(3)
    elif mode == "nul-error":
        send({"ok": False, "id": rid, "error": "before\u0000after the NUL"})
    elif mode == "nul-raw":
        raw(b'{"ok": true, "id": %d, "x_m": 1\x00 after the NUL' % rid)
    elif mode == "wrong-id":
        send(dict(state, ok=True, id=rid + 1, engine_s=1e-6))
    elif mode == "string-id":
        send(dict(state, ok=True, id=str(rid), engine_s=1e-6))
    elif mode.startswith("grandchild"):
        child = subprocess.Popen(["sleep", "300"], stdin=subprocess.DEVNULL, stdout=sys.stdout, stderr=subprocess.DEVNULL,
                                 start_new_session=mode == "grandchild-setsid")
        with open(sys.argv[2], "w") as f:
            f.write(f"{child.pid}\n")
        sys.exit(5)
    else:
        return False
    return True


def main():
    if mode == "latin1-start":
        sys.stderr.buffer.write(b"Fehler: Modul f\xfcr den L\xf6ser nicht gefunden\n")
        sys.stderr.flush()
        sys.exit(1)
    state, stepped = None, False
    for line in sys.stdin.buffer:
        req = json.loads(line)
        rid, op = req.get("id"), req["op"]
        if mode == "no-id":
            rid = None
        if op == "hello":
            if mode == "slow-hello":
                time.sleep(300)
            hello(rid, req.get("protocol"))
            continue
        if op == "bye":
            send({"ok": True, "id": rid})
            break
        if op in ("car", "disks"):
            state = car_state(req) if op == "car" else {"cM": req["cM0"], "cN": req["cN0"], "wM": [0.0, 0.0, 0.0], "contacts": {"count": 0}}
            reply = {k: v for k, v in state.items() if k != "contacts"}
            send(dict(reply, ok=True) if rid is None else dict(reply, ok=True, id=rid))
            if mode == "extra-build":
                send(dict(state, ok=True, id=rid, engine_s=1e-6))
            continue
        if not stepped:
            stepped = True
            if first_step(rid, state):
                continue
        send(dict(state, ok=True, engine_s=1e-6) if rid is None else dict(state, ok=True, id=rid, engine_s=1e-6))


main()
