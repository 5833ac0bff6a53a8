# The smallest scene that exercises value-driven animation end to end: one dial, a few ticks, one
# red needle whose animation "SpeedNeedle" is keyed frame k = k km/h (0..260).
# Geometry is chosen so a test can read the needle angle from pixels (see README.md):
#   640x480, orthographic camera looking straight down -Z at the dial, ortho_scale 3.2 units over
#   640 px -> 200 px per unit; dial centre (the needle pivot) at the world origin -> pixel (320, 240).
# Run:  blender -b --factory-startup --python-exit-code 1 --python build.py -- OUTDIR [--render]
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import bpy  # noqa: E402
import bscene as b  # noqa: E402

WIDTH, HEIGHT, FPS = 640, 480, 24
MAX_KMH = 260
SWEEP_DEG = 240.0        # 0 km/h at -120 deg (lower left), 260 km/h at +120 deg (lower right)
START_DEG = -120.0       # clockwise from straight up, as seen on screen
DIAL_R = 1.0             # world units; 200 px
NEEDLE_LEN = 0.90        # tip radius, 180 px
NEEDLE_TAIL = 0.15       # counterweight behind the pivot, 30 px
NEEDLE_W = 0.04          # 8 px wide


def screen_angle_to_blender_z(deg_cw_from_up):
    # The camera looks down -Z with +Y up on screen, so a positive rotation about +Z turns the
    # needle counter-clockwise on screen; "clockwise from up" is the negative of it.
    return math.radians(-deg_cw_from_up)


def build():
    outdir, render = b.parse_args()
    scene = b.reset_scene(WIDTH, HEIGHT, FPS)
    scene.frame_start = 0
    scene.frame_end = MAX_KMH
    b.set_world_color((0.0, 0.0, 0.0), strength=0.0)

    face_mat = b.principled("DialFace", base=(0.02, 0.02, 0.025), roughness=0.6)
    tick_mat = b.principled("Tick", base=(0.8, 0.8, 0.8), roughness=0.5,
                            emission=(0.8, 0.8, 0.8), emission_strength=1.0)
    needle_mat = b.principled("NeedleRed", base=(1.0, 0.0, 0.0), roughness=0.4,
                              emission=(1.0, 0.0, 0.0), emission_strength=1.0)
    hub_mat = b.principled("Hub", base=(0.05, 0.05, 0.05), metallic=0.8, roughness=0.3)

    dial = b.disc("DialFace", DIAL_R, 96, z=0.0, mat=face_mat)

    # Major ticks every 20 km/h, from r 0.80 to 0.95.
    for kmh in range(0, MAX_KMH + 1, 20):
        ang = START_DEG + SWEEP_DEG * kmh / MAX_KMH
        tick = b.box(f"Tick_{kmh:03d}", -0.012, 0.012, 0.80, 0.95, 0.0, 0.01, mat=tick_mat)
        tick.location = (0.0, 0.0, 0.005)
        tick.rotation_euler = (0.0, 0.0, screen_angle_to_blender_z(ang))
        tick.parent = dial

    # Needle: pointing +Y in its rest pose, pivot at its origin; the animation rotates it.
    needle = b.box("Needle", -NEEDLE_W / 2, NEEDLE_W / 2, -NEEDLE_TAIL, NEEDLE_LEN, 0.0, 0.02,
                   mat=needle_mat)
    needle.location = (0.0, 0.0, 0.03)
    needle.rotation_mode = "XYZ"
    for frame, kmh in ((0, 0), (MAX_KMH, MAX_KMH)):
        needle.rotation_euler = (0.0, 0.0, screen_angle_to_blender_z(
            START_DEG + SWEEP_DEG * kmh / MAX_KMH))
        needle.keyframe_insert("rotation_euler", index=2, frame=frame)
    action = needle.animation_data.action
    action.name = "SpeedNeedle"
    b.set_linear(action)
    needle.rotation_euler = (0.0, 0.0, screen_angle_to_blender_z(START_DEG))

    # Hub cap over the pivot (small: the needle stays visible outside r = 0.06 / 12 px).
    b.disc("Hub", 0.06, 32, z=0.0, mat=hub_mat, location=(0.0, 0.0, 0.06))

    b.camera_ortho("Camera", (0.0, 0.0, 10.0), ortho_scale=3.2)
    # Sun from the upper left at 45 deg: lit straight from the camera direction the flat dial would
    # mirror the specular peak into every pixel and turn grey.
    sun = b.light("Sun", "SUN", (-3.0, 3.0, 4.24), energy=3.0, target=(0.0, 0.0, 0.0))
    # No shadow (the exporter writes use_shadow): the needle's shadow would sweep the dial, so
    # every frame a needle moves would be drawn whole (docs/engine.md, "Shadows").
    sun.data.use_shadow = False

    scene.frame_set(0)
    b.export_glb(os.path.join(outdir, "minimal-gauge.glb"))

    if render:
        # Reference at 100 km/h (frame 100). EEVEE, 64 samples, no bloom/AO/SSR: the engine has
        # none of those.
        scene.frame_set(100)
        scene.render.engine = "BLENDER_EEVEE"
        scene.eevee.taa_render_samples = 64
        scene.eevee.use_gtao = False
        scene.eevee.use_bloom = False
        scene.eevee.use_ssr = False
        scene.render.film_transparent = False
        scene.render.image_settings.file_format = "PNG"
        scene.render.image_settings.color_mode = "RGB"
        scene.render.filepath = os.path.join(outdir, "reference-100kmh.png")
        bpy.ops.render.render(write_still=True)


build()
