# The production-like instrument cluster: 1280x480, speedometer 0-260 km/h and tachometer
# 0-8000 rpm with 3D needles driven by authored animations (frame k = value k), fuel and coolant
# gauges, gear / odometer / trip / outside-temperature / digital-speed text anchors, 17 telltales
# in ISO 2575 / UN R121 colours, a normal-mapped dial face, chrome rings, KHR_lights_punctual.
#
# World layout (Blender, Z up; the camera looks down -Z): 1 unit = 100 px on the z = 0 plane,
# origin at the frame centre (pixel 640, 240). Everything the driver reads faces +Z.
#
# Run:  blender -b --factory-startup --python-exit-code 1 --python build.py -- OUTDIR [--render]
import math
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import bpy  # noqa: E402
import numpy as np  # noqa: E402
import bscene as b  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import features as fx  # noqa: E402
from icons import fuel_pump_icon, telltale_mesh, thermometer_icon  # noqa: E402

WIDTH, HEIGHT, FPS = 1280, 480, 24
CAM_Z = 20.0
# 12.8 units across at z = 0 from 20 units away: lens = sensor * distance / width.
LENS_MM = 36.0 * CAM_Z / 12.8

SPEEDO = dict(name="Speedo", center=(-3.75, 0.05), radius=2.2, vmax=260, major=20, minor=10,
              label_every=20, sweep=240.0, start=-120.0, anim="SpeedNeedle", red_from=None,
              unit="km/h", label_scale=1)
TACHO = dict(name="Tacho", center=(3.75, 0.05), radius=2.2, vmax=8000, major=1000, minor=250,
             label_every=1000, sweep=240.0, start=-120.0, anim="RpmNeedle", red_from=6500,
             unit="x1000 rpm", label_scale=1000)
RPM_PER_FRAME = 100  # tachometer: 1 frame = 100 rpm -> frames 0..80

# Small gauges in the bottom gap of each main dial: 100 deg sweep centred on straight up.
FUEL = dict(name="Fuel", center=(-3.75, -1.45), radius=0.62, vmin=0, vmax=100, anim="FuelNeedle",
            labels={0: "E", 50: "1/2", 100: "F"}, red_to=12.5, red_from=None)
COOLANT = dict(name="Coolant", center=(3.75, -1.45), radius=0.62, vmin=50, vmax=130,
               anim="CoolantNeedle", labels={50: "C", 90: "90", 130: "H"}, red_to=None, red_from=115)
SMALL_SWEEP = 100.0

# Telltale colours (ISO 2575 / UN R121 Table 2): red = danger, amber = warning/malfunction,
# green = function on, blue = high beam. Linear RGB, used as the emissive "on" colour.
RED = (1.0, 0.02, 0.01)
AMBER = (1.0, 0.45, 0.0)
GREEN = (0.0, 0.9, 0.12)
BLUE = (0.0, 0.25, 1.0)

# (node suffix, catalog signal suffix, colour, position (x, y))
TELLTALES = [
    ("TurnLeft", "TurnLeft", GREEN, (-1.25, 2.0)),
    ("LowBeam", "LowBeam", GREEN, (-0.45, 2.0)),
    ("HighBeam", "HighBeam", BLUE, (0.0, 2.0)),
    ("FrontFog", "FrontFog", GREEN, (0.45, 2.0)),
    ("TurnRight", "TurnRight", GREEN, (1.25, 2.0)),
    ("ParkingBrake", "ParkingBrake", RED, (-1.25, -1.6)),
    ("BrakeFault", "BrakeFault", RED, (-0.75, -1.6)),
    ("Airbag", "Airbag", RED, (-0.25, -1.6)),
    ("SeatBelt", "SeatBelt", RED, (0.25, -1.6)),
    ("OilPressure", "OilPressure", RED, (0.75, -1.6)),
    ("Battery", "Battery", RED, (1.25, -1.6)),
    ("ABS", "ABS", AMBER, (-1.25, -2.1)),
    ("ESC", "ESC", AMBER, (-0.75, -2.1)),
    ("CheckEngine", "CheckEngine", AMBER, (-0.25, -2.1)),
    ("TPMS", "TPMS", AMBER, (0.25, -2.1)),
    ("FuelLow", "FuelLow", AMBER, (0.75, -2.1)),
    ("CoolantTemp", "CoolantTemp", RED, (1.25, -2.1)),
]
# Telltales that must light when their source is lost (a silent safety lamp is the dangerous
# failure; UN R13-H / R94 expect brake, ABS, ESC and airbag lamps to show a fault).
FAILSAFE_ON = {"BrakeFault", "ABS", "ESC", "Airbag"}


def screen_rot(deg_cw_from_up):
    # Camera looks down -Z with +Y up on screen: +rotation about Z is counter-clockwise.
    return math.radians(-deg_cw_from_up)


def polar(center, r, deg_cw_from_up):
    a = math.radians(deg_cw_from_up)
    return (center[0] + r * math.sin(a), center[1] + r * math.cos(a))


# ---------------------------------------------------------------- materials

def dial_normal_map(size=256):
    """A turned-aluminium 'sunburst' relief: concentric grooves, 16 per face radius (8 px per
    period at 256 px: finer grooves alias into moire and make the PNG incompressible; 256 px
    keeps the committed .glb small). Height h(r, phi); normal = normalize(-dh/dx, -dh/dy, 1),
    encoded as (n + 1) / 2 in tangent space (+X = u, +Y = v), the glTF convention."""
    t = (np.arange(size, dtype=np.float64) + 0.5) / size * 2.0 - 1.0
    x, y = np.meshgrid(t, t)  # row 0 is v = 0 (bottom), as Blender stores images
    r = np.sqrt(x * x + y * y)
    phi = np.arctan2(y, x)
    k = 2.0 * np.pi * 16.0
    amp = 0.0012  # slope amplitude amp*k ~ 0.12: a sheen, not ripples
    dh_dr = amp * k * np.cos(k * r)
    # Chain rule for a radial height field: dh/dx = cos(phi) dh/dr, dh/dy = sin(phi) dh/dr.
    dhdx = np.cos(phi) * dh_dr
    dhdy = np.sin(phi) * dh_dr
    n = np.stack([-dhdx, -dhdy, np.ones_like(r)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    rgba = np.concatenate([(n + 1.0) * 0.5, np.ones((size, size, 1))], axis=-1)
    return b.image_from_rgb("DialFaceNormal", size, size, rgba.astype(np.float32).ravel())


def dial_face_material(normal_img):
    mat = b.principled("DialFace", base=(0.018, 0.02, 0.024), metallic=0.6, roughness=0.35)
    nt = mat.node_tree
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = normal_img
    tex.interpolation = "Linear"
    nmap = nt.nodes.new("ShaderNodeNormalMap")
    nmap.space = "TANGENT"
    nmap.uv_map = "UVMap"
    nmap.inputs["Strength"].default_value = 1.0
    nt.links.new(tex.outputs["Color"], nmap.inputs["Color"])
    nt.links.new(nmap.outputs["Normal"], nt.nodes["Principled BSDF"].inputs["Normal"])
    return mat


# ---------------------------------------------------------------- pieces

def needle(name, center, length, tail, width, z, mat, anim_name, frames_values, angle_of):
    """A 3D needle: a tapered blade with a raised spine (a flat strip would vanish edge-on under
    a tilted camera), rest pose pointing +Y, pivot at the object origin. The action is keyed at
    the first and last frame with linear interpolation; the exporter samples every frame."""
    hw, tw, h = width / 2, width * 0.18, width * 0.45
    # Cross-section: left edge, spine, right edge along y; the tip narrows to tw.
    verts = [(-hw, -tail, 0), (0, -tail, h), (hw, -tail, 0),
             (-tw, length, 0), (0, length, h * 0.5), (tw, length, 0),
             (0, -tail, 0), (0, length, 0)]
    faces = [(0, 3, 4, 1), (1, 4, 5, 2), (0, 1, 2, 6), (3, 7, 5, 4), (0, 6, 7, 3), (6, 2, 5, 7)]
    obj = b.mesh_from_data(name, verts, faces, mat)
    obj.location = (center[0], center[1], z)
    obj.rotation_mode = "XYZ"
    for frame, value in frames_values:
        obj.rotation_euler = (0.0, 0.0, screen_rot(angle_of(value)))
        obj.keyframe_insert("rotation_euler", index=2, frame=frame)
    obj.animation_data.action.name = anim_name
    b.set_linear(obj.animation_data.action)
    obj.rotation_euler = (0.0, 0.0, screen_rot(angle_of(frames_values[0][1])))
    return obj


def chrome_ring(name, center, r_major, r_minor, mat):
    # No UVs: the ring is untextured, and UVs would make the exporter emit tangents for it.
    bpy.ops.mesh.primitive_torus_add(major_radius=r_major, minor_radius=r_minor,
                                     major_segments=72, minor_segments=8, generate_uvs=False,
                                     location=(center[0], center[1], 0.0))
    obj = bpy.context.active_object
    obj.name = name
    obj.data.name = name
    b.assign(obj, mat)
    bpy.ops.object.shade_smooth()
    return obj


def hub(name, center, r, z, mat):
    bpy.ops.mesh.primitive_cylinder_add(vertices=24, radius=r, depth=0.06, end_fill_type="TRIFAN",
                                        calc_uvs=False, location=(center[0], center[1], z))
    obj = bpy.context.active_object
    obj.name = name
    obj.data.name = name
    b.assign(obj, mat)
    return obj


def main_dial(d, mats, normal_mat):
    cx, cy = d["center"]
    R = d["radius"]
    angle = lambda v: d["start"] + d["sweep"] * v / d["vmax"]  # noqa: E731
    face = b.disc(f"{d['name']}_Face", R, 96, mat=normal_mat, location=(cx, cy, 0.0))
    b.planar_uv(face, -R, -R, 2 * R, 2 * R)
    chrome_ring(f"{d['name']}_Ring", (cx, cy), R + 0.02, 0.07, mats["chrome"])
    # Scale ring printed on the face (one object: a thin arc).
    b.annulus(f"{d['name']}_Arc", R - 0.36, R - 0.34, 96, z=0.004, mat=mats["print"],
              location=(cx, cy, 0.0),
              a0=math.radians(90 - angle(d["vmax"])), a1=math.radians(90 - angle(0)))
    if d["red_from"] is not None:
        b.annulus(f"{d['name']}_RedZone", R - 0.34, R - 0.16, 24, z=0.005, mat=mats["redzone"],
                  location=(cx, cy, 0.0),
                  a0=math.radians(90 - angle(d["vmax"])), a1=math.radians(90 - angle(d["red_from"])))
    scale_print(d, mats, parent=d.get("scale_parent"))
    step = d["vmax"] // (RPM_PER_FRAME if d["name"] == "Tacho" else 1)
    frames_values = [(0, 0), (step, d["vmax"])]
    needle(f"{d['name']}_Needle", (cx, cy), R - 0.2, 0.35, 0.09, 0.12, mats["needle"],
           d["anim"], frames_values, angle)
    hub(f"{d['name']}_Hub", (cx, cy), 0.16, 0.17, mats["hubcap"])


def scale_print(d, mats, parent=None, prefix=None):
    """The printed scale of a main dial: ticks, numerals and the unit label (under `parent`, so a
    unit system can switch a whole scale); `prefix` names its objects (default: the dial's name)."""
    cx, cy = d["center"]
    R = d["radius"]
    angle = lambda v: d["start"] + d["sweep"] * v / d["vmax"]  # noqa: E731
    prefix = prefix or d["name"]
    v = 0
    while v <= d["vmax"]:
        major = v % d["major"] == 0
        r0, r1 = (R - 0.36, R - 0.12) if major else (R - 0.36, R - 0.22)
        w = 0.028 if major else 0.014
        red = d["red_from"] is not None and v >= d["red_from"]
        t = b.box(f"{prefix}_Tick_{v:05d}", -w, w, r0, r1, 0.0, 0.012,
                  mat=mats["redprint" if red else "print"], parent=parent)
        t.location = (cx, cy, 0.004)
        t.rotation_euler = (0.0, 0.0, screen_rot(angle(v)))
        if v % d["label_every"] == 0:
            label = str(v // d["label_scale"])
            pos = polar((cx, cy), R - 0.66, angle(v))
            b.text_object(f"{prefix}_Num_{v:05d}", label, 0.26,
                          mat=mats["redprint" if red else "print"],
                          location=(pos[0], pos[1], 0.006), parent=parent)
        v += d["minor"]
    b.text_object(f"{prefix}_Unit", d["unit"], 0.16, mat=mats["print_dim"],
                  location=(cx, cy + 0.62, 0.006), parent=parent)


def small_gauge(g, mats):
    cx, cy = g["center"]
    R = g["radius"]
    span = g["vmax"] - g["vmin"]
    angle = lambda v: -SMALL_SWEEP / 2 + SMALL_SWEEP * (v - g["vmin"]) / span  # noqa: E731
    b.annulus(f"{g['name']}_Arc", R - 0.05, R - 0.03, 32, z=0.004, mat=mats["print"],
              location=(cx, cy, 0.0),
              a0=math.radians(90 - angle(g["vmax"])), a1=math.radians(90 - angle(g["vmin"])))
    if g["red_to"] is not None:
        b.annulus(f"{g['name']}_RedZone", R - 0.05, R + 0.04, 8, z=0.005, mat=mats["redzone"],
                  location=(cx, cy, 0.0),
                  a0=math.radians(90 - angle(g["red_to"])), a1=math.radians(90 - angle(g["vmin"])))
    if g["red_from"] is not None:
        b.annulus(f"{g['name']}_RedZone", R - 0.05, R + 0.04, 8, z=0.005, mat=mats["redzone"],
                  location=(cx, cy, 0.0),
                  a0=math.radians(90 - angle(g["vmax"])), a1=math.radians(90 - angle(g["red_from"])))
    for i in range(5):
        v = g["vmin"] + span * i / 4
        t = b.box(f"{g['name']}_Tick_{i}", -0.014, 0.014, R - 0.05, R + 0.06, 0.0, 0.01,
                  mat=mats["print"])
        t.location = (cx, cy, 0.004)
        t.rotation_euler = (0.0, 0.0, screen_rot(angle(v)))
    for v, text in g["labels"].items():
        pos = polar((cx, cy), R + 0.2, angle(v))
        b.text_object(f"{g['name']}_Label_{text.replace('/', '_')}", text, 0.14,
                      mat=mats["print"], location=(pos[0], pos[1], 0.006))
    # Symbol under the pivot: pump for fuel, thermometer for coolant.
    mb = b.MeshBuilder()
    if g["name"] == "Fuel":
        fuel_pump_icon(mb, 0.22)
    else:
        thermometer_icon(mb, 0.22)
    mb.build(f"{g['name']}_Icon", mats["print_dim"], location=(cx, cy + 0.2, 0.006))
    needle(f"{g['name']}_Needle", (cx, cy), R - 0.02, 0.1, 0.06, 0.06, mats["needle"],
           g["anim"], [(g["vmin"], g["vmin"]), (g["vmax"], g["vmax"])], angle)
    hub(f"{g['name']}_Hub", (cx, cy), 0.07, 0.1, mats["hubcap"])


# ---------------------------------------------------------------- binding file

def anim_time(frame):
    return round(frame / FPS, 6)


def write_config(path, scene):
    """The binding file is generated with the scene so node, material and animation names can
    never drift apart from the .glb."""
    white = [0.92, 0.94, 0.97, 1.0]
    bindings = [
        {"signal": "Vehicle.Speed", "kind": "animation", "animation": SPEEDO["anim"],
         "input": [0, SPEEDO["vmax"]], "time": [0.0, anim_time(SPEEDO["vmax"])],
         "smoothing_ms": 80, "failsafe": {"value": 0}},
        {"signal": "Vehicle.Powertrain.CombustionEngine.Speed", "kind": "animation",
         "animation": TACHO["anim"], "input": [0, TACHO["vmax"]],
         "time": [0.0, anim_time(TACHO["vmax"] / RPM_PER_FRAME)], "smoothing_ms": 60,
         "failsafe": {"value": 0}},
        # Fuel and coolant move slowly on real clusters (tank slosh, thermal mass); the long
        # smoothing is the look, the controller does the physical damping.
        {"signal": "Vehicle.Powertrain.FuelSystem.RelativeLevel", "kind": "animation",
         "animation": FUEL["anim"], "input": [FUEL["vmin"], FUEL["vmax"]],
         "time": [anim_time(FUEL["vmin"]), anim_time(FUEL["vmax"])], "smoothing_ms": 400,
         "failsafe": {"value": 0}},
        {"signal": "Vehicle.Powertrain.CombustionEngine.ECT", "kind": "animation",
         "animation": COOLANT["anim"], "input": [COOLANT["vmin"], COOLANT["vmax"]],
         "time": [anim_time(COOLANT["vmin"]), anim_time(COOLANT["vmax"])], "smoothing_ms": 400,
         "failsafe": {"value": COOLANT["vmin"]}},
        {"signal": "Vehicle.Speed", "kind": "text", "node": "Text_Speed", "format": "%.0f",
         "size_px": 64, "color": white, "align": "center", "failsafe": {"text": "---"}},
        {"signal": "Vehicle.Powertrain.Transmission.CurrentGear", "kind": "text",
         "node": "Text_Gear", "format": "%.0f", "size_px": 44, "color": white, "align": "center",
         "map": {"-1": "R", "0": "N", "126": "P", "127": "D"}, "failsafe": {"text": "-"}},
        {"signal": "Vehicle.TraveledDistance", "kind": "text", "node": "Text_Odometer",
         "format": "%.0f km", "size_px": 22, "color": white, "align": "right",
         "failsafe": {"text": "------ km"}},
        {"signal": "Vehicle.TripMeterReading", "kind": "text", "node": "Text_Trip",
         "format": "%.1f km", "size_px": 22, "color": white, "align": "right",
         "failsafe": {"text": "---.- km"}},
        {"signal": "Vehicle.Exterior.AirTemperature", "kind": "text", "node": "Text_OutsideTemp",
         "format": "%.0f \u00b0C", "size_px": 22, "color": white, "align": "left",
         "failsafe": {"text": "-- \u00b0C"}},
    ]
    for node, sig, colour, _pos in TELLTALES:
        bindings.append({"signal": f"Cluster.Telltale.{sig}", "kind": "visibility",
                         "node": f"TT_{node}", "failsafe": {"visible": node in FAILSAFE_ON}})
        bindings.append({"signal": f"Cluster.Telltale.{sig}", "kind": "emissive",
                         "material": f"TT_{node}_On", "off": [0.0, 0.0, 0.0],
                         "on": [round(c, 4) for c in colour]})
    bindings += fx.feature_bindings()
    fx.add_units(bindings)
    # Mesh-concatenation groups: checked by meter-convert (one material, no overlap,
    # no draw-order change over the animation ranges); kept in cluster.groups.json, which
    # `meter-convert --propose-groups --report` helps maintain when the scene changes.
    groups = json.load(open(os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                         "cluster.groups.json")))["groups"]
    config = {
        "format": "meter-scene-config/1",
        "size": [WIDTH, HEIGHT],
        "camera": "Camera",
        "clear_color": [0.0, 0.0, 0.0, 1.0],
        "time": 0.0,
        # The world is black (strength 0): no ambient, only the punctual lights and emission.
        "ambient": [0.0, 0.0, 0.0],
        # The MSAA resolve spreads edges as EEVEE's film filter (Render > Film > Filter Size,
        # Blender's default 1.5 px) does in the reference: the thin ticks, numerals and outlines
        # carry almost all the difference to it (docs/fidelity.md).
        # Its samples keep light above white until the filter has run (EEVEE's film is float): the
        # emissive, spot-lit print is brighter than white, and 8-bit samples clamped each one, so
        # a tick half covering a pixel came out half of white where Blender shows it nearly white.
        "resolve": {"filter": "blackman-harris", "width_px": round(scene.render.filter_size, 3),
                    "sample_format": "rgba16f"},
        "bindings": bindings,
        "link_loss": {"text_node": "Text_Status", "text": "NO SIGNAL"},
        "groups": groups,
        **fx.feature_config([SPEEDO["anim"], TACHO["anim"], FUEL["anim"], COOLANT["anim"]]),
    }
    b.write_scene_config(path, config)


# ---------------------------------------------------------------- scene

def build():
    outdir, render = b.parse_args()
    scene = b.reset_scene(WIDTH, HEIGHT, FPS)
    scene.frame_start = 0
    scene.frame_end = 260
    b.set_world_color((0.0, 0.0, 0.0), strength=0.0)

    mats = {
        "panel": b.principled("Panel", base=(0.008, 0.008, 0.01), metallic=0.0, roughness=0.8),
        "chrome": b.principled("Chrome", base=(0.95, 0.95, 0.95), metallic=1.0, roughness=0.12),
        "print": b.principled("Print", base=(0.85, 0.85, 0.85), roughness=0.6,
                              emission=(0.85, 0.87, 0.9), emission_strength=1.0),
        "print_dim": b.principled("PrintDim", base=(0.4, 0.4, 0.4), roughness=0.6,
                                  emission=(0.35, 0.36, 0.38), emission_strength=1.0),
        "redprint": b.principled("RedPrint", base=(0.9, 0.05, 0.02), roughness=0.6,
                                 emission=(0.9, 0.03, 0.01), emission_strength=1.0),
        "redzone": b.principled("RedZone", base=(0.5, 0.01, 0.0), roughness=0.5,
                                emission=(0.45, 0.0, 0.0), emission_strength=1.0),
        "needle": b.principled("Needle", base=(1.0, 0.12, 0.0), roughness=0.35,
                               emission=(1.0, 0.1, 0.0), emission_strength=1.0),
        "hubcap": b.principled("HubCap", base=(0.05, 0.05, 0.06), metallic=0.9, roughness=0.25),
        "window": b.principled("TelltaleWindow", base=(0.004, 0.004, 0.005), roughness=0.9),
        "centre": b.principled("CentrePanel", base=(0.012, 0.014, 0.02), metallic=0.3,
                               roughness=0.5),
    }
    normal_mat = dial_face_material(dial_normal_map())

    # Back panel slightly behind everything so nothing z-fights with it.
    b.box("BackPanel", -6.6, 6.6, -2.6, 2.6, -0.06, -0.02, mat=mats["panel"])
    b.box("CentreDisplay", -1.5, 1.5, -1.35, 1.7, -0.015, -0.005, mat=mats["centre"])

    # Both speedometer scales: km/h (the authored one) and mph, switched by the unit system.
    SPEEDO["scale_parent"] = fx.mph_scale(SPEEDO, mats, scale_print)
    main_dial(SPEEDO, mats, normal_mat)
    main_dial(TACHO, mats, normal_mat)
    small_gauge(FUEL, mats)
    small_gauge(COOLANT, mats)

    # Telltales: a dark window (the unlit dead front) plus the icon, whose material is the
    # emissive lamp colour. The engine hides the icon node when the lamp is off.
    for node, _sig, colour, (x, y) in TELLTALES:
        b.box(f"TTWindow_{node}", -0.22, 0.22, -0.22, 0.22, -0.004, 0.0, mat=mats["window"],
              location=(x, y, 0.0))
        mat = b.principled(f"TT_{node}_On", base=(colour[0] * 0.3, colour[1] * 0.3,
                                                  colour[2] * 0.3), roughness=0.6,
                           emission=colour, emission_strength=1.0)
        telltale_mesh(node, 0.4).build(f"TT_{node}", mat, location=(x, y, 0.006))

    # Text anchors: the engine draws text with its own font at these origins.
    b.empty("Text_Gear", (0.0, 0.95, 0.01))
    b.empty("Text_Odometer", (1.3, -0.55, 0.01))
    b.empty("Text_Trip", (1.3, -0.95, 0.01))
    b.empty("Text_OutsideTemp", (-1.3, -0.55, 0.01))
    # Above the gear letter: the link-loss text must not cover odometer / trip / temperature.
    b.empty("Text_Status", (0.0, 1.36, 0.01))
    # Display features: the two centre pages, the shift light, the night materials.
    fx.pages(mats)
    fx.shift_light(mats)
    fx.night_swatches()
    b.text_object("Label_Odo", "ODO", 0.11, mat=mats["print_dim"], location=(0.0, -0.55, 0.002))
    b.text_object("Label_Trip", "TRIP", 0.11, mat=mats["print_dim"], location=(0.0, -1.05, 0.002),
                  align="CENTER")
    b.box("Divider_Top", -1.3, 1.3, 1.55, 1.565, -0.004, 0.0, mat=mats["print_dim"])
    b.box("Divider_Bottom", -1.3, 1.3, -1.3, -1.285, -0.004, 0.0, mat=mats["print_dim"])

    b.camera_persp("Camera", (0.0, 0.0, CAM_Z), (0.0, 0.0, 0.0), lens_mm=LENS_MM)
    # Lights (all exported as KHR_lights_punctual): a key sun from the upper left, one spot over
    # each dial so the chrome and the normal-mapped face catch a highlight, a weak point fill.
    lights = [
        b.light("KeySun", "SUN", (-4.0, 6.0, 8.0), energy=2.0, target=(0.0, 0.0, 0.0)),
        b.light("SpotSpeedo", "SPOT", (-3.75, 3.5, 6.0), energy=900.0, target=(-3.75, 0.0, 0.0),
                spot_size_deg=50.0, spot_blend=0.3),
        b.light("SpotTacho", "SPOT", (3.75, 3.5, 6.0), energy=900.0, target=(3.75, 0.0, 0.0),
                spot_size_deg=50.0, spot_blend=0.3),
        b.light("FillPoint", "POINT", (0.0, -3.0, 5.0), energy=300.0, color=(0.8, 0.85, 1.0)),
    ]
    # No light casts shadows (the exporter writes use_shadow; the engine then draws no shadow
    # map). The needles would cast onto the dial faces: every frame a needle moves would then be
    # drawn whole, without the static layer (about 45x a partial frame in the drive, docs/engine.md
    # "Shadows"), and with Blender's default shadow settings the engine's maps came out 0.23 dB
    # further from this render than no shadows at all (docs/fidelity.md). A cluster that wants
    # them turns use_shadow on here and pays that.
    for lamp in lights:
        lamp.data.use_shadow = False

    scene.frame_set(0)
    b.export_glb(os.path.join(outdir, "cluster.glb"), extra=dict(export_tangents=True))
    write_config(os.path.join(outdir, "cluster.scene.json"), scene)
    n_obj = sum(1 for o in scene.objects if o.type == "MESH")
    n_vert = sum(len(o.data.vertices) for o in scene.objects if o.type == "MESH")
    print(f"cluster: {n_obj} mesh objects, {len(scene.objects)} objects, {n_vert} vertices")

    if render:
        # Preview only (docs): frame 100 puts the speedometer at 100 km/h.
        fx.hide_in_preview()
        scene.frame_set(100)
        scene.render.engine = "BLENDER_EEVEE"
        scene.eevee.taa_render_samples = 32
        scene.eevee.use_gtao = False
        scene.eevee.use_bloom = False
        scene.eevee.use_ssr = False
        # PNG, lossless: the reference the fidelity bench measures the engine against (a JPEG's
        # own loss capped any render at about 35.6 dB) and the picture in docs/scenes.md.
        scene.render.image_settings.file_format = "PNG"
        scene.render.image_settings.color_mode = "RGB"
        scene.render.image_settings.color_depth = "8"
        scene.render.image_settings.compression = 90
        scene.render.filepath = os.path.join(outdir, "preview-blender.png")
        bpy.ops.render.render(write_still=True)


build()
