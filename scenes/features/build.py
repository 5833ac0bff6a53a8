# The feature scenes, one Utah teapot each, 640x480: the twelve of the paper's Table 1 plus
# `shadow` (lights that cast shadows), and their reference images rendered by Blender EEVEE (the
# artist's approved look the engine must match).
#
#   blender -b --factory-startup --python-exit-code 1 --python build.py -- OUTDIR NAME [--render]
#
# writes OUTDIR/NAME.glb, OUTDIR/scene.json and with --render OUTDIR/reference.png (plus
# OUTDIR/environment.png for the scenes lit by an environment map).
#
# Reference render settings (identical for every scene, see docs/scenes.md):
#   EEVEE, 64 TAA samples, 1.5 px Blackman-Harris film filter, view transform 'Standard', look
#   None, exposure 0, gamma 1, sRGB display; no ambient occlusion, no bloom, no screen-space
#   reflections/refraction, no motion blur, no volumetrics, soft shadows off and every light's
#   shadow off (KHR_lights_punctual lights cast no shadows in a forward engine without shadow
#   maps) EXCEPT in the `shadow` scene, whose feature it is: there both lights cast, each from a
#   single shadow map (sun: one cascade, no fade; 2048 px cascade / 1024 px cube maps, no contact
#   shadows); the exporter writes each light's flag as extras.meter_cast_shadow. Light radius 0
#   (punctual). The world is black with strength 0 except in the scenes whose feature IS world
#   light (ambient: a uniform colour; reflection, envmap2d: an equirectangular image); there the
#   world is hidden from the camera so the background stays black.
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import bmesh  # noqa: E402
import bpy  # noqa: E402
import numpy as np  # noqa: E402
import bscene as b  # noqa: E402

WIDTH, HEIGHT, FPS = 640, 480, 24
# Render > Film > Filter Size (EEVEE's Blackman-Harris pixel filter, Blender's default), written into
# the scene config's "resolve" so the engine's MSAA resolve spreads edges the same way.
FILTER_SIZE_PX = 1.5
FEATURES = ("ambient", "diffuse", "specular", "shininess", "emission", "bump", "reflection",
            "envmap2d", "skinning", "morphing", "spot", "omni", "shadow")
ANIM_FRAMES = 24      # skinning / morphing: one second of animation
REFERENCE_FRAME = 12  # ... rendered half way (tests interpolation, not just a key)


def parse():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    render = "--render" in argv
    rest = [a for a in argv if not a.startswith("--")]
    if len(rest) != 2 or rest[1] not in FEATURES:
        raise SystemExit("usage: build.py -- OUTDIR NAME [--render]; NAME one of " +
                         ", ".join(FEATURES))
    outdir = os.path.abspath(rest[0])
    os.makedirs(outdir, exist_ok=True)
    return outdir, rest[1], render


def teapot(name, mat, resolution=6):
    """The Utah teapot from the bundled add_mesh_extra_objects add-on. Its Bezier patches come
    out as separate grids; welding the seams and smoothing gives one closed, smooth-shaded mesh
    (otherwise every patch border shows as a crease)."""
    bpy.ops.preferences.addon_enable(module="add_mesh_extra_objects")
    bpy.ops.mesh.primitive_teapot_add(resolution=resolution, location=(0.0, 0.0, 0.0))
    obj = bpy.context.active_object
    obj.name = name
    obj.data.name = name
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    bmesh.ops.remove_doubles(bm, verts=bm.verts, dist=1e-4)
    # Degenerate triangles at the poles of the lid/bottom patches.
    bmesh.ops.dissolve_degenerate(bm, edges=bm.edges, dist=1e-5)
    bmesh.ops.recalc_face_normals(bm, faces=bm.faces)
    bm.to_mesh(obj.data)
    bm.free()
    # Centre it on the origin, 2 units long (spout tip to handle).
    xs = [v.co.x for v in obj.data.vertices]
    zs = [v.co.z for v in obj.data.vertices]
    scale = 2.0 / (max(xs) - min(xs))
    shift = ((max(xs) + min(xs)) / 2.0, 0.0, (max(zs) + min(zs)) / 2.0)
    for v in obj.data.vertices:
        v.co.x = (v.co.x - shift[0]) * scale
        v.co.y = (v.co.y - shift[1]) * scale
        v.co.z = (v.co.z - shift[2]) * scale
    for p in obj.data.polygons:
        p.use_smooth = True
    obj.data.update()
    b.assign(obj, mat)
    return obj


def floor(mat, z):
    return b.box("Floor", -4.0, 4.0, -4.0, 4.0, z - 0.02, z, mat=mat)


def spherical_uv(obj):
    """UVs by longitude / latitude around the teapot's centre, so a tiled normal map covers it
    without the patch-by-patch stretching of the Bezier parameterisation."""
    mesh = obj.data
    uv = mesh.uv_layers.new(name="UVMap")
    for poly in mesh.polygons:
        us = []
        for li in poly.loop_indices:
            co = mesh.vertices[mesh.loops[li].vertex_index].co
            u = (math.atan2(co.y, co.x) / (2.0 * math.pi)) % 1.0
            v = math.atan2(co.z, math.hypot(co.x, co.y)) / math.pi + 0.5
            us.append([u, v])
        # A face straddling the u wrap must not span the whole texture backwards.
        if max(p[0] for p in us) - min(p[0] for p in us) > 0.5:
            for p in us:
                if p[0] < 0.5:
                    p[0] += 1.0
        for li, p in zip(poly.loop_indices, us):
            uv.data[li].uv = (p[0], p[1])


def dimple_normal_map(size=512, cells=16):
    """Hammered-metal dimples: a grid of cells x cells spherical caps. Tangent-space, +Y = +v."""
    t = (np.arange(size) + 0.5) / size * cells
    x, y = np.meshgrid(t, t)
    fx = x - np.floor(x) - 0.5
    fy = y - np.floor(y) - 0.5
    rr = fx * fx + fy * fy
    inside = rr < 0.16
    # Height of a cap: h = sqrt(0.16 - r^2) (depth scaled); slope from its gradient.
    depth = 0.45
    denom = np.sqrt(np.maximum(0.16 - rr, 1e-4))
    dhdx = np.where(inside, -fx / denom * depth, 0.0)
    dhdy = np.where(inside, -fy / denom * depth, 0.0)
    n = np.stack([dhdx, dhdy, np.ones_like(x)], axis=-1)  # dimples (h negative) invert the slope
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    rgba = np.concatenate([(n + 1.0) * 0.5, np.ones((size, size, 1))], axis=-1)
    return b.image_from_rgb("TeapotNormal", size, size, rgba.astype(np.float32).ravel())


def environment_image(path, width=512, height=256):
    """An equirectangular studio environment (sRGB PNG): blue sky gradient, grey ground with a
    grid, three bright softboxes. The same file is committed next to the scene so the engine can
    load exactly what Blender lit the reference with."""
    u = (np.arange(width) + 0.5) / width          # longitude 0..1
    v = (np.arange(height) + 0.5) / height        # 0 = bottom (Blender image rows)
    U, V = np.meshgrid(u, v)
    lat = (V - 0.5) * math.pi
    lon = (U - 0.5) * 2.0 * math.pi
    sky_t = np.clip(lat / (math.pi / 2), 0.0, 1.0)[..., None]
    sky = (1.0 - sky_t) * np.array([0.75, 0.8, 0.85]) + sky_t * np.array([0.12, 0.25, 0.6])
    gx = np.abs(((lon * 6.0 / math.pi) % 1.0) - 0.5) < 0.04
    gy = np.abs(((np.tan(np.clip(-lat, 0.05, 1.5)) ** -1 * 0.8) % 1.0) - 0.5) < 0.05
    ground = np.where((gx | gy)[..., None], np.array([0.35, 0.33, 0.3]),
                      np.array([0.16, 0.15, 0.14]))
    img = np.where((lat >= 0)[..., None], sky, ground)
    for lon0, lat0, w, h in ((-0.8, 0.5, 0.5, 0.25), (0.9, 0.35, 0.35, 0.3), (2.6, 0.7, 0.6, 0.2)):
        box = (np.abs(lon - lon0) < w / 2) & (np.abs(lat - lat0) < h / 2)
        img = np.where(box[..., None], np.array([1.0, 0.98, 0.92]), img)
    rgba = np.concatenate([img, np.ones((height, width, 1))], axis=-1).astype(np.float32)
    im = bpy.data.images.new("Environment", width, height, alpha=False, float_buffer=False)
    im.colorspace_settings.name = "sRGB"
    # Values are display-referred (sRGB-encoded) 0..1, as an artist's 8-bit PNG would be.
    im.pixels.foreach_set(rgba.ravel())
    # Mean linear radiance over the sphere (cos-latitude weighted): the engine's uniform ambient
    # for the diffuse part when it lights with this map (docs/shaders.md, "Ambient").
    q = np.round(img * 255.0) / 255.0  # what the 8-bit PNG holds
    lin = np.where(q <= 0.04045, q / 12.92, ((q + 0.055) / 1.055) ** 2.4)
    wgt = np.cos(lat)[..., None]
    environment_image.mean = [round(float(x), 4) for x in (lin * wgt).sum((0, 1)) / wgt.sum()]
    im.filepath_raw = path
    im.file_format = "PNG"
    im.save()
    return im


def world_setup(color=None, image=None, strength=1.0):
    """World light that the camera does not see: Light Path 'Is Camera Ray' picks black for the
    background pixels, so only the lighting comes from the world."""
    scene = bpy.context.scene
    world = bpy.data.worlds.get("World") or bpy.data.worlds.new("World")
    scene.world = world
    world.use_nodes = True
    nt = world.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputWorld")
    lit = nt.nodes.new("ShaderNodeBackground")
    lit.inputs["Strength"].default_value = strength
    if image is not None:
        env = nt.nodes.new("ShaderNodeTexEnvironment")
        env.image = image
        env.interpolation = "Linear"
        nt.links.new(env.outputs["Color"], lit.inputs["Color"])
    else:
        c = color or (0.0, 0.0, 0.0)
        lit.inputs["Color"].default_value = (c[0], c[1], c[2], 1.0)
    black = nt.nodes.new("ShaderNodeBackground")
    black.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    black.inputs["Strength"].default_value = 0.0
    path = nt.nodes.new("ShaderNodeLightPath")
    mix = nt.nodes.new("ShaderNodeMixShader")
    nt.links.new(path.outputs["Is Camera Ray"], mix.inputs["Fac"])
    nt.links.new(lit.outputs["Background"], mix.inputs[1])
    nt.links.new(black.outputs["Background"], mix.inputs[2])
    nt.links.new(mix.outputs["Shader"], out.inputs["Surface"])


def no_shadow(light_obj):
    light_obj.data.use_shadow = False
    light_obj.data.use_contact_shadow = False
    return light_obj


def key_light(energy=3.0):
    return no_shadow(b.light("Key", "SUN", (3.0, -4.0, 5.0), energy=energy, target=(0, 0, 0)))


# ---------------------------------------------------------------- the scenes
# Each returns a dict of notes that go into scene.json's glTF-independent side (the config) and
# into the glTF scene extras (what the engine must know that glTF cannot say: ambient colour,
# environment map).

def build_feature(name, outdir):
    extras = {}
    ambient = [0.0, 0.0, 0.0]  # black world: no ambient unless the feature is world light
    config_time = 0.0
    base_orange = (0.8, 0.25, 0.05)
    if name == "ambient":
        # Uniform world light = ambient term; a weak sun keeps the shape readable. The engine
        # reads it from the config's "ambient" (also in the glTF scene extras, meter_ambient).
        ambient = (0.25, 0.25, 0.28)
        world_setup(color=ambient)
        extras["meter_ambient"] = list(ambient)
        ambient = list(ambient)
        mat = b.principled("Teapot", base=base_orange, roughness=0.6)
        teapot("Teapot", mat)
        key_light(1.0)
    elif name == "diffuse":
        world_setup()
        mat = b.principled("Teapot", base=base_orange, roughness=1.0)
        teapot("Teapot", mat)
        key_light(3.0)
    elif name == "specular":
        world_setup()
        mat = b.principled("Teapot", base=(0.1, 0.25, 0.7), roughness=0.4)
        teapot("Teapot", mat)
        key_light(3.0)
        no_shadow(b.light("Rim", "POINT", (-3.0, 3.0, 2.5), energy=600.0))
    elif name == "shininess":
        world_setup()
        mat = b.principled("Teapot", base=(0.1, 0.25, 0.7), roughness=0.12)
        teapot("Teapot", mat)
        key_light(3.0)
        no_shadow(b.light("Rim", "POINT", (-3.0, 3.0, 2.5), energy=600.0))
    elif name == "emission":
        world_setup()
        mat = b.principled("Teapot", base=(0.05, 0.05, 0.05), roughness=0.5,
                           emission=(0.1, 0.8, 0.3), emission_strength=1.0)
        teapot("Teapot", mat)
        key_light(1.5)
    elif name == "bump":
        world_setup()
        mat = b.principled("Teapot", base=(0.7, 0.6, 0.45), metallic=0.0, roughness=0.35)
        nt = mat.node_tree
        tex = nt.nodes.new("ShaderNodeTexImage")
        tex.image = dimple_normal_map()
        nmap = nt.nodes.new("ShaderNodeNormalMap")
        nmap.uv_map = "UVMap"
        nt.links.new(tex.outputs["Color"], nmap.inputs["Color"])
        nt.links.new(nmap.outputs["Normal"], nt.nodes["Principled BSDF"].inputs["Normal"])
        pot = teapot("Teapot", mat)
        spherical_uv(pot)
        key_light(3.0)
        no_shadow(b.light("Rim", "POINT", (-3.0, 3.0, 2.5), energy=400.0))
    elif name in ("reflection", "envmap2d"):
        img = environment_image(os.path.join(outdir, "environment.png"))
        world_setup(image=img, strength=1.0)
        extras["meter_environment"] = "environment.png"
        extras["meter_environment_strength"] = 1.0
        ambient = environment_image.mean
        if name == "reflection":
            # Mirror chrome: the environment seen in the surface is the whole feature.
            mat = b.principled("Teapot", base=(0.95, 0.95, 0.95), metallic=1.0, roughness=0.05)
        else:
            # Image-based lighting of a rough dielectric from the 2D (equirectangular) map.
            mat = b.principled("Teapot", base=(0.8, 0.8, 0.8), metallic=0.0, roughness=0.5)
        teapot("Teapot", mat)
    elif name == "skinning":
        world_setup()
        mat = b.principled("Teapot", base=base_orange, roughness=0.5)
        pot = teapot("Teapot", mat)
        skin(pot)
        key_light(3.0)
        config_time = REFERENCE_FRAME / FPS
    elif name == "morphing":
        world_setup()
        mat = b.principled("Teapot", base=(0.2, 0.6, 0.25), roughness=0.5)
        pot = teapot("Teapot", mat)
        morph(pot)
        key_light(3.0)
        config_time = REFERENCE_FRAME / FPS
    elif name == "spot":
        world_setup()
        mat = b.principled("Teapot", base=(0.8, 0.8, 0.8), roughness=0.5)
        teapot("Teapot", mat)
        floor(b.principled("Floor", base=(0.3, 0.3, 0.3), roughness=0.9), -0.62)
        # Hard-edged cone partly on the teapot, partly on the floor: the inner/outer cone
        # angles are what the engine must reproduce.
        no_shadow(b.light("Spot", "SPOT", (1.2, -1.6, 3.0), energy=250.0, target=(0.0, 0.0, -0.3),
                          spot_size_deg=40.0, spot_blend=0.15))
    elif name == "omni":
        world_setup()
        mat = b.principled("Teapot", base=(0.8, 0.8, 0.8), roughness=0.5)
        teapot("Teapot", mat)
        floor(b.principled("Floor", base=(0.3, 0.3, 0.3), roughness=0.9), -0.62)
        # A point light close to the teapot: inverse-square falloff across floor and body.
        no_shadow(b.light("Omni", "POINT", (0.9, -1.0, 0.9), energy=60.0, color=(1.0, 0.9, 0.75)))
    elif name == "shadow":
        world_setup()
        mat = b.principled("Teapot", base=(0.8, 0.8, 0.8), roughness=0.5)
        teapot("Teapot", mat)
        floor(b.principled("Floor", base=(0.3, 0.3, 0.3), roughness=0.9), -0.62)
        # Two lights that cast: the teapot's self-shadow and its two shadows on the floor are the
        # feature (sun's to the right, spot's to the left inside its cone). Each shadow comes
        # from ONE shadow map the engine can match: the sun has a single cascade reaching just
        # past the floor's far edge (view depth ~7.9) and no cascade fade; radius / angle 0
        # (hard edges), no contact shadows.
        sun = b.light("Key", "SUN", (-3.5, -1.5, 4.5), energy=1.8, target=(0.0, 0.0, 0.0))
        sun.data.shadow_cascade_count = 1
        sun.data.shadow_cascade_max_distance = 9.0
        sun.data.shadow_cascade_fade = 0.0
        spot = b.light("Spot", "SPOT", (1.0, -1.4, 3.4), energy=260.0, target=(-0.3, 0.2, -0.62),
                       spot_size_deg=50.0, spot_blend=0.15)
        for lamp in (sun, spot):
            lamp.data.use_shadow = True
            lamp.data.use_contact_shadow = False
    b.camera_persp("Camera", (0.0, -3.7, 1.5), (0.0, 0.0, -0.05), lens_mm=50.0)
    return extras, ambient, config_time


def skin(pot):
    """Two-bone armature along the teapot's height; the upper bone bends the top 30 deg toward
    the spout over one second. Weights are a smooth ramp in z (what automatic weights give for a
    chain, but reproducible)."""
    arm_data = bpy.data.armatures.new("Rig")
    rig = bpy.data.objects.new("Rig", arm_data)
    bpy.context.scene.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode="EDIT")
    lower = arm_data.edit_bones.new("Lower")
    lower.head, lower.tail = (0.0, 0.0, -0.7), (0.0, 0.0, 0.0)
    upper = arm_data.edit_bones.new("Upper")
    upper.head, upper.tail = (0.0, 0.0, 0.0), (0.0, 0.0, 0.7)
    upper.parent = lower
    upper.use_connect = True
    bpy.ops.object.mode_set(mode="OBJECT")
    g_low = pot.vertex_groups.new(name="Lower")
    g_up = pot.vertex_groups.new(name="Upper")
    for v in pot.data.vertices:
        w = min(1.0, max(0.0, (v.co.z + 0.25) / 0.5))  # blend over z in [-0.25, 0.25]
        if w < 1.0:
            g_low.add([v.index], 1.0 - w, "REPLACE")
        if w > 0.0:
            g_up.add([v.index], w, "REPLACE")
    # Not parented to the rig: a skinned mesh under another node draws a validator warning
    # (glTF ignores the parent transform of a skinned mesh); the modifier alone deforms it.
    mod = pot.modifiers.new("Armature", "ARMATURE")
    mod.object = rig
    pb = rig.pose.bones["Upper"]
    pb.rotation_mode = "XYZ"
    for frame, deg in ((0, 0.0), (ANIM_FRAMES, -30.0)):
        # Bone Y runs along the bone (a twist); its local Z is world -Y for a +Z bone with roll 0,
        # so a negative angle about local Z tips the top toward +X (the spout).
        pb.rotation_euler = (0.0, 0.0, math.radians(deg))
        pb.keyframe_insert("rotation_euler", frame=frame)
    rig.animation_data.action.name = "Bend"
    b.set_linear(rig.animation_data.action)


def morph(pot):
    """One shape key, 'Squash': the teapot flattened and widened (volume roughly kept). Its
    weight animates 0 -> 1 over one second."""
    pot.shape_key_add(name="Basis", from_mix=False)
    key = pot.shape_key_add(name="Squash", from_mix=False)
    for i, v in enumerate(pot.data.vertices):
        x, y, z = v.co
        f = 1.0 + 0.35 * (1.0 - min(1.0, abs(z) / 0.7))
        key.data[i].co = (x * f, y * f, z * 0.6)
    key.value = 0.0
    key.keyframe_insert("value", frame=0)
    key.value = 1.0
    key.keyframe_insert("value", frame=ANIM_FRAMES)
    action = pot.data.shape_keys.animation_data.action
    action.name = "Squash"
    b.set_linear(action)


def render_settings(scene):
    scene.render.engine = "BLENDER_EEVEE"
    ee = scene.eevee
    ee.taa_render_samples = 64
    ee.use_gtao = False
    ee.use_bloom = False
    ee.use_ssr = False
    ee.use_motion_blur = False
    ee.use_soft_shadows = False
    # Shadow map sizes; only the `shadow` scene has lights that cast (sun: cascade, spot: cube).
    ee.shadow_cascade_size = "2048"
    ee.shadow_cube_size = "1024"
    ee.use_volumetric_lights = False
    ee.gi_cubemap_resolution = "512"
    scene.render.filter_size = FILTER_SIZE_PX
    scene.render.film_transparent = False
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.image_settings.color_depth = "8"
    scene.render.image_settings.compression = 100


def main():
    outdir, name, render = parse()
    scene = b.reset_scene(WIDTH, HEIGHT, FPS)
    scene.frame_start = 0
    scene.frame_end = ANIM_FRAMES
    extras, ambient, config_time = build_feature(name, outdir)
    for k, v in extras.items():
        scene[k] = v
    scene.frame_set(0)
    animated = name in ("skinning", "morphing")
    b.export_glb(os.path.join(outdir, f"{name}.glb"), animations=animated,
                 extra=dict(export_tangents=(name == "bump"), export_extras=bool(extras),
                            export_skins=True, export_morph=True, export_morph_normal=True))
    b.write_scene_config(os.path.join(outdir, "scene.json"), {
        "format": "meter-scene-config/1",
        "size": [WIDTH, HEIGHT],
        "camera": "Camera",
        "clear_color": [0.0, 0.0, 0.0, 1.0],
        "time": round(config_time, 6),
        "ambient": ambient,
        # The engine resolves MSAA with the same film filter the reference is rendered with.
        "resolve": {"filter": "blackman-harris", "width_px": FILTER_SIZE_PX},
        # Normal-mapped materials and mirrors shaded per MSAA sample: EEVEE's 64 samples per pixel
        # average the detail inside a pixel (only the bump scene has a normal map and only the
        # reflection scene a mirror; the others pay nothing).
        "sample_shading": ["normal-maps", "mirrors"],
        "bindings": [],
        "groups": [],
    })
    if render:
        render_settings(scene)
        scene.frame_set(REFERENCE_FRAME if animated else 0)
        scene.render.filepath = os.path.join(outdir, "reference.png")
        bpy.ops.render.render(write_still=True)


main()
