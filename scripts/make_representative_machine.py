#!/usr/bin/env python3
"""Writes scenes/machine/*.csv: REPRESENTATIVE (not measured) geometric error tables for a CFXZAY profile grinder
with strokes X 900, Y 400, Z 800 mm, A ±45°, C 360°.

The seed paper's measured curves (its Figs. 5-9) are not available. These tables have typical magnitudes for an
uncompensated machine of this size - positioning a few µm per 100 mm, straightness a few µm, angular errors 10-40 µrad,
rotary radial and axial motion a few µm - and smooth shapes (trends, bows and a few low-order waves), as
laser-interferometer and ball-bar identification give them. They are NOT tuned to reproduce the paper's topology.
Squareness and axis-line location errors are constants in the default scene itself.

Run from the repository root:  python3 scripts/make_representative_machine.py
"""
import math
import os

OUT = os.path.join(os.path.dirname(__file__), "..", "scenes", "machine")
HEADER = "# REPRESENTATIVE geometric errors (not measured) - scripts/make_representative_machine.py\n"


def write(name, pos_col, positions, columns):
    path = os.path.join(OUT, name)
    with open(path, "w") as f:
        f.write(HEADER)
        f.write("# units: position column as named; delta_* in µm, epsilon_* in µrad\n")
        f.write(",".join([pos_col] + [c for c, _ in columns]) + "\n")
        for p in positions:
            f.write(",".join([f"{p:g}"] + [f"{fn(p):.4f}" for _, fn in columns]) + "\n")


def frange(a, b, step):
    n = int(round((b - a) / step))
    return [a + i * step for i in range(n + 1)]


s, c = math.sin, math.cos
pi = math.pi

# X: 0..900 mm, every 50 mm
write("x_axis.csv", "x_mm", frange(0, 900, 50), [
    ("delta_xx_um", lambda x: 0.020 * x + 0.6 * s(2 * pi * x / 250)),      # positioning 2 µm/100 mm + cyclic
    ("delta_yx_um", lambda x: 12.0 * (x / 900) * (1 - x / 900)),           # straightness bow, 3 µm
    ("delta_zx_um", lambda x: -2.5 * s(pi * x / 900)),                     # straightness, 2.5 µm
    ("epsilon_xx_urad", lambda x: 10.0 * s(2 * pi * x / 900)),             # roll
    ("epsilon_yx_urad", lambda x: 15.0 * (2 * x / 900 - 1)),               # pitch
    ("epsilon_zx_urad", lambda x: 20.0 * (x / 900) ** 2 - 8.0),            # yaw
])
# Y: -200..200 mm, every 25 mm
write("y_axis.csv", "y_mm", frange(-200, 200, 25), [
    ("delta_xy_um", lambda y: 1.5 * (1 - (y / 200) ** 2)),
    ("delta_yy_um", lambda y: 0.015 * (y + 200) + 0.3 * s(2 * pi * y / 100)),
    ("delta_zy_um", lambda y: -1.2 * (y / 200) ** 2),
    ("epsilon_xy_urad", lambda y: 12.0 * (y / 200)),
    ("epsilon_yy_urad", lambda y: 6.0 * c(pi * y / 400)),
    ("epsilon_zy_urad", lambda y: -10.0 * (y / 200) + 4.0),
])
# Z: 0..800 mm, every 50 mm
write("z_axis.csv", "z_mm", frange(0, 800, 50), [
    ("delta_xz_um", lambda z: 4.0 * s(pi * z / 800)),                       # straightness 4 µm
    ("delta_yz_um", lambda z: -3.0 * (z / 800) ** 2),
    ("delta_zz_um", lambda z: 0.025 * z + 0.5 * s(2 * pi * z / 200)),      # positioning 2.5 µm/100 mm
    ("epsilon_xz_urad", lambda z: 12.0 * (z / 800) - 6.0),
    ("epsilon_yz_urad", lambda z: 25.0 * s(pi * z / 800) - 10.0),
    ("epsilon_zz_urad", lambda z: -15.0 * (z / 800)),
])
# A: -45..45 deg, every 5 deg
write("a_axis.csv", "a_deg", frange(-45, 45, 5), [
    ("delta_xa_um", lambda a: 2.0 * s(math.radians(a))),
    ("delta_ya_um", lambda a: 1.5 * (a / 45)),
    ("delta_za_um", lambda a: 1.0 * (1 - c(math.radians(2 * a)))),
    ("epsilon_xa_urad", lambda a: 20.0 * (a / 45)),                         # A positioning
    ("epsilon_ya_urad", lambda a: 8.0 + 4.0 * (a / 45) ** 2),
    ("epsilon_za_urad", lambda a: -6.0 * (a / 45) ** 2),
])
# C: 0..360 deg, every 10 deg, periodic (first and last rows equal)
write("c_axis.csv", "c_deg", frange(0, 360, 10), [
    ("delta_xc_um", lambda g: 3.0 * c(math.radians(g)) + 0.8 * c(math.radians(2 * g))),   # radial motion
    ("delta_yc_um", lambda g: 3.0 * s(math.radians(g)) + 0.6 * s(math.radians(3 * g))),
    ("delta_zc_um", lambda g: 1.5 * s(math.radians(2 * g))),                                # axial motion
    ("epsilon_xc_urad", lambda g: 8.0 * s(math.radians(g))),                                # tilt motion
    ("epsilon_yc_urad", lambda g: 8.0 * c(math.radians(g))),
    ("epsilon_zc_urad", lambda g: 15.0 * s(math.radians(g)) + 5.0 * s(math.radians(2 * g) + 1.0)),  # indexing
])
print("wrote", OUT)
