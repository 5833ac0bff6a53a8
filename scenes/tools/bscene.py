# Shared helpers for the Blender build scripts under scenes/.
# Every build script runs as
#   blender -b --factory-startup --python-exit-code 1 --python build.py -- OUTDIR [--render]
# so the result depends only on the script (no user preferences, no startup file), and a Python
# exception makes Blender exit non-zero instead of silently writing nothing.
import math
import os
import sys

import bpy


def parse_args():
    """Returns (outdir, render_flag) from the arguments after '--'."""
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    render = "--render" in argv
    rest = [a for a in argv if not a.startswith("--")]
    if len(rest) != 1:
        raise SystemExit("usage: blender -b --factory-startup --python build.py -- OUTDIR [--render]")
    outdir = os.path.abspath(rest[0])
    os.makedirs(outdir, exist_ok=True)
    return outdir, render


def reset_scene(width, height, fps=24):
    """Empties the factory scene (cube, light, camera) and sets the output format."""
    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.object.delete()
    for coll in (bpy.data.meshes, bpy.data.materials, bpy.data.lights, bpy.data.cameras,
                 bpy.data.actions, bpy.data.images, bpy.data.textures, bpy.data.curves):
        for block in list(coll):
            coll.remove(block)
    scene = bpy.context.scene
    scene.render.resolution_x = width
    scene.render.resolution_y = height
    scene.render.resolution_percentage = 100
    scene.render.fps = fps
    scene.render.fps_base = 1.0
    # Filmic (the default) tone-maps and differs from a plain sRGB engine by up to 50/255;
    # the engine writes linear -> sRGB, which is what 'Standard' does.
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.display_settings.display_device = "sRGB"
    # No render date / render time / memory / host in the PNG metadata: a regenerated reference
    # with the same pixels is then the same bytes, and git shows no change.
    r = scene.render
    r.use_stamp = False
    r.use_stamp_date = False
    r.use_stamp_time = False
    r.use_stamp_render_time = False
    r.use_stamp_memory = False
    r.use_stamp_hostname = False
    r.use_stamp_frame = False
    r.use_stamp_frame_range = False
    r.use_stamp_camera = False
    r.use_stamp_lens = False
    r.use_stamp_scene = False
    r.use_stamp_filename = False
    r.use_stamp_marker = False
    r.use_stamp_sequencer_strip = False
    return scene


def set_world_color(rgb, strength=1.0):
    """A uniform world colour. Used as the render background only; scenes that must not receive
    world lighting set strength 0 and rely on film_transparent/clear colour instead."""
    scene = bpy.context.scene
    world = bpy.data.worlds.get("World") or bpy.data.worlds.new("World")
    scene.world = world
    world.use_nodes = True
    bg = world.node_tree.nodes.get("Background")
    bg.inputs["Color"].default_value = (rgb[0], rgb[1], rgb[2], 1.0)
    bg.inputs["Strength"].default_value = strength
    return world


def principled(name, base=(0.8, 0.8, 0.8), metallic=0.0, roughness=0.5, emission=None,
               emission_strength=1.0, alpha=1.0):
    """A Principled BSDF material: the node the glTF exporter maps 1:1 onto metallic/roughness
    PBR (+ KHR_materials_emissive_strength when strength > 1)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (base[0], base[1], base[2], 1.0)
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Specular"].default_value = 0.5
    if emission is not None:
        bsdf.inputs["Emission"].default_value = (emission[0], emission[1], emission[2], 1.0)
        bsdf.inputs["Emission Strength"].default_value = emission_strength
    if alpha < 1.0:
        bsdf.inputs["Alpha"].default_value = alpha
        mat.blend_method = "BLEND"
    return mat


def link(obj, parent=None):
    if parent is not None:
        obj.parent = parent
    return obj


def assign(obj, mat):
    obj.data.materials.clear()
    obj.data.materials.append(mat)
    return obj


def mesh_from_data(name, verts, faces, mat=None, location=(0, 0, 0), parent=None):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.validate()
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    obj.location = location
    if mat is not None:
        assign(obj, mat)
    link(obj, parent)
    return obj


def disc(name, radius, segments, z=0.0, mat=None, parent=None, location=(0, 0, 0)):
    """A flat filled circle in the XY plane facing +Z (the camera)."""
    verts = [(0.0, 0.0, z)]
    for i in range(segments):
        a = 2.0 * math.pi * i / segments
        verts.append((radius * math.cos(a), radius * math.sin(a), z))
    faces = [(0, 1 + i, 1 + (i + 1) % segments) for i in range(segments)]
    return mesh_from_data(name, verts, faces, mat, location, parent)


def annulus(name, r_in, r_out, segments, z=0.0, mat=None, parent=None, location=(0, 0, 0),
            a0=0.0, a1=2.0 * math.pi):
    """A flat ring (or ring sector a0..a1, radians CCW from +X) in the XY plane facing +Z."""
    full = abs((a1 - a0) - 2.0 * math.pi) < 1e-9
    n = segments if full else segments + 1
    verts = []
    for i in range(n):
        a = a0 + (a1 - a0) * i / segments
        verts.append((r_in * math.cos(a), r_in * math.sin(a), z))
        verts.append((r_out * math.cos(a), r_out * math.sin(a), z))
    faces = []
    for i in range(segments):
        j = (i + 1) % n
        faces.append((2 * i, 2 * i + 1, 2 * j + 1, 2 * j))
    return mesh_from_data(name, verts, faces, mat, location, parent)


def box(name, x0, x1, y0, y1, z0, z1, mat=None, parent=None, location=(0, 0, 0)):
    """An axis-aligned box given by its extents (object origin stays at `location`)."""
    v = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
         (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    f = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    return mesh_from_data(name, v, f, mat, location, parent)


def camera_ortho(name, location, ortho_scale, rotation=(0, 0, 0)):
    """An orthographic camera. Blender's ortho_scale spans the larger render dimension."""
    cam_data = bpy.data.cameras.new(name)
    cam_data.type = "ORTHO"
    cam_data.ortho_scale = ortho_scale
    cam_data.clip_start = 0.1
    cam_data.clip_end = 100.0
    cam = bpy.data.objects.new(name, cam_data)
    bpy.context.scene.collection.objects.link(cam)
    cam.location = location
    cam.rotation_euler = rotation
    bpy.context.scene.camera = cam
    return cam


def camera_persp(name, location, look_at, lens_mm=50.0, sensor_mm=36.0):
    cam_data = bpy.data.cameras.new(name)
    cam_data.type = "PERSP"
    cam_data.lens = lens_mm
    cam_data.sensor_fit = "HORIZONTAL"
    cam_data.sensor_width = sensor_mm
    cam_data.clip_start = 0.1
    cam_data.clip_end = 100.0
    cam = bpy.data.objects.new(name, cam_data)
    bpy.context.scene.collection.objects.link(cam)
    cam.location = location
    point_at(cam, look_at)
    bpy.context.scene.camera = cam
    return cam


def point_at(obj, target):
    """Aims an object's local -Z (camera / light direction) at target, +Y up."""
    from mathutils import Vector
    direction = Vector(target) - Vector(obj.location)
    obj.rotation_mode = "XYZ"
    obj.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()


def light(name, kind, location, energy, color=(1, 1, 1), target=None, spot_size_deg=None,
          spot_blend=0.0, radius=0.0):
    """A punctual light. radius 0 (a true point) because KHR_lights_punctual lights have no size:
    a Blender light with a radius casts soft shadows the engine cannot reproduce."""
    data = bpy.data.lights.new(name, kind)
    data.energy = energy
    data.color = color
    if kind in ("POINT", "SPOT"):
        data.shadow_soft_size = radius
    if kind == "SUN":
        data.angle = 0.0
    if kind == "SPOT" and spot_size_deg is not None:
        data.spot_size = math.radians(spot_size_deg)
        data.spot_blend = spot_blend
    obj = bpy.data.objects.new(name, data)
    bpy.context.scene.collection.objects.link(obj)
    obj.location = location
    if target is not None:
        point_at(obj, target)
    return obj


# The light custom property export_glb stamps with Blender's use_shadow (see there).
SHADOW_PROP = "meter_cast_shadow"


def export_glb(path, animations=True, extra=None):
    """Exports the whole scene as binary glTF. export_force_sampling stays on (the 3.4 default):
    with it off a needle keyed across a large angle exports identical end quaternions."""
    kwargs = dict(
        filepath=path,
        export_format="GLB",
        use_selection=False,
        export_apply=True,
        export_yup=True,
        export_cameras=True,
        export_lights=True,
        export_animations=animations,
        export_force_sampling=True,
        export_def_bones=False,
        export_nla_strips=True,
        export_texcoords=True,
        export_normals=True,
        export_tangents=False,
        export_materials="EXPORT",
        export_image_format="AUTO",
        export_extras=False,
        export_draco_mesh_compression_enable=False,
    )
    if extra:
        kwargs.update(extra)
    # KHR_lights_punctual has no shadow flag: stamp Blender's own one (use_shadow, on by default)
    # on every light as a custom property, which the exporter writes as the light's
    # extensions.KHR_lights_punctual.lights[i].extras only with export_extras; the engine's
    # converter reads extras.meter_cast_shadow (Blender stores the bool as 1 / 0).
    for lamp in bpy.data.lights:
        lamp[SHADOW_PROP] = bool(lamp.use_shadow)
    if bpy.data.lights:
        kwargs["export_extras"] = True
    bpy.ops.export_scene.gltf(**kwargs)
    print("exported", path, os.path.getsize(path), "bytes")


def set_linear(action):
    """Linear interpolation on every key: a value-driven animation must be exactly linear between
    the keyed values (frame k = value k), never eased."""
    for fc in action.fcurves:
        for kp in fc.keyframe_points:
            kp.interpolation = "LINEAR"


class MeshBuilder:
    """Accumulates polygons from several pieces (primitives, converted text) into ONE mesh, so an
    icon made of many shapes is one glTF node and one draw: what an artist gets from Ctrl+J."""

    def __init__(self):
        self.verts = []
        self.faces = []

    def add(self, verts, faces, offset=(0.0, 0.0, 0.0), rot_z=0.0, scale=1.0):
        c, s = math.cos(rot_z), math.sin(rot_z)
        base = len(self.verts)
        for (x, y, z) in verts:
            x, y = x * scale, y * scale
            self.verts.append((c * x - s * y + offset[0], s * x + c * y + offset[1],
                               z * scale + offset[2]))
        for f in faces:
            self.faces.append(tuple(base + i for i in f))
        return self

    def poly(self, pts2d, z=0.0, **kw):
        """A flat convex-or-fan-able polygon facing +Z (points CCW)."""
        return self.add([(x, y, z) for (x, y) in pts2d], [tuple(range(len(pts2d)))], **kw)

    def rect(self, x0, y0, x1, y1, z=0.0, **kw):
        return self.poly([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], z, **kw)

    def ring(self, r_in, r_out, segments, a0=0.0, a1=2.0 * math.pi, z=0.0, **kw):
        full = abs((a1 - a0) - 2.0 * math.pi) < 1e-9
        n = segments if full else segments + 1
        v = []
        for i in range(n):
            a = a0 + (a1 - a0) * i / segments
            v.append((r_in * math.cos(a), r_in * math.sin(a), z))
            v.append((r_out * math.cos(a), r_out * math.sin(a), z))
        f = [(2 * i, 2 * i + 1, 2 * ((i + 1) % n) + 1, 2 * ((i + 1) % n)) for i in range(segments)]
        return self.add(v, f, **kw)

    def disc(self, r, segments, a0=0.0, a1=2.0 * math.pi, z=0.0, **kw):
        full = abs((a1 - a0) - 2.0 * math.pi) < 1e-9
        n = segments if full else segments + 1
        v = [(0.0, 0.0, z)] + [(r * math.cos(a0 + (a1 - a0) * i / segments),
                                r * math.sin(a0 + (a1 - a0) * i / segments), z) for i in range(n)]
        f = [(0, 1 + i, 1 + (i + 1) % n) for i in range(segments)]
        return self.add(v, f, **kw)

    def text(self, body, size, align="CENTER", z=0.0, **kw):
        v, f = text_polygons(body, size, align, z)
        return self.add(v, f, **kw)

    def build(self, name, mat=None, location=(0, 0, 0), parent=None):
        return mesh_from_data(name, self.verts, self.faces, mat, location, parent)


def text_polygons(body, size, align="CENTER", z=0.0, resolution=2):
    """Blender text (built-in Bfont) converted to mesh polygons, as the artist's 'Convert to Mesh'.
    Returns (verts, faces) centred horizontally per `align` and vertically on the cap height.
    resolution 2 keeps glyph outlines at a few dozen vertices (the scenes must stay compact)."""
    curve = bpy.data.curves.new("tmp_text", "FONT")
    curve.body = body
    curve.size = size
    curve.align_x = align
    curve.align_y = "CENTER"
    curve.resolution_u = resolution
    curve.fill_mode = "FRONT"
    obj = bpy.data.objects.new("tmp_text", curve)
    bpy.context.scene.collection.objects.link(obj)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    ev = obj.evaluated_get(depsgraph)
    mesh = ev.to_mesh()
    verts = [(v.co.x, v.co.y, v.co.z + z) for v in mesh.vertices]
    faces = [tuple(p.vertices) for p in mesh.polygons]
    ev.to_mesh_clear()
    bpy.data.objects.remove(obj)
    bpy.data.curves.remove(curve)
    return verts, faces


def text_object(name, body, size, mat=None, location=(0, 0, 0), align="CENTER", parent=None,
                rot_z=0.0):
    v, f = text_polygons(body, size, align)
    obj = mesh_from_data(name, v, f, mat, location, parent)
    obj.rotation_euler = (0.0, 0.0, rot_z)
    return obj


def planar_uv(obj, x0, y0, size_x, size_y):
    """UVs from the object's local XY (u right, v up), for flat faces carrying a texture."""
    mesh = obj.data
    uv = mesh.uv_layers.new(name="UVMap")
    for loop in mesh.loops:
        co = mesh.vertices[loop.vertex_index].co
        uv.data[loop.index].uv = ((co.x - x0) / size_x, (co.y - y0) / size_y)


def empty(name, location, parent=None):
    """An empty: exported as a glTF node with no mesh; the engine anchors text at its origin."""
    obj = bpy.data.objects.new(name, None)
    obj.empty_display_type = "PLAIN_AXES"
    obj.empty_display_size = 0.2
    bpy.context.scene.collection.objects.link(obj)
    obj.location = location
    link(obj, parent)
    return obj


def image_from_rgb(name, width, height, rgb_rows):
    """A Blender image from a flat list of floats (RGBA, bottom row first), stored as 8-bit PNG
    inside the .blend and written into the .glb by the exporter."""
    img = bpy.data.images.new(name, width, height, alpha=False, float_buffer=False)
    img.colorspace_settings.name = "Non-Color"
    img.pixels.foreach_set(rgb_rows)
    img.file_format = "PNG"
    img.pack()
    return img


def write_scene_config(path, config):
    """Writes a meter-scene-config/1 file with one binding / group per line: reviewable diffs
    when a binding changes, instead of a 600-line indent dump."""
    import json

    def dump(v):
        return json.dumps(v, ensure_ascii=False)

    lines = ["{"]
    items = list(config.items())
    for i, (key, value) in enumerate(items):
        comma = "," if i + 1 < len(items) else ""
        if isinstance(value, list) and value and all(isinstance(e, dict) for e in value):
            lines.append(f"  {dump(key)}: [")
            for j, e in enumerate(value):
                lines.append("    " + dump(e) + ("," if j + 1 < len(value) else ""))
            lines.append("  ]" + comma)
        else:
            lines.append(f"  {dump(key)}: {dump(value)}{comma}")
    lines.append("}")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
    json.loads(open(path, encoding="utf-8").read())  # never commit a file the engine cannot parse
