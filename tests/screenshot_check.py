#!/usr/bin/env python3
"""Reads the layout of a report's index.html in headless Chromium at 1366x768 and checks its first
screen: the summary matrix is no wider than the window, the whole matrix and the verdict counts lie
within the first screen, the whole page is at most 8 screens tall, every configuration has a column and every scenario a row, and each
cell's number is its scenario's headline metric, computed here from results.json. Element sizes
come from the browser's DOM (getBoundingClientRect), measured by a script added to a copy of the
page; a screenshot of the first screen is saved too.
Usage: screenshot_check.py REPORT_DIR OUT_PNG [--width W] [--height H] [--inject-css CSS]"""
import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

MEASURE = r"""<script>
(function () {
  function box(el) { if (!el) return null; var r = el.getBoundingClientRect();
    return {left: r.left, right: r.right, top: r.top, bottom: r.bottom, width: r.width}; }
  var m = document.getElementById('matrix'), out = {
    inner_width: window.innerWidth, inner_height: window.innerHeight,
    scroll_width: document.documentElement.scrollWidth, page_height: document.documentElement.scrollHeight,
    matrix: box(m), counts: box(document.getElementById('counts')), headers: [], rows: []};
  if (m) {
    var ths = m.rows[0].cells;
    for (var i = 2; i < ths.length; ++i) out.headers.push(ths[i].textContent);
    for (var r = 1; r < m.rows.length; ++r) {
      var row = m.rows[r], cells = [];
      for (var c = 2; c < row.cells.length; ++c) {
        var td = row.cells[c], a = td.querySelector('a');
        cells.push({metric: td.getAttribute('data-metric'), value: td.getAttribute('data-value'),
                    text: td.textContent, href: a ? a.getAttribute('href') : null, box: box(td)});
      }
      out.rows.push({scenario: row.cells[0].textContent, cells: cells});
    }
  }
  var pre = document.createElement('pre'); pre.id = 'layout-measure'; pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
})();
</script>"""


def chromium():
    return shutil.which("chromium") or shutil.which("chromium-browser")


def browser_cmd(browser, profile, width, height):
    return [browser, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
            "--disable-background-networking", "--disable-component-update", "--disable-sync",
            f"--user-data-dir={profile}", "--hide-scrollbars", f"--window-size={width},{height}"]


def measure(folder, width, height, css, out_png):
    """The page's layout as the browser reports it, and a screenshot of the first screen."""
    browser = chromium()
    index = os.path.abspath(os.path.join(folder, "index.html"))
    with open(index, encoding="utf-8") as f:
        page = f.read()
    base = "<base href=\"file://" + os.path.abspath(folder) + "/\">"
    extra = f"<style>{css}</style>" if css else ""
    page = page.replace("<head>", "<head>\n" + base + extra, 1).replace("</body>", MEASURE + "</body>", 1)
    with tempfile.TemporaryDirectory() as tmp:
        copy = os.path.join(tmp, "measure.html")
        with open(copy, "w", encoding="utf-8") as f:
            f.write(page)
        cmd = browser_cmd(browser, os.path.join(tmp, "profile"), width, height)
        dom = subprocess.run(cmd + ["--dump-dom", "file://" + copy], capture_output=True, text=True, timeout=180).stdout
        if out_png:
            shot = os.path.join(tmp, "shot.html")
            with open(shot, "w", encoding="utf-8") as f:
                f.write(page.replace(MEASURE, ""))
            subprocess.run(cmd + [f"--screenshot={os.path.abspath(out_png)}", "file://" + shot],
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=180)
    found = re.search(r'<pre id="layout-measure">(.*?)</pre>', dom, re.S)
    if not found:
        return None
    text = found.group(1).replace("&quot;", '"').replace("&lt;", "<").replace("&gt;", ">").replace("&amp;", "&")
    return json.loads(text)


def compared_error(m):
    e = m.get("rel_error") if m.get("tolerance_kind") == "rel" else m.get("abs_error")
    return e if isinstance(e, (int, float)) else float("nan")


def headline_value(run, headline):
    """The largest compared error among the headline's metrics the run measured (counted ones),
    scaled as declared; None when it measured none."""
    best, best_err = None, -1.0
    for name in headline.get("metrics", []):
        m = run.get("metrics", {}).get(name)
        if m is None or m.get("informational"):
            continue
        err = compared_error(m)
        if best is not None and not err > best_err:
            continue
        best_err = err
        if headline.get("per_step"):
            best = m["abs_error"] / run["params"]["dt"]
        else:
            best = err * headline.get("scale", 1.0)
    return best


def cell_number(text):
    found = re.search(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?|inf|nan", text.replace("\u2212", "-"))
    return float(found.group(0)) if found else None


def check_cells(results, layout):
    problems, checked = [], 0
    heads = {s["name"]: s.get("headline") for s in results.get("scenarios", [])}
    runs = {(r["scenario"], r["engine"]): r for r in results["runs"]}
    engines = [e["name"] for e in results["context"]["engines"]]
    if [h.replace("\u00ad", "") for h in layout["headers"]] != engines:
        problems.append(f"the matrix's columns {layout['headers']} are not the configurations {engines}")
    scenarios = list(dict.fromkeys(r["scenario"] for r in results["runs"]))
    if [row["scenario"] for row in layout["rows"]] != scenarios:
        problems.append(f"the matrix's rows are not the scenarios {scenarios}")
    for row in layout["rows"]:
        sc = row["scenario"]
        head = heads.get(sc)
        if not head or not head.get("metrics"):
            problems.append(f"results.json declares no headline metric for {sc}")
            continue
        if any(n.startswith("lo_") for n in head["metrics"]):
            problems.append(f"{sc}: the headline names a check of the paper's approximation ({head['metrics']})")
        for eng, cell in zip(engines, row["cells"]):
            run = runs.get((sc, eng))
            if run is None:
                continue
            want = None if run["status"] in ("skip", "error") else headline_value(run, head)
            if want is None:
                if cell["value"] is not None:
                    problems.append(f"{sc} on {eng}: the cell shows {cell['value']} where the run has no headline figure")
                continue
            checked += 1
            if cell["metric"] not in head["metrics"]:
                problems.append(f"{sc} on {eng}: the cell's metric {cell['metric']} is not a headline metric {head['metrics']}")
            shown = cell_number(cell["text"])
            got = float(cell["value"]) if cell["value"] is not None else None
            if got is None or not math.isclose(got, want, rel_tol=1e-9, abs_tol=1e-300):
                problems.append(f"{sc} on {eng}: the cell's value {got} is not the headline {want}")
            elif shown is None or not math.isclose(shown, want, rel_tol=0.06, abs_tol=1e-300):
                problems.append(f"{sc} on {eng}: the cell shows {cell['text']!r}, the headline is {want:.3g}")
            if not (cell["href"] or "").endswith("#" + eng):
                problems.append(f"{sc} on {eng}: the cell links to {cell['href']}, not the engine's section")
    return problems, checked


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("folder")
    ap.add_argument("out_png")
    ap.add_argument("--width", type=int, default=1366)
    ap.add_argument("--height", type=int, default=768)
    ap.add_argument("--inject-css", default="", help="extra CSS (to show that a too wide matrix fails)")
    a = ap.parse_args()
    if not chromium():
        print("FAIL chromium is not installed (Debian package chromium)")
        print("0 passed, 1 failed")
        return 1
    with open(os.path.join(a.folder, "results.json")) as f:
        results = json.load(f)
    layout = measure(a.folder, a.width, a.height, a.inject_css, a.out_png)
    checks = []
    if layout is None or layout["matrix"] is None:
        checks.append((False, "the page has no summary matrix (#matrix) the browser could measure"))
    else:
        w, h, mx = layout["inner_width"], layout["inner_height"], layout["matrix"]
        checks.append((mx["right"] <= w and layout["scroll_width"] <= w,
                       f"matrix {mx['width']:.0f} px wide, right edge at {mx['right']:.0f} px, page {layout['scroll_width']} px wide; window {w} px"))
        checks.append((mx["bottom"] <= h, f"matrix bottom at {mx['bottom']:.0f} px; first screen {h} px high (window {a.width}x{a.height})"))
        cb = layout["counts"]
        checks.append((cb is not None and cb["bottom"] <= h, f"counts bottom at {cb['bottom']:.0f} px" if cb else "no counts (#counts)"))
        # The page a reader scrolls: at most 8 screens, the long tables folded (<details>), not dropped.
        checks.append((layout["page_height"] <= 8 * h, f"page {layout['page_height']} px tall, {layout['page_height'] / h:.1f} screens (at most 8)"))
        problems, checked = check_cells(results, layout)
        checks.append((not problems, f"{checked} cells show their scenario's headline metric" + "".join("\n  " + p for p in problems[:20])))
        print(f"page height {layout['page_height']} px; {len(layout['headers'])} configurations, {len(layout['rows'])} scenarios")
    for ok, what in checks:
        print(("PASS " if ok else "FAIL ") + what)
    failed = sum(not ok for ok, _ in checks)
    print(f"{len(checks) - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
