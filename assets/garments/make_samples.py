#!/usr/bin/env python3
"""Writes the sample garments (tshirt, skirt, trousers, dress) as .atelier projects.

The patterns are drafted here from a few dimensions (millimetres) so that they can be changed
in one place; `atelier-cli project format` (or any load -> save) gives the canonical file.
Run: python3 assets/garments/make_samples.py
"""
import json
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def line(x, y):
    return {"line": {"from": [x, y]}}


def cubic(x, y, c1, c2):
    return {"cubic": {"from": [x, y], "c1": list(c1), "c2": list(c2)}}


def quad(x, y, c1):
    return {"quadratic": {"from": [x, y], "c1": list(c1)}}


def edge(panel, segment, t0=0.0, t1=1.0):
    return {"panel": panel, "segment": segment, "t0": t0, "t1": t1}


def seam(name, a, b):
    return {"name": name, "a": a, "b": b}


def panel(name, outline, slot, offset=(0, 0), material="fabric", side="front",
          clearance=20, rotation=0, **extra):
    p = {"name": name, "material": material, "side": side, "grain_deg": 90,
         "outline": outline, "holes": [], "internal_lines": [], "darts": [], "notches": [],
         "placement": {"slot": slot, "offset_mm": list(offset), "rotation_deg": rotation,
                       "clearance_mm": clearance}}
    p.update(extra)
    return p


def project(name, panels, seams, fabric, simulation=None):
    # Sewing: gravity waits 1 s while the seams (elastics, τ = 30 ms) pull the panels shut
    # around the body; pairs closer than 1.5 mm weld for good.
    # 10 ms implicit steps: 3x fewer than the engine's default and more numerical damping,
    # which a drape to rest wants.
    sim = {"particle_distance_mm": 10, "dt_s": 0.01, "sewing_time_s": 1.0,
           "seam_weld_distance_mm": 1.5, "time_limit_s": 4}
    sim.update(simulation or {})
    return {"format": "atelier-project", "version": 1, "name": name,
            "body": {"base": "female", "measurements": {}},
            "materials": [{"name": "fabric", "fabric": fabric}],
            "panels": panels, "seams": seams, "simulation": sim}


def torso(neck_drop, length, half_width=260, hem_half=None, armhole_y=None):
    """Front or back bodice outline, counter-clockwise from the hem's left corner.

    Segments: 0 hem, 1 right side, 2 right armhole, 3 right shoulder, 4 neckline,
    5 left shoulder, 6 left armhole, 7 left side. y = 0 at the hem.
    """
    w = half_width
    hw = hem_half if hem_half is not None else w
    ay = armhole_y if armhole_y is not None else length - 210
    sy = length - 35        # shoulder point height
    ny = length             # neck side height
    sx, nx = 185, 100       # shoulder point, neck side
    return [
        line(-hw, 0),
        line(hw, 0),
        cubic(w, ay, (w - 40, ay + 20), (sx + 5, ay + 110)),
        line(sx, sy),
        quad(nx, ny, (0, ny - 2.0 * neck_drop)),
        line(-nx, ny),
        cubic(-sx, sy, (-sx - 5, ay + 110), (-w + 40, ay + 20)),
        line(-w, ay),
    ]


def tshirt():
    length = 620
    # Slot origins sit at the default body's waist (y = 1.05 m); the shoulder points
    # (585 mm above the hem) go 3 cm above its shoulder top (1.37 m), so the shoulder seams
    # close over the shoulders rather than against them. The hem flares to clear the hips.
    # The armholes reach 250 mm below the neck side (370 mm above the hem) and are 470 mm round,
    # front and back together, against the arm's 370 mm girth at the shoulder: a woven's
    # armhole ease. At 210 mm deep and 392 mm round (a knit's, no ease) the jersey drape
    # closed, but in the woven presets the sleeve's underarm corner and the bodice's met in a
    # tangle at the armpit that the end-of-sewing welds could not undo (10 mm: cotton, denim,
    # polyester and silk 19-80 intersecting pairs), and the 20 mm jersey kept a 26 mm fin
    # open at the shoulder.
    armhole_y = length - 250
    front = panel("front", torso(90, length, hem_half=285, armhole_y=armhole_y),
                  "torso_front", offset=(0, 75))
    back = panel("back", torso(25, length, hem_half=285, armhole_y=armhole_y),
                 "torso_back", offset=(0, 75))
    # Sleeve: hem at y = 0, underarm seams up to y = 70, a cap to the top at y = 170. The cap
    # is 469 mm round, as long as the armhole within a millimetre (no gathers); the sleeve is
    # 420 mm round at the underarm. A cap much longer than its
    # armhole (433 mm against 392 once) gathered in and curled the bodice's armhole corner
    # between the two sides of the side seam. A low cap also suits the A-pose, the arm held
    # 45 degrees from the body.
    sw, sh, cap = 210, 70, 170
    sleeve = [
        line(-sw, 0),
        line(sw, 0),
        cubic(sw, sh, (sw - 60, sh + 10), (60, cap)),
        cubic(0, cap, (-60, cap), (-sw + 60, sh + 10)),
        line(-sw, sh),
    ]
    # Segment 2 of the sleeve starts at (sw, sh): the underarm end of the cap's +x half.
    # Arm slots start at the shoulder joint and run down the arm: the cap top 70 mm below it,
    # clear of the shoulder.
    left = panel("sleeve_left", sleeve, "arm_left", offset=(0, -70 - cap / 2))
    right = panel("sleeve_right", sleeve, "arm_right", offset=(0, -70 - cap / 2))
    seams = [
        # Side seams: the front's right side (world +x) meets the back's left side.
        seam("side_left", [edge("front", 1)], [edge("back", 7, 1, 0)]),
        seam("side_right", [edge("front", 7)], [edge("back", 1, 1, 0)]),
        seam("shoulder_left", [edge("front", 3)], [edge("back", 5, 1, 0)]),
        seam("shoulder_right", [edge("front", 5)], [edge("back", 3, 1, 0)]),
        seam("underarm_left", [edge("sleeve_left", 1)], [edge("sleeve_left", 4, 1, 0)]),
        seam("underarm_right", [edge("sleeve_right", 1)], [edge("sleeve_right", 4, 1, 0)]),
        # Caps run underarm -> top -> underarm; each armhole edge is taken in that order
        # (the +x half of the left sleeve lies at the back of the arm, of the right sleeve at
        # the front).
        seam("armhole_left",
             [edge("sleeve_left", 2), edge("sleeve_left", 3)],
             [edge("back", 6, 1, 0), edge("front", 2, 1, 0)]),
        seam("armhole_right",
             [edge("sleeve_right", 2), edge("sleeve_right", 3)],
             [edge("front", 6, 1, 0), edge("back", 2, 1, 0)]),
    ]
    return project("tshirt", [front, back, left, right], seams, "jersey-knit")


def skirt():
    # A-line on the default body (waist 0.70 m at 1.05 m, hip 0.97 m 170 mm below it): waist
    # about 770 mm around, 1.12 m at the hip line 200 mm below the waist, hem 1500 mm around,
    # 595 mm long. Ease counts the contact layer: cloth resting 4 mm off the body (both
    # thicknesses) spans a girth 25 mm longer than the body's, and a 720 mm waist left its
    # side seams 16-18 mm open at the end of sewing. The hip curve leaves the waist vertically and the waist line rises towards
    # the sides, so each side seam meets the waist at a right angle and front and back join
    # in a smooth waist line (an A-line side slanted at the waist, as this sample had, left a
    # point at the top of each side seam that the sewn waist stretched by up to 90%).
    waist_half, hip_half, hem_half, length, hip_depth = 190, 280, 375, 595, 200
    hip_y = length - hip_depth
    outline = [
        quad(-hem_half, 0, (0, -40)),                                   # 0 hem
        line(hem_half, 0),                                              # 1 right side, A-line
        cubic(hip_half, hip_y, (hip_half - 15, hip_y + 58),             # 2 right hip curve
              (waist_half + 2, length - 55)),
        quad(waist_half, length, (0, length - 30)),                     # 3 waist, 15 mm lower at the centre
        cubic(-waist_half, length, (-waist_half - 2, length - 55),      # 4 left hip curve
              (-hip_half + 15, hip_y + 58)),
        line(-hip_half, hip_y),                                         # 5 left side
    ]
    # The waist line at the body's waist (the slot's origin); 60 mm clearance so that the
    # flared hems of front and back do not overlap at the sides when placed.
    front = panel("front", outline, "waist_front", offset=(0, -300), clearance=60)
    back = panel("back", outline, "waist_back", offset=(0, -300), clearance=60)
    seams = [
        seam("side_left", [edge("front", 1)], [edge("back", 5, 1, 0)]),
        seam("hip_left", [edge("front", 2)], [edge("back", 4, 1, 0)]),
        seam("hip_right", [edge("front", 4)], [edge("back", 2, 1, 0)]),
        seam("side_right", [edge("front", 5)], [edge("back", 1, 1, 0)]),
    ]
    return project("skirt", [front, back], seams, "cotton")


def dress():
    length = 1000
    front = panel("front", torso(80, length, half_width=250, hem_half=330,
                                 armhole_y=length - 230), "torso_front", offset=(0, -115),
                  clearance=60)
    back = panel("back", torso(30, length, half_width=250, hem_half=330,
                               armhole_y=length - 230), "torso_back", offset=(0, -115),
                 clearance=60)
    seams = [
        seam("side_left", [edge("front", 1)], [edge("back", 7, 1, 0)]),
        seam("side_right", [edge("front", 7)], [edge("back", 1, 1, 0)]),
        seam("shoulder_left", [edge("front", 3)], [edge("back", 5, 1, 0)]),
        seam("shoulder_right", [edge("front", 5)], [edge("back", 3, 1, 0)]),
    ]
    # Its shoulder straps take longer to close than 1 s (at 10 mm they were welded across 5 cm
    # and tore there; with 2 s, 37 mm).
    return project("dress", [front, back], seams, "cotton",
                   {"sewing_time_s": 2.0, "time_limit_s": 5})


def trousers():
    """Four panels (front and back of each leg), sewn at the outer sides, the inseams and the
    centre front and back (crotch) seams.

    Each panel is drawn as seen from outside with its side seam on the body's outer side;
    y = 0 at the hem. Segments: 0 hem, 1 outer side (hem to hip), 2 side (hip to waist),
    3 waist, 4 centre (waist down to the crotch curve), 5 crotch curve, 6 inseam.
    Drawn for the body's left leg (outer side = +x); the right leg's panels are mirrored
    copies. The default body's waist is at 1.05 m and its crotch at 0.77 m; the crotch point
    (360 mm below the waistline) is placed 7 cm below the body's crotch. With 30 mm less
    rise, placed 4 cm below, the hip seams' tops stayed 10-14 mm open at the end of sewing
    and at 10 mm one welded pair was pulled 17 mm apart again.
    """
    length, crotch_y, hip_y = 960, 600, 770

    def leg(hip_w, waist_w, ext, hem_w):
        # Centre line at x = 0; the outer side at +x; the crotch extends to x = -ext.
        return [
            line(-ext + 40, 0),                                   # 0 hem (inner to outer)
            line(hem_w - ext + 40, 0),                            # 1 outer side seam
            cubic(hip_w, hip_y, (hip_w + 8, hip_y + 60),         # 2 hip to waist
                  (waist_w + 2, length - 60)),
            line(waist_w, length),                                # 3 waist
            line(0, length),                                      # 4 centre seam
            cubic(0, crotch_y + 90, (0, crotch_y + 20), (-ext * 0.5, crotch_y)),  # 5 crotch
            line(-ext, crotch_y),                                 # 6 inseam
        ]

    front_ext, back_ext = 50, 100
    # The hip curve leaves the waist at a right angle, as the skirt's does, so front and back
    # join in a smooth waist line; with the curve slanted in at 132° to the waist the sewn
    # waist had a point at the top of each hip seam, and its top pairs stalled 8-11 mm apart
    # (welded at the end of sewing; 2.5 mm with this curve).
    # Front and back take the same steps in from the hip (100 mm to the waist, 100 mm to the
    # hem's outer corner), so their side seams have the same length: with the back 15-50 mm
    # wider there, the drape warned of outseams 5 mm and hip curves 6 mm apart. The hip
    # widths give the seat its ease: the body measures 0.97 m round the hips but 1.07 m a
    # little lower, round the seat and the tops of the thighs (y = 0.80 m), and with 30 mm
    # less per panel the trousers ended sewing with the centre back, the outseams and the
    # inseams 10-25 mm open there, held by the fabric's tension.
    front = leg(hip_w=285, waist_w=185, ext=front_ext, hem_w=195)
    back = leg(hip_w=300, waist_w=200, ext=back_ext, hem_w=260)
    # Each panel goes on its leg's slot, which follows the leg and above the crotch the half
    # of the pelvis on its side, so the panels start around their own leg with the inseams
    # side by side at the inner leg. Placement centres the panel's bounding box on the slot's
    # facing: shift it so the crease (the hem's middle) faces front or back. The back slot's
    # "right" is the body's right, so the left leg's back panel is the mirrored one. The
    # crotch point (y = crotch_y) goes 7 cm below the slot's origin (the body's crotch). The
    # right leg's panels sit 15 mm further out than the left's: the two legs' surfaces cross
    # at the centre, and this puts the crossing beyond the left panels' centre edges, so the
    # panels never start through each other there. The back panels' crotch extension wraps
    # round the inner thigh below the crotch, where the two legs' surfaces overlap: with the
    # crease at the slot's facing the two extensions started through each other (55
    # intersecting triangle pairs; 2 at 25 mm), so the back panels sit 40 mm further round
    # towards the outer side.
    def crease_shift(hip_w, ext, hem_w):
        bbox_centre = (hip_w + 2 - ext) / 2   # (the hip curve reaches < 1 mm past hip_w)
        return bbox_centre - (-ext + 40 + hem_w / 2)

    fs = crease_shift(285, front_ext, 195)
    bs = crease_shift(300, back_ext, 260) + 40
    down = -70 - (crotch_y - length / 2)
    panels = [
        panel("front_left", front, "leg_left_front", offset=(fs, down), side="front"),
        panel("front_right", front, "leg_right_front", offset=(-fs, down), side="back",
              clearance=35),
        panel("back_left", back, "leg_left_back", offset=(-bs, down), side="back"),
        panel("back_right", back, "leg_right_back", offset=(bs, down), side="front",
              clearance=35),
    ]
    seams = [
        # Outer sides in two seams, hem to hip and hip to waist, so both sides have a vertex
        # at the hip point (one seam over both would space the front's vertices by the
        # back's lengths and leave a sliver at the front's hip corner).
        seam("outseam_left", [edge("front_left", 1)], [edge("back_left", 1)]),
        seam("hip_left", [edge("front_left", 2)], [edge("back_left", 2)]),
        seam("outseam_right", [edge("front_right", 1)], [edge("back_right", 1)]),
        seam("hip_right", [edge("front_right", 2)], [edge("back_right", 2)]),
        seam("inseam_left", [edge("front_left", 6)], [edge("back_left", 6)]),
        seam("inseam_right", [edge("front_right", 6)], [edge("back_right", 6)]),
        seam("centre_front", [edge("front_left", 4), edge("front_left", 5)],
             [edge("front_right", 4), edge("front_right", 5)]),
        seam("centre_back", [edge("back_left", 4), edge("back_left", 5)],
             [edge("back_right", 4), edge("back_right", 5)]),
    ]
    return project("trousers", panels, seams, "denim")


def main():
    for name, make in (("tshirt", tshirt), ("skirt", skirt), ("dress", dress),
                       ("trousers", trousers)):
        path = os.path.join(HERE, name + ".atelier")
        with open(path, "w") as f:
            json.dump(make(), f, indent=2)
            f.write("\n")
        print("wrote", path)


if __name__ == "__main__":
    main()
