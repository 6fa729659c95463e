#!/usr/bin/env python3
"""Checks `atelier-cli export-pattern` with tools that share no code with it: every sample
garment's pattern parses with Python's XML parser (sizes in mm, a viewBox of as many units, one
group per panel), and librsvg (`rsvg-convert`) draws it at 1 pixel a millimetre into a picture
of the sheet's size in which the 100 mm calibration square's sides are drawn where the SVG
puts them and its inside is empty.

Usage: check_pattern_svg.py ATELIER_CLI GARMENTS_DIR WORK_DIR
Exit 0: all checked; 1: a check failed; 77 (skipped): the XML checks passed but rsvg-convert
is not installed (packaging/install-deps.sh installs it).
"""
import os
import shutil
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET
import zlib

SVG = "{http://www.w3.org/2000/svg}"


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def read_png(path):
    """Width, height and rows of RGBA bytes of an 8-bit RGBA PNG (what rsvg-convert writes)."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        fail(path + ": not a PNG")
    pos, idat, width, height = 8, b"", 0, 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
            if depth != 8 or colour != 6:
                fail(path + ": expected 8-bit RGBA, got depth %d colour type %d" % (depth, colour))
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride, rows, prev = width * 4, [], bytearray(width * 4)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - 4] if x >= 4 else 0
            b = prev[x]
            c = prev[x - 4] if x >= 4 else 0
            if kind == 1:
                line[x] = (line[x] + a) & 255
            elif kind == 2:
                line[x] = (line[x] + b) & 255
            elif kind == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return width, height, rows


def main():
    if len(sys.argv) != 4:
        fail(__doc__)
    cli, garments, work = sys.argv[1:4]
    os.makedirs(work, exist_ok=True)
    rsvg = shutil.which("rsvg-convert")
    samples = sorted(f for f in os.listdir(garments) if f.endswith(".atelier"))
    if len(samples) != 4:
        fail("expected the 4 sample garments in %s, found %s" % (garments, samples))
    for sample in samples:
        svg_path = os.path.join(work, sample.replace(".atelier", ".svg"))
        run = subprocess.run([cli, "export-pattern", os.path.join(garments, sample), "--out", svg_path],
                             capture_output=True, text=True)
        if run.returncode != 0:
            fail("%s: export-pattern exited %d: %s" % (sample, run.returncode, run.stderr))
        root = ET.parse(svg_path).getroot()
        if root.tag != SVG + "svg":
            fail("%s: root element %s" % (sample, root.tag))
        width, height = root.get("width"), root.get("height")
        if not (width.endswith("mm") and height.endswith("mm")):
            fail("%s: size %s x %s is not in mm" % (sample, width, height))
        w, h = float(width[:-2]), float(height[:-2])
        if [float(v) for v in root.get("viewBox").split()] != [0, 0, w, h]:
            fail("%s: viewBox %s for %s x %s" % (sample, root.get("viewBox"), width, height))
        panels = [g for g in root.iter(SVG + "g") if g.get("class") == "panel"]
        if not panels:
            fail(sample + ": no panel groups")
        square = next(g for g in root.iter(SVG + "g") if g.get("id") == "calibration")
        d = square.find(SVG + "path").get("d").replace("M", "").replace("L", "").replace("Z", "").split()
        x0, y0 = float(d[0]), float(d[1])
        print("%s: %d panels, %s x %s, calibration square at (%g, %g)" % (sample, len(panels), width, height, x0, y0))
        if rsvg is None:
            continue
        png = svg_path + ".png"
        # 25.4 dots per inch: one pixel a millimetre.
        subprocess.run([rsvg, "--dpi-x", "25.4", "--dpi-y", "25.4", "-o", png, svg_path], check=True)
        pw, ph, rows = read_png(png)
        # librsvg rounds the size in inches up to whole pixels: 1391 mm can give 1392 px.
        if abs(pw - w) > 1 or abs(ph - h) > 1:
            fail("%s: rsvg-convert drew %d x %d px at 1 px/mm for %s x %s" % (sample, pw, ph, width, height))

        def alpha(x, y):
            return rows[int(y)][int(x) * 4 + 3]

        for name, (x, y) in {"top": (x0 + 30, y0), "bottom": (x0 + 30, y0 + 100), "left": (x0, y0 + 30),
                             "right": (x0 + 100, y0 + 30)}.items():
            # The 0.3 mm line covers part of the pixel it crosses (or of its neighbour).
            if max(alpha(x, y), alpha(x - (name in ("left", "right")), y - (name in ("top", "bottom")))) == 0:
                fail("%s: the calibration square's %s side is not drawn at (%g, %g)" % (sample, name, x, y))
        for x, y in [(x0 + 10, y0 + 10), (x0 + 90, y0 + 90), (x0 + 10, y0 + 90)]:
            if alpha(x, y) != 0:
                fail("%s: ink inside the calibration square at (%g, %g)" % (sample, x, y))
    if rsvg is None:
        print("SKIP: rsvg-convert is not installed (librsvg2-bin); the XML checks passed")
        sys.exit(77)
    print("OK")


if __name__ == "__main__":
    main()
