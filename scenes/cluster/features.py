# The cluster's display features, built by build.py: the shift light, the two centre pages with
# their slide-in clips, the night material set (the scene carries both looks), the mph scale of
# the speedometer, and the config keys that drive them (docs/scene-config.md, docs/scenes.md).
import bpy
import bscene as b

# Shift light: lit above this engine speed. The demo drive reaches it only cruising at 130 km/h
# in 6th (3055 rpm); a gear-dependent rule is a script's job.
SHIFT_RPM = 3000
SHIFT_COLOUR = (1.0, 0.2, 0.0)
SHIFT_POS = (3.75, 1.02)

# mph print of the speedometer: 0..160 mph over the same 240 degrees as 0..260 km/h.
MPH_VMAX = 160

# Page slide-in: the entering page rises 0.3 units into place over 12 frames (0.5 s at 24 fps).
PAGE_FRAMES = 12
PAGE_RISE = 0.3

# Night look per day material: warm amber print, dimmer chrome, a darker centre display.
NIGHT = {
    "Print": dict(base=(0.5, 0.22, 0.04), roughness=0.6, emission=(0.55, 0.2, 0.02), emission_strength=1.0),
    "PrintDim": dict(base=(0.2, 0.09, 0.02), roughness=0.6, emission=(0.2, 0.08, 0.01), emission_strength=1.0),
    "Chrome": dict(base=(0.3, 0.3, 0.32), metallic=1.0, roughness=0.12),
    "CentrePanel": dict(base=(0.004, 0.004, 0.007), metallic=0.3, roughness=0.5),
}
THEME_MS = 1000
# Brightness 0 % takes 3 stops (1/8) off the exposure.
BRIGHTNESS_MIN_STOPS = -3.0

WHITE = [0.92, 0.94, 0.97, 1.0]
HMI = "Vehicle.Cabin.Infotainment.HMI"


def shift_light(mats):
    b.box("ShiftLightWindow", -0.38, 0.38, -0.09, 0.09, 0.002, 0.006, mat=mats["window"],
          location=(SHIFT_POS[0], SHIFT_POS[1], 0.0))
    mat = b.principled("ShiftLight_On", base=tuple(c * 0.3 for c in SHIFT_COLOUR), roughness=0.6,
                       emission=SHIFT_COLOUR, emission_strength=1.0)
    b.box("ShiftLight", -0.34, 0.34, -0.05, 0.05, 0.006, 0.01, mat=mat,
          location=(SHIFT_POS[0], SHIFT_POS[1], 0.0))


def slide_in(obj, action_name):
    """Keys the page root rising into place: the page's transition clip."""
    for frame, dy in ((0, -PAGE_RISE), (PAGE_FRAMES, 0.0)):
        obj.location = (0.0, dy, 0.0)
        obj.keyframe_insert("location", index=1, frame=frame)
    obj.animation_data.action.name = action_name
    b.set_linear(obj.animation_data.action)


def pages(mats):
    """Page 0 (drive): digital speed and its unit; page 1 (trip computer): trip and fuel.
    Returns the page roots; the text anchors under them move and hide with their page."""
    drive = b.empty("Page_Drive", (0.0, 0.0, 0.0))
    b.empty("Text_Speed", (0.0, 0.25, 0.01), parent=drive)
    b.text_object("Label_SpeedUnit", "km/h", 0.13, mat=mats["print_dim"], location=(0.0, -0.05, 0.002),
                  parent=drive)
    b.text_object("Label_SpeedUnit_Mph", "mph", 0.13, mat=mats["print_dim"], location=(0.0, -0.05, 0.002),
                  parent=drive)
    slide_in(drive, "PageDrive_In")
    trip = b.empty("Page_Trip", (0.0, 0.0, 0.0))
    b.text_object("Label_TripComputer", "TRIP COMPUTER", 0.12, mat=mats["print_dim"],
                  location=(0.0, 0.55, 0.002), parent=trip)
    b.empty("Text_TripPage", (0.0, 0.05, 0.01), parent=trip)
    b.empty("Text_TripFuel", (0.0, -0.25, 0.01), parent=trip)
    slide_in(trip, "PageTrip_In")
    return drive, trip


def night_swatches():
    """The night materials, each on a small quad under one root the engine never shows (the
    exporter writes only materials some mesh uses)."""
    root = b.empty("Theme_NightSwatches", (0.0, 0.0, -1.0))
    for i, (day, look) in enumerate(NIGHT.items()):
        mat = b.principled(f"{day}_Night", **look)
        b.box(f"Swatch_{day}_Night", 0.0, 0.05, 0.0, 0.05, 0.0, 0.01, mat=mat, parent=root,
              location=(0.1 * i, 0.0, 0.0))


def mph_scale(speedo, mats, scale_print):
    kmh = b.empty("Speedo_Scale_Kmh", (0.0, 0.0, 0.0))
    mph = b.empty("Speedo_Scale_Mph", (0.0, 0.0, 0.0))
    mph_dial = dict(speedo, vmax=MPH_VMAX, unit="mph")
    scale_print(mph_dial, mats, parent=mph, prefix="SpeedoMph")
    return kmh


def imperial(binding, quantity, **look):
    binding["quantity"] = quantity
    if look:
        binding["imperial"] = look
    return binding


def feature_bindings():
    """Bindings of the feature nodes (the trip page's readouts, the shift light)."""
    return [
        imperial({"signal": "Vehicle.TripMeterReading", "kind": "text", "node": "Text_TripPage",
                  "format": "%.1f km", "size_px": 44, "color": WHITE, "align": "center",
                  "failsafe": {"text": "---.- km"}}, "distance", format="%.1f mi", failsafe_text="---.- mi"),
        {"signal": "Vehicle.Powertrain.FuelSystem.RelativeLevel", "kind": "text", "node": "Text_TripFuel",
         "format": "fuel %.0f %%", "size_px": 22, "color": WHITE, "align": "center",
         "failsafe": {"text": "fuel -- %"}},
        # The shift light is advice, not a telltale: "safety": false keeps it out of the integrity
        # monitor's regions (docs/integrity.md).
        {"signal": "Vehicle.Powertrain.CombustionEngine.Speed", "kind": "visibility", "node": "ShiftLight",
         "threshold": SHIFT_RPM, "safety": False, "failsafe": {"visible": False}},
        {"signal": "Vehicle.Powertrain.CombustionEngine.Speed", "kind": "emissive", "material": "ShiftLight_On",
         "off": [0.0, 0.0, 0.0], "on": list(SHIFT_COLOUR), "threshold": SHIFT_RPM, "safety": False},
    ]


def add_units(bindings):
    """Marks the readouts and the speed needle with what they measure and their imperial look."""
    looks = {
        "SpeedNeedle": ("speed", dict(input=[0, MPH_VMAX])),
        "Text_Speed": ("speed", {}),
        "Text_Odometer": ("distance", dict(format="%.0f mi", failsafe_text="------ mi")),
        "Text_Trip": ("distance", dict(format="%.1f mi", failsafe_text="---.- mi")),
        "Text_OutsideTemp": ("temperature", dict(format="%.0f \u00b0F", failsafe_text="-- \u00b0F")),
    }
    for bd in bindings:
        key = bd.get("animation") or bd.get("node")
        if key in looks:
            imperial(bd, looks[key][0], **looks[key][1])


def feature_config(needle_animations):
    return {
        "pages": {"signal": "Cluster.Page", "nodes": ["Page_Drive", "Page_Trip"],
                  "transitions": ["PageDrive_In", "PageTrip_In"]},
        "theme": {"signal": f"{HMI}.DayNightMode", "transition_ms": THEME_MS,
                  "pairs": [{"day": day, "night": f"{day}_Night"} for day in NIGHT],
                  "swatch_nodes": ["Theme_NightSwatches"],
                  "brightness_signal": f"{HMI}.Brightness", "brightness_min_stops": BRIGHTNESS_MIN_STOPS},
        "units": {"distance_signal": f"{HMI}.DistanceUnit", "temperature_signal": f"{HMI}.TemperatureUnit",
                  "metric_nodes": ["Speedo_Scale_Kmh", "Label_SpeedUnit"],
                  "imperial_nodes": ["Speedo_Scale_Mph", "Label_SpeedUnit_Mph"]},
        "sweep": {"signal": "Vehicle.LowVoltageSystemState", "on_at_least": 4, "rise_ms": 1000,
                  "hold_ms": 200, "fall_ms": 1000, "animations": needle_animations},
    }


def hide_in_preview():
    """Blender's preview render (after the export) shows the authored look: page 1, km/h, day.
    The other looks' objects are left out of it, as the engine never shows them together."""
    for root in ("Speedo_Scale_Mph", "Label_SpeedUnit_Mph", "Page_Trip", "Theme_NightSwatches"):
        obj = bpy.data.objects[root]
        for o in [obj] + list(obj.children_recursive):
            o.hide_render = True
