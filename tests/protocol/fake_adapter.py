#!/usr/bin/env python3
"""An adapter that lies, for the tests of liftcheck's engine protocol (docs/protocol.md): it says
hello and builds like an honest one (a car that stands where it was put, disks that stay put),
then breaks the protocol in the way its mode names, at the first step (every reply carries its
request's number, "id", as protocol 2 and later require):
  version    hello answers protocol 1
  malformed  a reply that is not JSON
  nan        a reply with NaN in it (Python writes the bare word, which is not JSON)
  missing    a reply without the field x_m
  die        exits with status 7, a last word on stderr
  hang       never replies (liftcheck's --timeout must end it)
  flood      a line longer than 1 MiB
  badrole    hello declares a real-valued setting as a solver iteration count
  nullforce  a car's step reply whose optional ground_force_W is null
  chassisgone  a car's step replies carry ground forces, and the optional v_chassis_W on every
             other step only
  badservo   hello offers "steps" (servo_steps), whose replies give the servo law's rates as applied
             but for the fifth step's steering rate, off by 1e-9 rad/s
(the last three break car replies only: their disks stand still, and fail, without an error)"""
import json
import sys
import time

mode = sys.argv[1]


def out(obj):
    obj = dict(obj, id=req["id"]) if "id" in req else obj
    sys.stdout.write(json.dumps(obj) + "\n")
    sys.stdout.flush()


def car_state(req):
    R, q0 = req["car"]["R_m"], req["q0"]
    wheel = {"v_hub_W": [0, 0, 0], "omega_W": [0, 0, 0], "axle_W": [0, 1, 0], "hub_z_m": R}
    return {"ok": True, "spin_joint_rad": [0, 0], "steer_rad": [q0["beta_rad"], q0["beta_rad"]], "x_m": q0["x_m"], "y_m": q0["y_m"],
            "z_m": R, "phi_rad": q0["phi_rad"], "rear_z_m": R, "wheels": [wheel] * req["car"]["wheels"]}


built = None
steps = 0
for line in sys.stdin:
    req = json.loads(line)
    op = req["op"]
    if op == "hello":
        out({"ok": True, "protocol": 1 if mode == "version" else req["protocol"], "engine": "Fake", "version": "0", "precision": "float64",
             "vehicles": ["car", "disks"], "fixed": [["lies", mode]], "servo_steps": mode == "badservo",
             "settings": [{"key": "relax", "vehicle": "car", "kind": "real", "default": 0.5, "min": 0, "max": 1,
                           "role": "solver_iterations"}] if mode == "badrole" else []})
    elif op == "car":
        built = car_state(req)
        out(built)
    elif op == "disks":
        built = {"ok": True, "cM": req["cM0"], "cN": req["cN0"], "wM": [0.0, 0.0, 0.0], "contacts": {"count": 0}, "engine_s": 0.0}
        out({"ok": True, "cM": req["cM0"], "cN": req["cN0"]})
    elif op == "step":
        steps += 1
        car = "x_m" in built
        if car and mode == "nullforce":
            out(dict(built, engine_s=1e-6, ground_force_W=None))
        elif car and mode == "chassisgone":
            chassis = {"v_chassis_W": [0.0, 0.0, 0.0]} if steps % 2 else {}
            out(dict(built, engine_s=1e-6, ground_force_W=[0.0, 0.0, 10.0], **chassis))
        elif mode in ("nullforce", "chassisgone"):
            out(dict(built, engine_s=1e-6))
        elif mode == "malformed":
            sys.stdout.write("step done, x = 1.0\n")
            sys.stdout.flush()
        elif mode == "nan":
            out(dict(built, engine_s=1e-6, x_m=float("nan")) if "x_m" in built else dict(built, cM=[float("nan"), 0.0]))
        elif mode == "missing":
            out({k: v for k, v in dict(built, engine_s=1e-6).items() if k not in ("x_m", "cM")})
        elif mode == "die":
            sys.stderr.write("fake adapter: giving up\n")
            sys.exit(7)
        elif mode == "hang":
            time.sleep(3600)
        elif mode == "flood":
            sys.stdout.write("[" + "0," * (1 << 20) + "0]\n")
            sys.stdout.flush()
        else:
            out(dict(built, engine_s=1e-6))
    elif op == "steps":
        # A line a target with the law's rates (the car stands still: the booked wheel angle and the
        # steering stay as sent), but the fifth of a drive's steps claims a steering rate off by a
        # hair: liftcheck must check every line, and the steering as well as the spin.
        for alpha, beta, alpha_rate, beta_rate in req["targets"]:
            applied = [alpha_rate + req["spin_gain_per_s"] * (alpha - req["alpha_rad"]),
                       beta_rate + req["steer_gain_per_s"] * (beta - req["steer_rad"])]
            steps += 1
            if steps == 5:
                applied[1] += 1e-9
            out(dict(built, engine_s=1e-6, applied=applied))
    elif op == "bye":
        out({"ok": True})
        break
