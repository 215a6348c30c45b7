#!/usr/bin/env python3
"""Opens a report's index.html in headless Chromium, saves a screenshot, and checks that it shows
the summary matrix: the matrix's pass colour (#c6efce) covers a visible area of the page.
Usage: screenshot_check.py REPORT_DIR OUT_PNG"""
import os
import shutil
import subprocess
import sys
import tempfile
import zlib


def png_rgb_rows(path):
    """Decodes an 8-bit RGB or RGBA PNG with the standard library (zlib), returning rows of bytes."""
    with open(path, "rb") as f:
        data = f.read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, width = 8, b"", 0
    while pos < len(data):
        length = int.from_bytes(data[pos:pos + 4], "big")
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height = int.from_bytes(body[:4], "big"), int.from_bytes(body[4:8], "big")
            depth, ctype = body[8], body[9]
            assert depth == 8 and ctype in (2, 6), "expects 8-bit RGB(A)"
            bpp = 3 if ctype == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride, rows, prev = width * bpp, [], bytearray(width * bpp)
    for y in range(height):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append((bytes(line), bpp))
        prev = line
    return rows


def main(folder, out_png):
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if not browser:
        print("FAIL chromium is not installed (Debian package chromium)")
        print("0 passed, 1 failed")
        return 1
    index = os.path.abspath(os.path.join(folder, "index.html"))
    with tempfile.TemporaryDirectory() as profile:
        cmd = [browser, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
               "--disable-background-networking", "--disable-component-update", "--disable-sync",
               f"--user-data-dir={profile}", "--hide-scrollbars", "--window-size=1280,1400",
               f"--screenshot={os.path.abspath(out_png)}", "file://" + index]
        subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=180)
    if not os.path.isfile(out_png):
        print("FAIL no screenshot written")
        print("0 passed, 1 failed")
        return 1
    green = 0
    for line, bpp in png_rgb_rows(out_png):
        for x in range(0, len(line), bpp):
            r, g, b = line[x], line[x + 1], line[x + 2]
            green += abs(r - 0xC6) < 6 and abs(g - 0xEF) < 6 and abs(b - 0xCE) < 6
    ok = green > 5000
    print(f"{'PASS' if ok else 'FAIL'} screenshot {out_png}: {green} pixels of the matrix's pass colour")
    print(f"{1 if ok else 0} passed, {0 if ok else 1} failed")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
