#!/usr/bin/env python3
"""Capture the requests an outside configuration receives in a suite, and replay them through
its adapter: the adapter's own cost per step (its CPU less its engine's engine_s, no round trip,
no liftcheck) and whether its replies are byte for byte those of another version of it (every
field but engine_s). For work on an adapter's speed: a change that alters no reply alters no
verdict.

  adapter_replay.py capture NAME STREAM [--liftcheck build/liftcheck] [--suite DIR]
      runs `liftcheck validate --engines NAME --no-sweeps --no-report --jobs 1` with NAME's
      registration wrapped so that every request line is also written to STREAM
  adapter_replay.py replay NAME STREAM REPLIES [--adapters DIR] [--suite DIR]
      feeds STREAM to NAME's adapter (its registration's command, the adapter taken from DIR,
      default engines/outside) on one core, writes its replies to REPLIES, prints its CPU
  adapter_replay.py same REPLIES_A REPLIES_B
      exit 0 if the two agree on every line but engine_s; else the first line that differs
  adapter_replay.py tee STREAM -- COMMAND...   (the wrapper capture registers; not for people)
"""
import argparse
import itertools
import json
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import threading

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
ENGINE_S = re.compile(rb'"engine_s":[-+0-9.eE]+')


def registration(suite, name):
    path = os.path.join(suite, f"{name}.json")
    try:
        with open(path) as f:
            return json.load(f)
    except OSError as e:
        sys.exit(f"adapter_replay.py: no registration '{path}': {e.strerror}")


def tee(args):
    """Copies standard input to STREAM and to COMMAND's standard input; COMMAND's output is ours."""
    child = subprocess.Popen(args.command, stdin=subprocess.PIPE)
    # Appended (capture empties it first: an adapter started again adds its requests), unbuffered
    # (liftcheck may kill this process at the end).
    with open(args.stream, "ab", buffering=0) as log:
        for line in sys.stdin.buffer:
            log.write(line)
            try:
                child.stdin.write(line)
                child.stdin.flush()
            except BrokenPipeError:
                break
    child.stdin.close()
    return child.wait()


def steps_in(line):
    """The engine steps a request line asks for: 1 for "step", one per target of "steps"."""
    if b'"op":"step"' in line:
        return 1
    if b'"op":"steps"' in line:
        return len(json.loads(line).get("targets", []))
    return 0


def segments(stream):
    """The stream cut after each "bye": what each process of the adapter was sent, in turn."""
    parts, part = [], []
    for line in stream:
        part.append(line)
        if b'"op":"bye"' in line:
            parts.append(part)
            part = []
    return parts + ([part] if part else [])


def capture(args):
    reg = registration(args.suite, args.name)
    open(args.stream, "wb").close()
    with tempfile.TemporaryDirectory() as tmp:
        wrapped = dict(reg, name=f"{args.name}-capture")
        command = reg["command"]
        # The command starts in its registration's folder: absolute paths for what it names there.
        command = [c if os.path.isabs(c) or not os.path.exists(os.path.join(args.suite, c))
                   else os.path.abspath(os.path.join(args.suite, c)) for c in command]
        wrapped["command"] = [sys.executable, os.path.abspath(__file__), "tee",
                              os.path.abspath(args.stream), "--", *command]
        with open(os.path.join(tmp, f"{args.name}-capture.json"), "w") as f:
            json.dump(wrapped, f)
        out = os.path.join(tmp, "out")
        run = subprocess.run([args.liftcheck, "--engine-dir", tmp, "validate", "--engines", f"{args.name}-capture",
                              "--no-sweeps", "--no-report", "--jobs", "1", "--out", out],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if not os.path.exists(os.path.join(out, "results.json")):
            sys.exit(f"adapter_replay.py: the suite wrote no results: {run.stderr.strip()[-300:]}")
    with open(args.stream, "rb") as f:
        lines = f.readlines()
    steps = sum(steps_in(line) for line in lines)
    starts = sum(1 for line in lines if b'"op":"hello"' in line)
    print(f"{args.stream}: {steps} steps" + (f" from {starts} processes of the adapter, one after another" if starts > 1 else ""))


def replay(args):
    reg = registration(args.suite, args.name)
    command = []
    for c in reg["command"]:
        local = os.path.join(args.suite, c)
        # An adapter named beside the registration is taken from --adapters instead.
        if c.endswith(".mjs") and os.path.exists(local):
            c = os.path.join(args.adapters, os.path.basename(c))
        command.append(c)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    # A process of the adapter for each part of the stream, as the suite started them (a process
    # ends at "bye"), one after another on one core.
    with open(args.stream, "rb") as stream, open(args.replies, "wb") as replies:
        cpu = os.sched_getaffinity(0)
        for part in segments(stream):
            done = subprocess.run(["taskset", "-c", str(max(cpu)), *command], input=b"".join(part), stdout=replies,
                                  stderr=subprocess.DEVNULL, cwd=args.suite, check=False)
            if done.returncode != 0:
                break
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu_s = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    engine_s, steps, refused = 0.0, 0, 0
    with open(args.replies, "rb") as f:
        for line in f:
            refused += line.startswith(b'{"ok":false')
            m = ENGINE_S.search(line)
            if m:
                engine_s += float(m.group(0).split(b":")[1])
                steps += 1
    if done.returncode != 0 or refused or steps == 0:
        print(f"{args.name}: the adapter exited with {done.returncode}, refused {refused} requests, "
              f"answered {steps} with engine_s: no figure (its replies are in {args.replies})")
        return 1
    per = (cpu_s - engine_s) / steps * 1e6
    print(f"{args.name}: {steps} replies with engine_s; {cpu_s:.2f} s of CPU, {engine_s:.2f} s of it the engine's: "
          f"{per:.1f} us a step in the adapter (start-up and builds included)")


def same(args):
    n = 0
    with open(args.a, "rb") as fa, open(args.b, "rb") as fb:
        for n, (x, y) in enumerate(itertools.zip_longest(fa, fb), 1):
            if x is None or y is None:
                print(f"line {n}: only {args.b if x is None else args.a} has it")
                return 1
            if ENGINE_S.sub(b"", x) != ENGINE_S.sub(b"", y):
                print(f"line {n} differs:\n  {x[:300]!r}\n  {y[:300]!r}")
                return 1
    print(f"the same replies (engine_s aside), {n} lines")
    return 0


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="what", required=True)
    for what in ("capture", "replay"):  # a configuration's registration and its stream
        q = sub.add_parser(what)
        q.add_argument("name")
        q.add_argument("stream")
        q.add_argument("--suite", default=os.path.join(ROOT, "engines", "outside", "suite"))
        if what == "capture":
            q.add_argument("--liftcheck", default=os.path.join(ROOT, "build", "liftcheck"))
        else:
            q.add_argument("replies")
            q.add_argument("--adapters", default=os.path.join(ROOT, "engines", "outside"))
    s = sub.add_parser("same")
    s.add_argument("a")
    s.add_argument("b")
    t = sub.add_parser("tee")
    t.add_argument("stream")
    t.add_argument("command", nargs=argparse.REMAINDER)
    args = p.parse_args()
    if args.what == "replay":
        args.adapters = os.path.abspath(args.adapters)  # the adapter starts in the suite's folder
    if args.what == "tee":
        args.command = args.command[1:] if args.command[:1] == ["--"] else args.command
        return tee(args)
    if not shutil.which("taskset") and args.what == "replay":
        sys.exit("adapter_replay.py: replay needs taskset (util-linux)")
    return {"capture": capture, "replay": replay, "same": same}[args.what](args) or 0


if __name__ == "__main__":
    sys.exit(main())
