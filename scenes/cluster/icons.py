# The cluster's telltale icons as meshes: each drawn in a 1 x 1 box centred on the origin and
# scaled by s. Shapes follow the ISO 2575 symbols closely enough to be recognised at 36 px; they
# are not traced drawings. Used by build.py (the telltale row and the small gauges' symbols).
# Imported by build.py, which puts scenes/tools (bscene) on the path first.
import math

import bscene as b


def arrow_icon(mb, s, left):
    sign = -1.0 if left else 1.0
    pts = [(-0.1, -0.16), (0.12, -0.16), (0.12, -0.34), (0.46, 0.0), (0.12, 0.34), (0.12, 0.16),
           (-0.1, 0.16)]
    pts = [(sign * (x - 0.0) * s, y * s) for x, y in pts]
    if left:
        pts.reverse()
    # Arrow body as shaft (quad) + head (triangle) keeps every face convex.
    shaft = [pts[0], pts[1], pts[5], pts[6]] if not left else [pts[6], pts[5], pts[1], pts[0]]
    head = [pts[2], pts[3], pts[4]] if not left else [pts[4], pts[3], pts[2]]
    mb.poly(shaft)
    mb.poly(head)
    mb.rect(-0.42 * s, -0.16 * s, -0.1 * s, 0.16 * s, offset=(0.0 if not left else 0.52 * s, 0, 0))


def lamp_icon(mb, s, beams):
    """Headlamp: a D shape (half disc facing right), beams to its left."""
    mb.disc(0.24 * s, 12, a0=-math.pi / 2, a1=math.pi / 2, offset=(0.12 * s, 0, 0))
    mb.rect(0.06 * s, -0.24 * s, 0.13 * s, 0.24 * s)
    for i, (y, dy) in enumerate(beams):
        y0 = y * s
        mb.poly([(-0.42 * s, y0 + dy * s - 0.03 * s), (-0.02 * s, y0 - 0.03 * s),
                 (-0.02 * s, y0 + 0.03 * s), (-0.42 * s, y0 + dy * s + 0.03 * s)])


def circle_bracket_icon(mb, s, text):
    """Brake-style symbol: ring, text inside, two outer arcs (ISO 2575 K.14 family)."""
    mb.ring(0.25 * s, 0.31 * s, 24)
    mb.ring(0.38 * s, 0.44 * s, 8, a0=math.radians(130), a1=math.radians(230))
    mb.ring(0.38 * s, 0.44 * s, 8, a0=math.radians(-50), a1=math.radians(50))
    mb.text(text, 0.34 * s if len(text) == 1 else 0.2 * s)


def person_icon(mb, s):
    mb.disc(0.09 * s, 12, offset=(-0.1 * s, 0.3 * s, 0))
    mb.poly([(-0.22 * s, -0.15 * s), (0.02 * s, -0.15 * s), (0.02 * s, 0.18 * s),
             (-0.2 * s, 0.18 * s)])
    mb.poly([(0.02 * s, -0.15 * s), (0.25 * s, -0.15 * s), (0.25 * s, -0.06 * s),
             (0.02 * s, -0.06 * s)])
    mb.poly([(0.18 * s, -0.15 * s), (0.26 * s, -0.15 * s), (0.26 * s, -0.42 * s),
             (0.18 * s, -0.42 * s)])


def airbag_icon(mb, s):
    person_icon(mb, s)
    mb.disc(0.16 * s, 16, offset=(0.28 * s, 0.12 * s, 0))


def seatbelt_icon(mb, s):
    person_icon(mb, s)
    mb.poly([(-0.2 * s, 0.12 * s), (-0.14 * s, 0.18 * s), (0.12 * s, -0.2 * s),
             (0.06 * s, -0.26 * s)], z=0.002)


def oil_icon(mb, s):
    mb.rect(-0.3 * s, -0.16 * s, 0.12 * s, 0.1 * s)
    mb.poly([(0.12 * s, -0.02 * s), (0.44 * s, 0.12 * s), (0.44 * s, 0.18 * s),
             (0.12 * s, 0.1 * s)])
    mb.rect(-0.12 * s, 0.1 * s, -0.04 * s, 0.2 * s)
    mb.rect(-0.2 * s, 0.2 * s, 0.04 * s, 0.25 * s)
    mb.disc(0.05 * s, 8, offset=(0.44 * s, -0.05 * s, 0))


def battery_icon(mb, s):
    mb.rect(-0.38 * s, -0.24 * s, 0.38 * s, -0.18 * s)
    mb.rect(-0.38 * s, 0.14 * s, 0.38 * s, 0.2 * s)
    mb.rect(-0.38 * s, -0.24 * s, -0.32 * s, 0.2 * s)
    mb.rect(0.32 * s, -0.24 * s, 0.38 * s, 0.2 * s)
    mb.rect(-0.28 * s, 0.2 * s, -0.16 * s, 0.28 * s)
    mb.rect(0.16 * s, 0.2 * s, 0.28 * s, 0.28 * s)
    mb.text("-  +", 0.22 * s, offset=(0, -0.02 * s, 0))


def engine_icon(mb, s):
    mb.rect(-0.26 * s, -0.22 * s, 0.22 * s, 0.16 * s)
    mb.rect(-0.14 * s, 0.16 * s, 0.1 * s, 0.22 * s)
    mb.rect(-0.2 * s, 0.22 * s, 0.16 * s, 0.27 * s)
    mb.rect(-0.4 * s, -0.1 * s, -0.26 * s, 0.06 * s)
    mb.rect(0.22 * s, -0.06 * s, 0.34 * s, 0.02 * s)
    mb.poly([(0.34 * s, -0.2 * s), (0.44 * s, -0.2 * s), (0.44 * s, 0.2 * s),
             (0.34 * s, 0.1 * s)])


def esc_icon(mb, s):
    mb.rect(-0.3 * s, 0.04 * s, 0.3 * s, 0.2 * s)
    mb.poly([(-0.18 * s, 0.2 * s), (0.16 * s, 0.2 * s), (0.1 * s, 0.34 * s),
             (-0.12 * s, 0.34 * s)])
    mb.disc(0.06 * s, 8, offset=(-0.18 * s, 0.04 * s, 0))
    mb.disc(0.06 * s, 8, offset=(0.18 * s, 0.04 * s, 0))
    for side in (-1, 1):
        # Skid marks: two S-like zigzags under the car.
        x = side * 0.14 * s
        mb.poly([(x - 0.03 * s, -0.06 * s), (x + 0.03 * s, -0.06 * s), (x + 0.09 * s, -0.22 * s),
                 (x + 0.03 * s, -0.22 * s)])
        mb.poly([(x + 0.03 * s, -0.22 * s), (x + 0.09 * s, -0.22 * s), (x + 0.03 * s, -0.4 * s),
                 (x - 0.03 * s, -0.4 * s)])


def tpms_icon(mb, s):
    mb.ring(0.26 * s, 0.32 * s, 16, a0=math.radians(-230), a1=math.radians(50))
    mb.rect(-0.3 * s, -0.32 * s, 0.3 * s, -0.26 * s)
    mb.text("!", 0.32 * s)


def fuel_pump_icon(mb, s):
    mb.rect(-0.32 * s, -0.4 * s, 0.12 * s, 0.36 * s)
    mb.rect(0.12 * s, 0.1 * s, 0.3 * s, 0.16 * s)
    mb.rect(0.26 * s, -0.3 * s, 0.32 * s, 0.16 * s)
    mb.rect(-0.22 * s, 0.08 * s, 0.02 * s, 0.26 * s, z=0.002)


def thermometer_icon(mb, s):
    mb.rect(-0.05 * s, -0.2 * s, 0.05 * s, 0.4 * s)
    mb.disc(0.12 * s, 12, offset=(0, -0.26 * s, 0))
    for y in (0.3, 0.16, 0.02):
        mb.rect(0.05 * s, y * s - 0.02 * s, 0.2 * s, y * s + 0.02 * s)
    for side in (-1, 1):
        mb.rect(side * 0.42 * s - 0.12 * s, -0.42 * s, side * 0.42 * s + 0.12 * s, -0.38 * s)


def front_fog_icon(mb, s):
    lamp_icon(mb, s, [(0.14, 0.0), (0.0, 0.0), (-0.14, 0.0)])
    mb.poly([(-0.27 * s, -0.3 * s), (-0.22 * s, -0.3 * s), (-0.2 * s, 0.3 * s),
             (-0.25 * s, 0.3 * s)], z=0.002)


# Each telltale's icon, drawn into a MeshBuilder at size s.
ICONS = {
    "TurnLeft": lambda mb, s: arrow_icon(mb, s, True),
    "TurnRight": lambda mb, s: arrow_icon(mb, s, False),
    "HighBeam": lambda mb, s: lamp_icon(mb, s, [(0.18, 0.0), (0.06, 0.0), (-0.06, 0.0), (-0.18, 0.0)]),
    "LowBeam": lambda mb, s: lamp_icon(mb, s, [(0.14, -0.14), (0.02, -0.14), (-0.1, -0.14), (-0.22, -0.14)]),
    "FrontFog": front_fog_icon,
    "ParkingBrake": lambda mb, s: circle_bracket_icon(mb, s, "P"),
    "BrakeFault": lambda mb, s: circle_bracket_icon(mb, s, "!"),
    "ABS": lambda mb, s: circle_bracket_icon(mb, s, "ABS"),
    "Airbag": airbag_icon,
    "SeatBelt": seatbelt_icon,
    "OilPressure": oil_icon,
    "Battery": battery_icon,
    "CheckEngine": engine_icon,
    "ESC": esc_icon,
    "TPMS": tpms_icon,
    "FuelLow": fuel_pump_icon,
    "CoolantTemp": thermometer_icon,
}


def telltale_mesh(name, s):
    if name not in ICONS:
        raise ValueError(f"no icon for telltale {name}")
    mb = b.MeshBuilder()
    ICONS[name](mb, s)
    return mb
