#!/usr/bin/env python3
"""The peak memory of a command and every process it starts (docs/performance.md).

    tests/tools/peak_memory.py [--every SECONDS] -- COMMAND...

Runs COMMAND and samples its process tree (every 0.1 s): each process's resident set (VmRSS) and
its proportional set (Pss, /proc/PID/smaps_rollup: a page shared by n processes counts 1/n in each,
so a forked renderer's pages shared with its parent are not counted twice). Prints, in MB (1e6
bytes): the largest resident set of one process over its life (VmHWM, exact: the kernel's own
high-water mark, read at each sample) and which process it was, the largest sampled sum of the
tree's resident sets and of its proportional sets. Exits with the command's status."""
import os
import subprocess
import sys
import time


def children_of():
    """{parent pid: [child pids]} of every process now."""
    kids = {}
    for name in os.listdir("/proc"):
        if not name.isdigit():
            continue
        try:
            with open(f"/proc/{name}/stat") as f:
                stat = f.read()
        except OSError:
            continue
        ppid = int(stat[stat.rindex(")") + 2:].split()[1])
        kids.setdefault(ppid, []).append(int(name))
    return kids


def tree(root):
    kids, out, todo = children_of(), [], [root]
    while todo:
        p = todo.pop()
        out.append(p)
        todo.extend(kids.get(p, []))
    return out


def status_kb(pid, keys):
    got = {}
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                k = line.split(":")[0]
                if k in keys:
                    got[k] = int(line.split()[1])
        with open(f"/proc/{pid}/smaps_rollup") as f:
            for line in f:
                if line.startswith("Pss:"):
                    got["Pss"] = int(line.split()[1])
        with open(f"/proc/{pid}/cmdline", "rb") as f:
            got["cmd"] = f.read().replace(b"\0", b" ").decode(errors="replace")[:100]
    except OSError:
        pass
    return got


def main():
    args = sys.argv[1:]
    every = 0.1
    if args[:1] == ["--every"]:
        every, args = float(args[1]), args[2:]
    if args[:1] == ["--"]:
        args = args[1:]
    child = subprocess.Popen(args)
    hwm, hwm_who, rss_sum, pss_sum, own, most = 0, "", 0, 0, 0, 0
    by_kind = {}  # the largest VmHWM of a process by its command's first two words
    while child.poll() is None:
        rss = pss = alive = 0
        for pid in tree(child.pid):
            s = status_kb(pid, {"VmRSS", "VmHWM"})
            rss += s.get("VmRSS", 0)
            pss += s.get("Pss", 0)
            alive += 1
            kind = " ".join(s.get("cmd", "?").split()[:2])
            by_kind[kind] = max(by_kind.get(kind, 0), s.get("VmHWM", 0))
            if pid == child.pid:
                own = max(own, s.get("VmHWM", 0))
            if s.get("VmHWM", 0) > hwm:
                hwm, hwm_who = s["VmHWM"], f"pid {pid}: {s.get('cmd', '?')}"
        rss_sum, pss_sum, most = max(rss_sum, rss), max(pss_sum, pss), max(most, alive)
        time.sleep(every)
    mb = lambda kb: kb * 1024 / 1e6
    print(f"peak memory: one process {mb(hwm):.0f} MB (VmHWM, {hwm_who}); the process tree {mb(rss_sum):.0f} MB of resident sets summed, "
          f"{mb(pss_sum):.0f} MB proportional (Pss, shared pages counted once)", file=sys.stderr)
    print(f"the command itself {mb(own):.0f} MB (VmHWM); at most {most} processes at once; the largest of each kind: "
          + ", ".join(f"{k} {mb(v):.0f} MB" for k, v in sorted(by_kind.items(), key=lambda kv: -kv[1])[:8]), file=sys.stderr)
    return child.returncode


if __name__ == "__main__":
    sys.exit(main())
