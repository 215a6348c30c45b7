#!/usr/bin/env python3
"""Reads the layout of a report's index.html in headless Chromium at 1366x768 and checks its first
screen: the summary matrix is no wider than the window, the whole matrix and the verdict counts lie
within the first screen, the whole page is at most 8 screens tall, every configuration has a row
with its counts and standing (its worst known failure) and every scenario a column, and each cell
shows the figure that decided it (the headline, or the failing metric's multiple of tolerance),
its multiple, a colour that darkens with the multiple on a log scale, and the negative control's
hatching, all computed here from results.json; and the whole report folder is at most 20 MB. Element sizes
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
  // What keeps an element from being seen as drawn, from it up to the page: filters, clipping,
  // opacity below 1, hidden or transparent text, a font too small to read. Empty: nothing.
  function seen(el) {
    var why = [], st = getComputedStyle(el);
    if (st.visibility !== 'visible') why.push('visibility ' + st.visibility);
    if (parseFloat(st.fontSize) < 7) why.push('font ' + st.fontSize);
    if (st.webkitTextFillColor && /rgba\(.*, 0\)$/.test(st.webkitTextFillColor)) why.push('text fill ' + st.webkitTextFillColor);
    for (var e = el; e && e.nodeType === 1; e = e.parentElement) {
      var s = getComputedStyle(e);
      if (s.filter !== 'none') why.push(e.tagName + ' filter ' + s.filter);
      if (parseFloat(s.opacity) < 1) why.push(e.tagName + ' opacity ' + s.opacity);
      if (s.clipPath !== 'none') why.push(e.tagName + ' clip-path ' + s.clipPath);
      if (s.display === 'none') why.push(e.tagName + ' display none');
    }
    return why;
  }
  var m = document.getElementById('matrix'), out = {
    inner_width: window.innerWidth, inner_height: window.innerHeight,
    scroll_width: document.documentElement.scrollWidth, page_height: document.documentElement.scrollHeight,
    matrix: box(m), counts: box(document.getElementById('counts')), headers: [], rows: []};
  if (m) {
    var ths = m.rows[0].cells;
    for (var i = 2; i < ths.length; ++i) out.headers.push(ths[i].querySelector('a').textContent);
    for (var r = 1; r < m.rows.length; ++r) {
      var row = m.rows[r], cells = [];
      for (var c = 2; c < row.cells.length; ++c) {
        var td = row.cells[c], a = td.querySelector('a');
        cells.push({metric: td.getAttribute('data-metric'), headline: td.getAttribute('data-headline'),
                    ratio: td.getAttribute('data-ratio'), cls: td.className,
                    background: getComputedStyle(td).backgroundColor,
                    background_image: getComputedStyle(td).backgroundImage,
                    ink: a ? getComputedStyle(a).color : null, visible: a ? getComputedStyle(a).visibility : null,
                    filter: seen(a || td),
                    text: td.textContent,
                    href: a ? a.getAttribute('href') : null, box: box(td)});
      }
      out.rows.push({configuration: row.cells[0].textContent, standing: row.cells[1].textContent,
                     standing_box: box(row.cells[1]), standing_scroll: row.cells[1].scrollWidth,
                     standing_client: row.cells[1].clientWidth, cells: cells});
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
    text = found.group(1).replace("&nbsp;", "\u00a0").replace("&quot;", '"').replace("&lt;", "<").replace("&gt;", ">").replace("&amp;", "&")
    return json.loads(text)


def compared_error(m):
    e = m.get("rel_error") if m.get("tolerance_kind") == "rel" else m.get("abs_error")
    return e if isinstance(e, (int, float)) else float("nan")


def headline_metric(run, headline):
    """The headline metric whose figure the cell shows: the largest compared error among the
    headline's metrics the run measured (counted ones); None when it measured none."""
    best, best_err = None, -1.0
    for name in headline.get("metrics", []):
        m = run.get("metrics", {}).get(name)
        if m is None or m.get("informational"):
            continue
        err = compared_error(m)
        if best is not None and not err > best_err:
            continue
        best, best_err = name, err
    return best


def headline_value(run, headline):
    """The headline metric's figure, scaled as declared; None when the run measured none."""
    name = headline_metric(run, headline)
    if name is None:
        return None
    m = run["metrics"][name]
    return m["abs_error"] / run["params"]["dt"] if headline.get("per_step") else compared_error(m) * headline.get("scale", 1.0)


def cell_numbers(text):
    """The numbers a cell shows, each with whether it is a multiple ("42x")."""
    out = []
    for found in re.finditer(r"([-+]?(?:\d+\.?\d*|\.\d+)(?:e[-+]?\d+)?|inf|nan)(\u00d7?)",
                             text.replace("\u2212", "-").replace("\u221e", "inf")):
        out.append((float(found.group(1)), found.group(2) == "\u00d7"))
    return out


def ratio_of(m):
    """A metric's error over its tolerance, at most its error over its floor (RecordView's ratio);
    a missing error (NaN) is infinite."""
    err, tol = compared_error(m), m.get("tolerance")
    if math.isnan(err):
        err = math.inf
    tol = tol if isinstance(tol, (int, float)) else math.inf
    r = err / tol if tol > 0 else (math.inf if err > 0 else 0.0)
    floor = m.get("floor") or 0
    if floor > 0:
        a = m.get("abs_error")
        r = min(r, (a if isinstance(a, (int, float)) else math.inf) / floor)
    return r


def multiple(run):
    """The largest finite multiple of tolerance among the run's counted metrics, and the failing
    metric that decided its verdict (largest finite multiple; a zero tolerance only when no other
    failed): (finite, (name, ratio) or None)."""
    finite, deciding = 0.0, None
    for name, m in run.get("metrics", {}).items():
        if m.get("informational"):
            continue
        r = ratio_of(m)
        if math.isfinite(r):
            finite = max(finite, r)
        if m.get("pass", True):
            continue
        if deciding is None or (math.isfinite(r) and (not math.isfinite(deciding[1]) or r > deciding[1])):
            deciding = (name, r)
    return finite, deciding


MARKS = {"pass": "\u2713", "known failure": "\u2717", "skip": "\u2013", "fail": "FAIL", "error": "ERROR",
         "unexpected pass": "UNEXP. PASS"}


def luminance(css):
    """The colour's darkness towards red: its luminance, or None when it is not a warm colour (a
    failure's scale runs from pale yellow to red: green or blue is off the scale)."""
    found = re.match(r"rgba?\((\d+), (\d+), (\d+)", css or "")
    if not found:
        return None
    r, g, b = (int(v) / 255 for v in found.groups())
    if not (r >= g >= b and r > 0.5):
        return None
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


def contrast(ink, background):
    """WCAG contrast ratio of two CSS colours (a transparent background is the white page)."""
    def rel(css, default):
        found = re.match(r"rgba?\((\d+), (\d+), (\d+)(?:, ([\d.]+))?", css or "")
        if not found or (found.group(4) is not None and float(found.group(4)) == 0):
            return default
        c = [int(v) / 255 for v in found.groups()[:3]]
        c = [v / 12.92 if v <= 0.03928 else ((v + 0.055) / 1.055) ** 2.4 for v in c]
        return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
    a, b = rel(ink, 0.0), rel(background, 1.0)
    return (max(a, b) + 0.05) / (min(a, b) + 0.05)


def verdict(run):
    return run.get("verdict", run["status"])


def check_cells(results, layout):
    """Each cell against results.json: the figure that decided it, its multiple, its colour."""
    problems, checked, shaded = [], 0, []
    heads = {s["name"]: s.get("headline") for s in results.get("scenarios", [])}
    controls = {s["name"] for s in results.get("scenarios", []) if s.get("negative_control")}
    runs = {(r["scenario"], r["engine"]): r for r in results["runs"]}
    engines = [e["name"] for e in results["context"]["engines"]]
    scenarios = list(dict.fromkeys(r["scenario"] for r in results["runs"]))
    if [h.replace("\u00ad", "") for h in layout["headers"]] != scenarios:
        problems.append(f"the matrix's columns {layout['headers']} are not the scenarios {scenarios}")
    if [row["configuration"].strip() for row in layout["rows"]] != engines:
        problems.append(f"the matrix's rows are not the configurations {engines}")
    for row in layout["rows"]:
        eng = row["configuration"].strip()
        for sc, cell in zip(scenarios, row["cells"]):
            run, head = runs.get((sc, eng)), heads.get(sc)
            if run is None:
                continue
            if not head or not head.get("metrics"):
                problems.append(f"results.json declares no headline metric for {sc}")
                continue
            checked += 1
            where = f"{sc} on {eng}"
            want_ratio, deciding = multiple(run)
            got_ratio = float(cell["ratio"]) if cell["ratio"] is not None else None
            if got_ratio is None or not math.isclose(got_ratio, want_ratio, rel_tol=1e-9, abs_tol=1e-300):
                problems.append(f"{where}: the cell's multiple {cell['ratio']} is not the run's largest finite one {want_ratio}")
            shown = cell_numbers(cell["text"])
            status = verdict(run)
            mark = MARKS.get(status if run.get("as_expected", True) or status != "known failure" else "fail")
            if not cell["text"].replace("\u00a0", " ").startswith(mark):
                problems.append(f"{where}: the cell reads {cell['text']!r}, its verdict is {status} ({mark})")
            if cell["ink"] in (None, "rgba(0, 0, 0, 0)") or cell["visible"] != "visible" or \
                    contrast(cell["ink"], cell["background"]) < 3 or cell["filter"]:
                problems.append(f"{where}: the cell cannot be seen as drawn (colour {cell['ink']}, {cell['visible']}; {', '.join(cell['filter'])})")
            want_head = None if run["status"] in ("skip", "error") else headline_value(run, head)
            if want_head is not None and (cell["headline"] is None or
                                          not math.isclose(float(cell["headline"]), want_head, rel_tol=1e-9, abs_tol=1e-300)):
                problems.append(f"{where}: the cell's headline {cell['headline']} is not {want_head}")
            failing = status in ("known failure", "fail", "unexpected pass") and deciding
            head_metric = headline_metric(run, head)
            if failing and deciding[0] != head_metric:
                # Another metric decided the verdict: the cell shows its multiple of tolerance.
                if cell["metric"] != deciding[0]:
                    problems.append(f"{where}: the cell names {cell['metric']}, the deciding metric is {deciding[0]}")
                if not any(is_mult and (math.isclose(v, deciding[1], rel_tol=0.06) or (math.isinf(deciding[1]) and math.isinf(v)))
                           for v, is_mult in shown):
                    problems.append(f"{where}: the cell shows {cell['text']!r}, the deciding multiple is {deciding[1]:.3g}x")
            elif want_head is not None:
                if cell["metric"] != head_metric:
                    problems.append(f"{where}: the cell's metric {cell['metric']} is not the headline's {head_metric}")
                if not any(not is_mult and math.isclose(v, want_head, rel_tol=0.06, abs_tol=1e-300) for v, is_mult in shown):
                    problems.append(f"{where}: the cell shows {cell['text']!r}, the headline is {want_head:.3g}")
            is_control = sc in controls and run.get("as_expected", True)
            hatched = "repeating-linear-gradient" in (cell["background_image"] or "")
            if is_control != ("neg" in cell["cls"].split()) or is_control != hatched:
                problems.append(f"{where}: {'a negative control not' if is_control else 'hatched as a negative control but not'} hatched as one")
            if (not run.get("as_expected", True)) != ("unexp" in cell["cls"].split()):
                problems.append(f"{where}: the cell's 'not as expected' mark disagrees with the run")
            if status == "known failure" and not is_control:
                shaded.append((want_ratio, luminance(cell["background"]), where))
            if not (cell["href"] or "").endswith("#" + eng):
                problems.append(f"{where}: the cell links to {cell['href']}, not the engine's section")
    # The colour grows with the multiple on a log scale: darker for a larger multiple, and a decade
    # apart visibly so (1x to 1e4x spans the scale).
    shaded.sort(key=lambda s: s[0])
    for (r0, l0, w0), (r1, l1, w1) in zip(shaded, shaded[1:]):
        if l0 is None or l1 is None:
            problems.append(f"{w0}: no background colour")
        elif l1 > l0 + 1e-6:
            problems.append(f"{w1} ({r1:.3g}x) is lighter than {w0} ({r0:.3g}x)")
    for (r0, l0, w0) in shaded:
        for (r1, l1, w1) in shaded:
            if 1 <= r0 and r1 >= 100 * r0 and r1 <= 1e4 and l0 is not None and l1 is not None and l0 - l1 < 0.08:
                problems.append(f"{w0} ({r0:.3g}x) and {w1} ({r1:.3g}x) look alike (luminance {l0:.2f}, {l1:.2f})")
                break
    return problems, checked


def check_standing(results, layout):
    """Each configuration's row: its counts and where it is furthest off, from results.json."""
    problems = []
    controls = {s["name"] for s in results.get("scenarios", []) if s.get("negative_control")}
    for row in layout["rows"]:
        eng = row["configuration"].strip()
        runs = [r for r in results["runs"] if r["engine"] == eng]
        expected = [r for r in runs if r.get("as_expected", True)]
        n_pass = sum(verdict(r) == "pass" for r in expected)
        n_known = sum(verdict(r) == "known failure" for r in expected)
        n_skip = sum(verdict(r) == "skip" for r in expected)
        text = row["standing"].replace("\u00a0", " ")
        unexpected = [r["scenario"] for r in runs if not r.get("as_expected", True)]
        if unexpected:
            if f"{len(unexpected)} not as expected" not in text or any(sc not in text for sc in unexpected):
                problems.append(f"{eng}: the standing {text!r} does not name its {len(unexpected)} unexpected runs")
            continue
        want = f"\u2713{n_pass} \u2717{n_known}" + (f" \u2013{n_skip}" if n_skip else "")
        if not text.startswith(want):
            problems.append(f"{eng}: the standing {text!r} does not start with its counts {want!r}")
        off = [r for r in expected if verdict(r) == "known failure" and r["scenario"] not in controls]
        if off:
            def rank(r):  # a run off only against a zero tolerance ranks last
                finite, deciding = multiple(r)
                return 0.0 if finite <= 1 and deciding and math.isinf(deciding[1]) else finite
            worst = max(off, key=rank)  # the first of equals, as the report takes it
            tail = text.split("worst", 1)[-1]
            shown = [v for v, is_mult in cell_numbers(tail) if is_mult]
            want = rank(worst)
            if want == 0 and worst["status"] == "error":
                good = "an error" in tail
            else:
                good = bool(shown) and (math.isclose(shown[0], want, rel_tol=0.06) or (want == 0 and math.isinf(shown[0])))
            if worst["scenario"] not in text or not good:
                problems.append(f"{eng}: the standing {text!r} is not its worst, {worst['scenario']} {want:.3g}x")
        if row["standing_scroll"] > row["standing_client"] + 1:
            problems.append(f"{eng}: the standing is cut off ({row['standing_scroll']} px of text in {row['standing_client']} px)")
    return problems


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
        checks.append((not problems, f"{checked} cells show the figure that decided them, coloured by their multiple of tolerance" + "".join("\n  " + p for p in problems[:20])))
        problems = check_standing(results, layout)
        checks.append((not problems, f"{len(layout['rows'])} configurations show their counts and standing" + "".join("\n  " + p for p in problems[:20])))
        print(f"page height {layout['page_height']} px; {len(layout['rows'])} configurations, {len(layout['headers'])} scenarios")
    # The whole report folder (pages, snapshots, plots, results.json): at most 20 MB.
    size = sum(os.path.getsize(os.path.join(d, f)) for d, _, files in os.walk(a.folder) for f in files)
    checks.append((size <= 20_000_000, f"report {size / 1e6:.1f} MB (at most 20)"))
    for ok, what in checks:
        print(("PASS " if ok else "FAIL ") + what)
    failed = sum(not ok for ok, _ in checks)
    print(f"{len(checks) - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
