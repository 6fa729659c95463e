#!/usr/bin/env python3
"""The drape's speed against its error: each solver setting draped to rest, against a reference.

    tools/drape_work_precision.py assets/garments/tshirt.atelier --particle-distance 20 \
        --out work-precision.csv --plot work-precision.svg

Drapes the project once as a reference with a small step and a tight linear solve (--ref-dt,
--ref-cg-tolerance), then once per setting of a sweep over the step (--dts), the conjugate
gradients' tolerance (--cg-tolerances) and the preconditioner (--solvers), each to rest (or to
the project's time limit) with `atelier-cli drape`. Every run meshes the same pattern at the
same particle distance, so the draped garments (written with `--split-panels`, each panel's
own vertices, whatever the seams welded) have the same vertices in the same order; a row's error is the RMS and the largest distance of its
vertices from the reference's [m]. The work is the report's wall time and, repeatable on any
machine, its steps and conjugate-gradient iterations. A drape that does not come to rest, does
not close its seams or ends with intersecting pairs says so in its row. Python's standard
library only: the error is measured from the written meshes, not taken from Atelier.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

from obj_triangles import read_obj

COLUMNS = ["setting", "dt_s", "cg_tolerance", "linear_solver", "wall_s", "steps",
           "cg_iterations", "rested_at_s", "rms_error_m", "max_error_m", "seam_gap_max_m",
           "intersecting_pairs", "status"]


def drape(cli, project, settings, particle_distance, threads, folder, name):
    """Drapes `project` with its `simulation` updated by `settings`; (report, vertices)."""
    with open(project, encoding="utf-8") as f:
        document = json.load(f)
    document.setdefault("simulation", {}).update(settings)
    path = os.path.join(folder, name + ".atelier")
    with open(path, "w", encoding="utf-8") as f:
        json.dump(document, f)
    obj = os.path.join(folder, name + ".obj")
    report = os.path.join(folder, name + ".json")
    command = [cli, "drape", path, "--out", obj, "--split-panels", "--report", report,
               "--threads", str(threads)]
    if particle_distance:
        command += ["--particle-distance", str(particle_distance)]
    run = subprocess.run(command, capture_output=True, text=True, check=False)
    if not os.path.exists(report):
        sys.exit(f"{name}: atelier-cli drape wrote no report (exit {run.returncode}):\n"
                 + run.stderr)
    with open(report, encoding="utf-8") as f:
        result = json.load(f)
    vertices = read_obj(obj)[0] if os.path.exists(obj) else None
    return result, vertices


def errors(vertices, reference):
    """RMS and largest distance between corresponding vertices [m]."""
    if vertices is None or len(vertices) != len(reference):
        return None, None
    squares = [sum((a - b) ** 2 for a, b in zip(p, q)) for p, q in zip(vertices, reference)]
    return math.sqrt(sum(squares) / len(squares)), math.sqrt(max(squares))


def plot(rows, path, title):
    """Log-log SVG: RMS error against wall time, one colour per preconditioner."""
    points = [r for r in rows if r["rms_error_m"] not in ("", None) and r["rms_error_m"] > 0]
    if not points:
        return
    width, height, margin = 640, 420, 60
    xs = [math.log10(r["wall_s"]) for r in points]
    ys = [math.log10(r["rms_error_m"]) for r in points]
    x0, x1 = math.floor(min(xs)), math.ceil(max(xs) + 1e-9)
    y0, y1 = math.floor(min(ys)), math.ceil(max(ys) + 1e-9)
    x1, y1 = max(x1, x0 + 1), max(y1, y0 + 1)

    def at(x, y):
        return (margin + (x - x0) / (x1 - x0) * (width - 2 * margin),
                height - margin - (y - y0) / (y1 - y0) * (height - 2 * margin))

    colours = {"block-jacobi": "#1f77b4", "block-ic0": "#d62728"}
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
           f'font-family="sans-serif" font-size="11">',
           f'<rect width="{width}" height="{height}" fill="white"/>',
           f'<text x="{width / 2}" y="20" text-anchor="middle" font-size="13">'
           f'{escape(title)}</text>']
    for e in range(x0, x1 + 1):
        x, _ = at(e, y0)
        out.append(f'<line x1="{x:.1f}" y1="{margin}" x2="{x:.1f}" y2="{height - margin}" '
                   f'stroke="#ddd"/><text x="{x:.1f}" y="{height - margin + 16}" '
                   f'text-anchor="middle">1e{e} s</text>')
    for e in range(y0, y1 + 1):
        _, y = at(x0, e)
        out.append(f'<line x1="{margin}" y1="{y:.1f}" x2="{width - margin}" y2="{y:.1f}" '
                   f'stroke="#ddd"/><text x="{margin - 6}" y="{y + 4:.1f}" '
                   f'text-anchor="end">1e{e} m</text>')
    out.append(f'<text x="{width / 2}" y="{height - 18}" text-anchor="middle">wall time to '
               f'rest</text><text x="14" y="{height / 2}" text-anchor="middle" '
               f'transform="rotate(-90 14 {height / 2})">RMS distance from the reference</text>')
    for r, x, y in zip(points, xs, ys):
        px, py = at(x, y)
        colour = colours.get(r["linear_solver"], "#555")
        fill = colour if r["status"] == "clean" else "white"
        out.append(f'<circle cx="{px:.1f}" cy="{py:.1f}" r="4" fill="{fill}" '
                   f'stroke="{colour}"/><text x="{px + 6:.1f}" y="{py - 5:.1f}" '
                   f'font-size="9">{r["dt_s"] * 1000:g} ms, {r["cg_tolerance"]:g}</text>')
    legend_x, legend_y = margin + 10, height - margin - 50
    for k, (name, colour) in enumerate(colours.items()):
        out.append(f'<circle cx="{legend_x}" cy="{legend_y + 14 * k}" r="4" fill="{colour}"/>'
                   f'<text x="{legend_x + 10}" y="{legend_y + 4 + 14 * k}">{name}</text>')
    out.append(f'<text x="{legend_x - 4}" y="{legend_y + 32}" font-size="9">labels: step, CG '
               f'tolerance; hollow: not clean</text></svg>')
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(out) + "\n")


def escape(text):
    return (str(text).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
            .replace('"', "&quot;"))


def status(report):
    """'clean', or what is wrong with the drape."""
    problems = []
    if not report.get("rested"):
        problems.append("not at rest")
    if report.get("seam_gap_max_m", 0) > 0:
        problems.append(f"seam gap {report['seam_gap_max_m'] * 1000:.1f} mm")
    if report.get("intersecting_triangle_pairs", 0) > 0:
        problems.append(f"{report['intersecting_triangle_pairs']} intersecting pairs")
    if report.get("error"):
        problems.append(str(report["error"]))
    return "; ".join(problems) if problems else "clean"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("project")
    parser.add_argument("--cli", default="atelier-cli", help="the atelier-cli to run")
    parser.add_argument("--particle-distance", type=float, help="[mm] (default: the project's)")
    parser.add_argument("--threads", type=int, default=1, help="engine threads of every run")
    parser.add_argument("--dts", type=float, nargs="+", default=[0.02, 0.01, 0.005, 0.0025],
                        help="steps of the sweep [s]")
    parser.add_argument("--cg-tolerances", type=float, nargs="+", default=[1e-3, 1e-4],
                        help="conjugate-gradient tolerances of the sweep")
    parser.add_argument("--solvers", nargs="+", default=["block-jacobi", "block-ic0"])
    parser.add_argument("--ref-dt", type=float, default=0.0025, help="the reference's step [s]")
    parser.add_argument("--ref-cg-tolerance", type=float, default=1e-6)
    parser.add_argument("--ref-time-limit", type=float, default=10,
                        help="the reference's simulated time limit [s]: a small step damps "
                             "less, and the reference must come to rest")
    parser.add_argument("--out", required=True, help="CSV of the runs")
    parser.add_argument("--plot", help="SVG: RMS error against wall time")
    args = parser.parse_args()

    with tempfile.TemporaryDirectory() as folder:
        reference, ref_vertices = drape(
            args.cli, args.project, {"dt_s": args.ref_dt, "cg_tolerance": args.ref_cg_tolerance,
                                     "linear_solver": "block-jacobi",
                                     "time_limit_s": args.ref_time_limit},
            args.particle_distance, args.threads, folder, "reference")
        if ref_vertices is None:
            sys.exit("the reference drape wrote no mesh")
        if status(reference) != "clean":
            print(f"warning: the reference is not clean ({status(reference)})", file=sys.stderr)
        print(f"reference: dt {args.ref_dt} s, CG tolerance {args.ref_cg_tolerance}: "
              f"{status(reference)}, {reference['wall_time_s']:.1f} s wall, "
              f"{reference['steps']} steps", flush=True)
        rows = []
        for solver in args.solvers:
            for tolerance in args.cg_tolerances:
                for dt in args.dts:
                    name = f"{solver} dt {dt * 1000:g} ms tol {tolerance:g}"
                    report, vertices = drape(
                        args.cli, args.project,
                        {"dt_s": dt, "cg_tolerance": tolerance, "linear_solver": solver},
                        args.particle_distance, args.threads, folder, f"run{len(rows)}")
                    rms, largest = errors(vertices, ref_vertices)
                    row = {"setting": name, "dt_s": dt, "cg_tolerance": tolerance,
                           "linear_solver": solver, "wall_s": report.get("wall_time_s"),
                           "steps": report.get("steps"),
                           "cg_iterations": report.get("cg_iterations"),
                           "rested_at_s": report.get("sim_time_to_rest_s") or "",
                           "rms_error_m": rms if rms is not None else "",
                           "max_error_m": largest if largest is not None else "",
                           "seam_gap_max_m": report.get("seam_gap_max_m"),
                           "intersecting_pairs": report.get("intersecting_triangle_pairs"),
                           "status": status(report)}
                    rows.append(row)
                    print(f"{name}: {row['wall_s']:.2f} s wall, {row['steps']} steps, "
                          f"{row['cg_iterations']} CG iterations, RMS "
                          f"{rms if rms is not None else float('nan'):.2e} m, "
                          f"{row['status']}", flush=True)
    with open(args.out, "w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=COLUMNS, lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    if args.plot:
        at = f" at {args.particle_distance:g} mm" if args.particle_distance else ""
        plot(rows, args.plot, f"{os.path.basename(args.project)}{at}: drape to rest, against "
                              f"dt {args.ref_dt * 1000:g} ms, CG {args.ref_cg_tolerance:g}")


if __name__ == "__main__":
    main()
