#!/usr/bin/env python3
"""Checks a liftcheck report folder: every HTML page is well formed (tags balance), every file it
references exists inside the folder, no page reaches the network, and results.json lists what the
pages show. Usage: report_check.py REPORT_DIR"""
import json
import os
import sys
from html.parser import HTMLParser

VOID = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta", "source", "track", "wbr"}


class Checker(HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.stack, self.refs, self.problems = [], [], []

    def handle_starttag(self, tag, attrs):
        for name, value in attrs:
            if name in ("src", "href") and value:
                self.refs.append(value)
        if tag not in VOID:
            self.stack.append((tag, self.getpos()))

    def handle_endtag(self, tag):
        if tag in VOID:
            return
        if not self.stack or self.stack[-1][0] != tag:
            self.problems.append(f"unexpected </{tag}> at line {self.getpos()[0]}")
            return
        self.stack.pop()


def check(folder):
    problems = []
    pages = sorted(f for f in os.listdir(folder) if f.endswith(".html"))
    if "index.html" not in pages:
        return ["no index.html"]
    for page in pages:
        with open(os.path.join(folder, page), encoding="utf-8") as f:
            text = f.read()
        if not text.lstrip().lower().startswith("<!doctype html>"):
            problems.append(f"{page}: no doctype")
        c = Checker()
        c.feed(text)
        c.close()
        problems += [f"{page}: {p}" for p in c.problems]
        problems += [f"{page}: <{t}> opened at line {pos[0]} is never closed" for t, pos in c.stack]
        for ref in c.refs:
            if ref.startswith(("http:", "https:", "//")):
                problems.append(f"{page}: reaches the network: {ref}")
                continue
            target = ref.split("#")[0]
            if target and not os.path.isfile(os.path.join(folder, target)):
                problems.append(f"{page}: missing {ref}")
    with open(os.path.join(folder, "results.json")) as f:
        results = json.load(f)
    report = results.get("report", {})
    if report.get("errors"):
        problems += [f"report error: {e}" for e in report["errors"]]
    for key in ("snapshots", "plots"):
        for item in report.get(key, []):
            if not os.path.isfile(os.path.join(folder, item["file"])):
                problems.append(f"results.json lists a missing {key[:-1]}: {item['file']}")
    ran = {(r["scenario"], r["engine"]) for r in results["runs"] if r["status"] in ("pass", "fail")}
    shot = {(s["scenario"], s["engine"]) for s in report.get("snapshots", [])}
    problems += [f"no snapshot for {sc} on {en}" for sc, en in sorted(ran - shot)]
    return problems


if __name__ == "__main__":
    found = check(sys.argv[1])
    for p in found:
        print("FAIL", p)
    print(f"{0 if found else 1} passed, {1 if found else 0} failed")
    sys.exit(1 if found else 0)
