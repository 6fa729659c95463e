#!/usr/bin/env python3
"""The desktop application end to end, without a display: opens a project, drapes it for a
fraction of a second, saves the window (atelier --screenshot) and checks the picture: the
pattern view on the left shows the panels, the 3D view on the right the garment on its body.
The PNG is decoded here (zlib + the five PNG filters) so the check does not trust Qt's reader.

    check_screenshot.py ATELIER PROJECT OUT.png
Exit 77 (skipped) when the machine has no EGL for the 3D view.
"""
import struct
import subprocess
import sys
import zlib


def read_png(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, width, height, ctype = 8, b"", 0, 0, 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, ctype = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and ctype in (2, 6), f"unsupported PNG: depth {depth} type {ctype}"
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    bpp = 3 if ctype == 2 else 4
    raw = zlib.decompress(idat)
    stride = width * bpp
    rows, prev = [], bytearray(stride)
    for y in range(height):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return width, height, bpp, rows


def main():
    app, project, out = sys.argv[1:4]
    run = subprocess.run([app, project, "--screenshot", out, "--drape-seconds", "0.1"],
                         capture_output=True, text=True, timeout=540)
    print(run.stdout + run.stderr)
    if run.returncode != 0:
        if "EGL" in run.stdout + run.stderr:
            print("SKIP: no EGL for the 3D view")
            return 77
        print(f"FAIL: atelier exited {run.returncode}")
        return 1
    width, height, bpp, rows = read_png(out)
    print(f"{out}: {width}x{height}")

    def share(x0, x1, test):
        n = hits = 0
        for y in range(height // 8, height * 7 // 8, 2):
            row = rows[y]
            for x in range(int(x0 * width), int(x1 * width), 2):
                r, g, b = row[x * bpp], row[x * bpp + 1], row[x * bpp + 2]
                n += 1
                hits += 1 if test(r, g, b) else 0
        return hits / max(n, 1)

    red = lambda r, g, b: r > g + 40 and r > b + 40      # the front panel (panelColour(0))
    blue = lambda r, g, b: b > r + 40                     # the back panel (panelColour(1))
    grey = lambda r, g, b: r > 150 and abs(r - g) < 20 and abs(r - b) < 30 and r < 236  # body
    checks = [
        ("pattern view: front panel", share(0.0, 0.37, red), 0.05),
        ("pattern view: back panel", share(0.0, 0.37, blue), 0.05),
        ("3D view: garment", share(0.4, 1.0, red), 0.01),
        ("3D view: body", share(0.4, 1.0, grey), 0.01),
    ]
    ok = True
    for name, value, least in checks:
        print(f"{name}: {100 * value:.1f}% of the region (at least {100 * least:.0f}%)")
        ok = ok and value >= least
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
