#!/usr/bin/env python3
"""Robustness sweep of assets/scenes/hard/through-body.json: the sheet entering the torso at
four depths, three heights and two resolutions (24 variants). Runs each with atelier-cli and
prints, per variant, cloth-body pairs, all intersecting pairs, max edge strain at the end.

Usage: tools/through_body_variants.py [path/to/atelier-cli] (default build/release/app/atelier-cli)
"""
import json
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
cli = sys.argv[1] if len(sys.argv) > 1 else str(ROOT / "build/release/app/atelier-cli")
base = json.loads((ROOT / "assets/scenes/hard/through-body.json").read_text())
passed = clean_body = total = 0
with tempfile.TemporaryDirectory() as tmp:
    for x0 in (-0.1, -0.05, 0.0, 0.05):           # sheet edge inside the 0.15 m torso
        for height in (1.1, 1.25, 0.75):           # middle, top and bottom of the cylinder
            for cells in ((32, 24), (48, 36)):
                scene = json.loads(json.dumps(base))
                cloth = scene["cloths"][0]
                cloth["placement"]["origin"][0] = x0
                cloth["placement"]["origin"][1] = height
                cloth["mesh"]["cells"] = list(cells)
                name = f"x{x0:+.2f}_y{height:.2f}_{cells[0]}"
                path = pathlib.Path(tmp) / f"{name}.json"
                path.write_text(json.dumps(scene))
                report = pathlib.Path(tmp) / f"{name}.report.json"
                subprocess.run([cli, "simulate", str(path), "--report", str(report),
                                "--out", str(pathlib.Path(tmp) / f"{name}.obj")],
                               check=True, capture_output=True)
                r = json.loads(report.read_text())
                body = r["intersecting_pairs_with_obstacles"]
                pairs = r["intersecting_triangle_pairs"]
                strain = r["max_edge_strain"]
                ok = body == 0 and pairs == 0 and strain < 0.1 and r["finite"]
                total += 1
                clean_body += body == 0
                passed += ok
                print(f"{name:22s} body pairs {body:4d}  all pairs {pairs:4d}  strain {strain:7.3f}"
                      f"  {'pass' if ok else 'FAIL'}", flush=True)
print(f"{clean_body}/{total} without cloth-body pairs, {passed}/{total} pass every check")
