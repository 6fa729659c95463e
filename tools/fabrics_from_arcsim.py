#!/usr/bin/env python3
"""Atelier fabric presets from the material files of Wang, O'Brien & Ramamoorthi 2011.

    python3 tools/fabrics_from_arcsim.py DIR [--prefix wang-]

DIR holds ARCSim material files (<name>.json with "density", "stretching" 6x4 and "bending"
3x5), the published parameters of "Data-driven elastic models for cloth: modeling and
measurement" (SIGGRAPH 2011). Prints one preset per file in the form of
assets/materials/fabrics.json's "presets". What each table means and why B = k_e/4:
docs/decisions/035-measured-presets-wang-2011.md. Standard library only.

Per direction (weft = the material's u, warp = v):
- small-strain 2D modulus and Poisson ratio from the zero-strain row (k0, k1, k2, k3):
  E_weft = 2(k0 - k1^2/k2), E_warp = 2(k2 - k1^2/k0), nu = k1/k2, shear = k3/2; a negative k1
  (the knits) is taken as 0, since our orthotropic law takes nu >= 0;
- the stiffening law (a knee strain and the modulus beyond it) fitted by least squares to the
  uniaxial tension of their model, T(G) = 2(k0(s) - k1(s)^2/k2(s)) G with the stiffness
  interpolated linearly in the principal stretch s from the zero-strain row to the row at
  s = 1/6 along that direction (constant beyond), over Green strains 0 to 0.2;
- bending rigidity B = k_e/4 at zero curvature from the rows of edges along u (warp strips),
  at 45 degrees (bias) and along v (weft strips).
"""

import argparse
import json
import math
import pathlib
import sys

GREEN_MAX = 0.2  # fit range of Green strain (about 18% stretch)
SAMPLES = 201


def stiffness_at(rows, direction, s):
    """(k0, k1, k2, k3) at principal stretch s along `direction` (1 = 0 deg, 5 = 90 deg)."""
    w = min(max(6.0 * s, 0.0), 1.0)
    return [a + (b - a) * w for a, b in zip(rows[0], rows[direction])]


def uniaxial_modulus(k, along):
    k0, k1, k2, _ = k
    k1 = max(k1, 0.0)
    return 2.0 * (k0 - k1 * k1 / k2) if along == "weft" else 2.0 * (k2 - k1 * k1 / k0)


def tension(rows, along, green):
    """Their uniaxial tension [N/m] at Green strain `green` along weft or warp."""
    s = math.sqrt(1.0 + 2.0 * green) - 1.0
    k = stiffness_at(rows, 1 if along == "weft" else 5, s)
    return uniaxial_modulus(k, along) * green


def biphasic(e_small, knee, beyond, green):
    return e_small * green + (beyond - e_small) * max(green - knee, 0.0)


GREENS = [GREEN_MAX * i / (SAMPLES - 1) for i in range(SAMPLES)]


def rms(rows, along, e_small, knee, beyond):
    """Root-mean-square departure of the biphasic law from their tension over GREENS [N/m]."""
    err = sum((biphasic(e_small, knee, beyond, g) - tension(rows, along, g)) ** 2 for g in GREENS)
    return math.sqrt(err / SAMPLES)


def beyond_at(rows, along, e_small, knee):
    """Least-squares modulus beyond a given knee (the law is linear in it), never below e_small."""
    num = den = 0.0
    for g in GREENS:
        h = max(g - knee, 0.0)
        num += h * (tension(rows, along, g) - e_small * g)
        den += h * h
    return e_small + (max(num / den, 0.0) if den > 0 else 0.0)


def fit_knee(rows, along, e_small):
    """Least-squares knee over a grid; 0 when stiffening does not pay."""
    best = (rms(rows, along, e_small, 0.0, e_small), 0.0)
    for j in range(1, 200):
        knee = GREEN_MAX * j / 200
        err = rms(rows, along, e_small, knee, beyond_at(rows, along, e_small, knee))
        if err < best[0]:
            best = (err, knee)
    return best[1]


def preset(name, data):
    rows = data["stretching"]
    _, k1, k2, k3 = rows[0]
    e_small = {"weft": uniaxial_modulus(rows[0], "weft"),
               "warp": uniaxial_modulus(rows[0], "warp")}
    # One knee for both directions (the engine's law): the earlier of the two fitted apart,
    # with the moduli beyond it refitted.
    knees_apart = [fit_knee(rows, along, e_small[along]) for along in ("weft", "warp")]
    knee = min((k for k in knees_apart if k > 0), default=0.0)
    bending = data["bending"]
    b_warp, b_bias, b_weft = (row[0] / 4.0 for row in bending)
    out = {
        "density_kg_per_m2": data["density"],
        "stretch_weft_n_per_m": round(e_small["weft"], 3),
        "stretch_warp_n_per_m": round(e_small["warp"], 3),
        "shear_n_per_m": round(k3 / 2.0, 3),
        "poisson": round(max(k1, 0.0) / k2, 4),
        "bending_n_m": float(f"{math.sqrt(b_weft * b_warp):.4g}"),
        "bending_weft_n_m": float(f"{b_weft:.4g}"),
        "bending_warp_n_m": float(f"{b_warp:.4g}"),
        "bending_bias_n_m": float(f"{b_bias:.4g}"),
    }
    fit = {"knees": knees_apart}
    if knee > 0:
        out["stretch_knee_strain"] = round(knee, 4)
    for along in ("weft", "warp"):
        key = f"stretch_{along}_beyond_n_per_m"
        beyond = beyond_at(rows, along, e_small[along], knee) if knee > 0 else e_small[along]
        if beyond > e_small[along]:
            out[key] = round(beyond, 3)
        fit["linear_rms_" + along] = rms(rows, along, e_small[along], 0.0, e_small[along])
        # How far the law written departs from their tension.
        fit["rms_" + along] = rms(rows, along, e_small[along], knee, out.get(key, e_small[along]))
    return out, fit


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dir", type=pathlib.Path)
    parser.add_argument("--prefix", default="wang-")
    args = parser.parse_args()
    files = sorted(args.dir.glob("*.json"))
    if not files:
        sys.exit(f"fabrics_from_arcsim: no material files (*.json) in {args.dir}")
    presets = {}
    for path in files:
        try:
            data = json.loads(path.read_text())
            entry, fit = preset(path.stem, data)
        except (KeyError, IndexError, TypeError, ValueError, ZeroDivisionError) as e:
            sys.exit(f"fabrics_from_arcsim: {path}: not an ARCSim material file ({e})")
        presets[args.prefix + path.stem] = entry
        print(f"{path.stem}: tension fit rms weft {fit['rms_weft']:.3g} N/m "
              f"(linear {fit['linear_rms_weft']:.3g}), warp {fit['rms_warp']:.3g} N/m "
              f"(linear {fit['linear_rms_warp']:.3g}); knees fitted apart {fit['knees'][0]:.3f} "
              f"{fit['knees'][1]:.3f}", file=sys.stderr)
    json.dump(presets, sys.stdout, indent=2)
    print()


if __name__ == "__main__":
    main()
