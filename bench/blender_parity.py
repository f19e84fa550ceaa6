# SPDX-License-Identifier: Apache-2.0
"""Parity of the Blender add-on (engine PRINCIPLED) against Cycles on small general scenes.

    blender -b -noaudio --factory-startup --python bench/blender_parity.py -- \
        [--out out/parity] [--res 128] [--spp 128] [--max-bounces 8] \
        [--only NAME[,NAME...]] [--module-dir build/lib/python] [--recycle] \
        [--engines cycles,principled] [--set KEY=VALUE[,KEY=VALUE...]]

Builds each scene of SCENES in Blender 3.4 and renders it twice with Cycles (seeds 0 and 1,
SPP samples each: CPU, denoising off, Filter Glossy 0, box filter 1 px, no clamping, adaptive
sampling off, every bounce limit = MAX_BOUNCES, Standard view transform) and twice with
PRINCIPLED (seeds 0 and 1, SPP samples, Max Bounces = MAX_BOUNCES), at RES x RES, both read
back from a float EXR (linear, scene-referred). --recycle reuses Cycles EXRs already in OUT.

Per scene it prints and writes (OUT/parity.json, OUT/parity.md): the mean RGB of each engine
(mean of both seeds), the relative difference of the mean luminance, the RMSE between the
engines, the noise floor (relative difference of the two Cycles seeds' means and their
RMSE / sqrt(2), i.e. the RMSE expected from noise alone), and the same means over the "lit"
region (pixels whose 5x5-blurred luminance, averaged over both engines so the selection is
symmetric, is above the scene's 60th percentile) and over each scene's named box. Diff images:
OUT/<scene>.png = Cycles | PRINCIPLED | |difference| x 4 (sRGB, clipped).

--set passes render settings to the delegate on top of the add-on's (e.g. --set
specularFresnel=dielectric: the Disney specular Fresnel shaped like Cycles'); values that read
as numbers are passed as int or float, others as tokens.

The add-on and module are put on sys.path here (--factory-startup ignores user scripts), the
same way tests/blender does.
"""
import json
import math
import os
import struct
import sys
import time
import zlib

import bpy
import numpy as np
from mathutils import Matrix, Vector

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    o = {"out": os.path.join(ROOT, "out", "parity"), "res": 128, "spp": 128,
         "max_bounces": 8, "only": None, "recycle": False, "engines": "cycles,principled",
         "set": "",
         "module_dir": os.path.join(ROOT, "build", "lib", "python")}
    i = 0
    while i < len(argv):
        k = argv[i].lstrip("-").replace("-", "_")
        if k == "recycle":
            o["recycle"] = True
            i += 1
            continue
        v = argv[i + 1]
        o[k] = int(v) if k in ("res", "spp", "max_bounces") else v
        i += 2
    return o


A = parse_args()
sys.path.insert(0, A["module_dir"])
sys.path.insert(0, os.path.join(ROOT, "plugins", "blender"))
import principled_blender  # noqa: E402

try:
    principled_blender.register()
except ValueError:
    pass  # already registered


def setting_value(text):
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


EXTRA_SETTINGS = {}
for item in filter(None, A["set"].split(",")):
    if "=" not in item:
        raise SystemExit(f"bench/blender_parity.py: --set expects KEY=VALUE, got '{item}'")
    key, text = item.split("=", 1)
    EXTRA_SETTINGS[key.strip()] = setting_value(text.strip())
if EXTRA_SETTINGS:
    _addon_settings = principled_blender._settings

    def _settings_and_extra(scene, viewport):
        out = _addon_settings(scene, viewport)
        out.update(EXTRA_SETTINGS)
        return out

    principled_blender._settings = _settings_and_extra

OUT = os.path.abspath(A["out"])
os.makedirs(OUT, exist_ok=True)
RES, SPP, MAXB = A["res"], A["spp"], A["max_bounces"]


# ---- scene building helpers ------------------------------------------------------------
def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    principled_blender_ensure()
    sc = bpy.context.scene
    sc.render.resolution_x = sc.render.resolution_y = RES
    sc.render.resolution_percentage = 100
    sc.render.film_transparent = False
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.image_settings.color_depth = "32"
    sc.render.image_settings.color_mode = "RGBA"
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0, 0, 0, 1)
    sc.world = world
    return sc


def principled_blender_ensure():
    # read_factory_settings unregisters nothing of ours, but the Scene property may be gone.
    if not hasattr(bpy.types.Scene, "principled"):
        principled_blender.register()


def world_color(sc, rgb, strength=1.0):
    bg = sc.world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (*rgb, 1.0)
    bg.inputs["Strength"].default_value = strength


def material(name, base=(0.8, 0.8, 0.8), rough=0.5, metallic=0.0, specular=0.5, **kw):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    b = m.node_tree.nodes["Principled BSDF"]
    b.distribution = "GGX"
    b.inputs["Base Color"].default_value = (*base, 1.0)
    b.inputs["Roughness"].default_value = rough
    b.inputs["Metallic"].default_value = metallic
    b.inputs["Specular"].default_value = specular
    for k, v in kw.items():
        sock = b.inputs[k.replace("_", " ")]
        sock.default_value = v
    return m


def link(obj, mat):
    obj.data.materials.clear()
    obj.data.materials.append(mat)
    return obj


def plane(size=10.0, loc=(0, 0, 0), mat=None, rot=(0, 0, 0)):
    bpy.ops.mesh.primitive_plane_add(size=size, location=loc, rotation=rot)
    o = bpy.context.active_object
    return link(o, mat or material("Floor"))


def sphere(r=1.0, loc=(0, 0, 1), mat=None, smooth=True, seg=96, rings=48):
    bpy.ops.mesh.primitive_uv_sphere_add(segments=seg, ring_count=rings, radius=r, location=loc)
    o = bpy.context.active_object
    if smooth:
        bpy.ops.object.shade_smooth()
    return link(o, mat or material("Ball"))


def cube(size=1.0, loc=(0, 0, 0.5), mat=None, rot=(0, 0, 0)):
    bpy.ops.mesh.primitive_cube_add(size=size, location=loc, rotation=rot)
    o = bpy.context.active_object
    return link(o, mat or material("Box"))


def camera(sc, loc=(0, -7, 4), target=(0, 0, 0.6), lens=50.0):
    cd = bpy.data.cameras.new("Cam")
    cd.lens = lens
    cd.sensor_fit = "AUTO"
    co = bpy.data.objects.new("Cam", cd)
    sc.collection.objects.link(co)
    co.location = loc
    d = Vector(target) - Vector(loc)
    co.rotation_euler = d.to_track_quat("-Z", "Y").to_euler()
    sc.camera = co
    return co


def light(sc, kind, loc=(0, 0, 5), target=None, rot=None, **kw):
    ld = bpy.data.lights.new("L_" + kind, kind)
    for k, v in kw.items():
        setattr(ld, k, v)
    lo = bpy.data.objects.new("L_" + kind, ld)
    sc.collection.objects.link(lo)
    lo.location = loc
    if target is not None:
        d = Vector(target) - Vector(loc)
        lo.rotation_euler = d.to_track_quat("-Z", "Y").to_euler()
    elif rot is not None:
        lo.rotation_euler = rot
    return lo


def image_texture_node(mat, image, socket="Base Color", interpolation="Linear"):
    nt = mat.node_tree
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = image
    tex.interpolation = interpolation
    nt.links.new(tex.outputs["Color"], nt.nodes["Principled BSDF"].inputs[socket])
    return tex


def write_png(path, rgb8):
    """Minimal PNG writer (8-bit RGB or RGBA, rows top first)."""
    h, w, nc = rgb8.shape
    raw = b"".join(b"\x00" + rgb8[y].tobytes() for y in range(h))

    def chunk(t, d):
        c = struct.pack(">I", len(d)) + t + d
        return c + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2 if nc == 3 else 6, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def checker_png():
    path = os.path.join(OUT, "checker.png")
    n, cells = 64, 8
    y, x = np.mgrid[0:n, 0:n]
    c = ((x // (n // cells) + y // (n // cells)) % 2).astype(bool)
    img = np.zeros((n, n, 3), np.uint8)
    img[c] = (230, 200, 60)   # sRGB yellow
    img[~c] = (40, 80, 160)   # sRGB blue
    img[:8, :8] = (200, 30, 30)  # one red corner cell marks the orientation (v = 1 at top)
    write_png(path, img)
    return bpy.data.images.load(path)


def bump_normal_png():
    """Tangent-space normal map of 4 x 4 cones tilting the normal up to ~45 degrees (corners)."""
    path = os.path.join(OUT, "normals.png")
    n, cells = 128, 4
    y, x = np.mgrid[0:n, 0:n].astype(np.float64)
    fx = (x + 0.5) / (n / cells) % 1.0 - 0.5
    fy = 0.5 - (y + 0.5) / (n / cells) % 1.0  # image rows go down, v goes up
    nx, ny = fx * 1.4, fy * 1.4
    nz = np.ones_like(nx)
    ln = np.sqrt(nx * nx + ny * ny + nz * nz)
    rgb = np.stack([nx / ln, ny / ln, nz / ln], -1) * 0.5 + 0.5
    write_png(path, np.clip(np.round(rgb * 255), 0, 255).astype(np.uint8))
    im = bpy.data.images.load(path)
    im.colorspace_settings.name = "Non-Color"
    return im


def env_image():
    """Float equirect: warm sky gradient, dark ground, a bright 'sun' blob; 128 x 64."""
    w, h = 128, 64
    im = bpy.data.images.new("Env", w, h, float_buffer=True, alpha=False)
    v = (np.arange(h) + 0.5) / h          # row 0 = bottom (Blender order): v = 0 nadir
    u = (np.arange(w) + 0.5) / w
    U, V = np.meshgrid(u, v)
    px = np.zeros((h, w, 4), np.float32)
    sky = V > 0.5
    t = np.clip((V - 0.5) * 2, 0, 1)
    px[..., 0] = np.where(sky, 0.4 + 0.4 * t, 0.15)
    px[..., 1] = np.where(sky, 0.6 + 0.3 * t, 0.12)
    px[..., 2] = np.where(sky, 1.0, 0.1)
    blob = ((U - 0.3) ** 2 + (V - 0.75) ** 2) < 0.004
    px[blob, :3] = (40.0, 35.0, 30.0)
    if os.environ.get("PARITY_ENV") == "noblob":  # diagnosis: the gradient alone
        px[blob, :3] = px[np.roll(blob, 20, axis=0), :3].mean(axis=0)
    px[..., 3] = 1.0
    im.pixels.foreach_set(px.ravel())
    return im


# ---- scenes ------------------------------------------------------------------------------
# Each returns {"box": (x0, y0, x1, y1) in pixels of the top-first image, "note": str}.

def s_glass(sc):
    camera(sc, (0, -6, 3), (0, 0, 0.8))
    plane(mat=material("Floor", (0.7, 0.7, 0.7), 0.6))
    sphere(1.0, (0, 0, 1.0), material("Glass", (1, 1, 1), 0.0, Transmission=1.0, IOR=1.45))
    light(sc, "SUN", rot=(math.radians(35), 0, math.radians(30)), energy=3.0,
          angle=math.radians(3))
    world_color(sc, (0.2, 0.25, 0.3))
    return {"box": (40, 30, 88, 80)}  # the sphere


def s_checker(sc):
    camera(sc, (0, -5, 5), (0, 0, 0))
    img = checker_png()
    m = material("Checker", rough=0.8, specular=0.3)
    image_texture_node(m, img)
    plane(4.0, mat=m, rot=(0, 0, math.radians(20)))
    # Out of frame: Cycles' lamps are invisible to camera rays, principled's are not.
    light(sc, "POINT", loc=(-2.5, -1.0, 4.5), energy=800.0, shadow_soft_size=0.3)
    world_color(sc, (0.02, 0.02, 0.02))
    return {"box": (44, 44, 84, 84)}


def s_checker_mapping(sc):
    """The checker through Texture Coordinate UV -> Mapping (scale 3 x 2, rotation 30 deg,
    offset) -> Image Texture: tiling as real scenes use it."""
    camera(sc, (0, -5, 5), (0, 0, 0))
    m = material("Tiled", rough=0.8, specular=0.3)
    tex = image_texture_node(m, checker_png())
    nt = m.node_tree
    mp = nt.nodes.new("ShaderNodeMapping")
    mp.inputs["Location"].default_value = (0.1, 0.2, 0.0)
    mp.inputs["Rotation"].default_value = (0.0, 0.0, math.radians(30))
    mp.inputs["Scale"].default_value = (3.0, 2.0, 1.0)
    tc = nt.nodes.new("ShaderNodeTexCoord")
    nt.links.new(tc.outputs["UV"], mp.inputs["Vector"])
    nt.links.new(mp.outputs["Vector"], tex.inputs["Vector"])
    plane(4.0, mat=m, rot=(0, 0, math.radians(20)))
    light(sc, "SUN", rot=(math.radians(30), 0, math.radians(20)), energy=3.0, angle=0.0)
    world_color(sc, (0.02, 0.02, 0.02))
    return {"box": (44, 44, 84, 84)}


def s_area_square(sc):
    camera(sc)
    plane(mat=material("Floor", (0.8, 0.8, 0.8), 0.7))
    cube(1.2, (0, 0, 0.6), material("Red", (0.8, 0.1, 0.1), 0.5), rot=(0, 0, math.radians(30)))
    light(sc, "AREA", loc=(1.5, -1.5, 4.5), target=(0, 0, 0), energy=500.0, shape="SQUARE",
          size=1.0)  # out of frame (camera visibility differs)
    return {"box": (44, 50, 84, 90)}  # the cube


def s_area_disk_metal(sc):
    camera(sc)
    plane(mat=material("Floor", (0.5, 0.5, 0.5), 0.5))
    sphere(1.0, (0, 0, 1), material("Gold", (1.0, 0.77, 0.34), 0.35, metallic=1.0))
    light(sc, "AREA", loc=(-2, -1, 3.5), target=(0, 0, 0.5), energy=500.0, shape="DISK", size=1.5)
    return {"box": (40, 35, 88, 85)}


def s_spot(sc):
    camera(sc, (0, -7, 6), (0, 0, 0))
    plane(mat=material("Floor", (0.8, 0.8, 0.8), 0.9))
    sphere(0.7, (0.5, 0.5, 0.7), material("Ball", (0.2, 0.6, 0.2), 0.4))
    light(sc, "SPOT", loc=(0, 0, 4), target=(0, 0, 0), energy=1000.0, shadow_soft_size=0.2,
          spot_size=math.radians(50), spot_blend=0.2)
    return {"box": (36, 36, 92, 92)}


def s_emission_mesh(sc):
    camera(sc)
    plane(mat=material("Floor", (0.8, 0.8, 0.8), 0.8))
    cube(0.8, (0.8, 0.5, 0.4), material("Lamp", (0, 0, 0), 0.5, specular=0.0,
                                        Emission=(1.0, 0.6, 0.3, 1.0), Emission_Strength=5.0))
    sphere(0.6, (-0.8, -0.3, 0.6), material("Ball", (0.8, 0.8, 0.8), 0.5))
    return {"box": (20, 50, 64, 100)}  # the lit sphere / floor left of the emitter


def s_emission_shader(sc):
    """An Emission shader node (not the Principled BSDF's Emission) on a mesh: the only light."""
    camera(sc)
    plane(mat=material("Floor", (0.8, 0.8, 0.8), 0.8))
    lamp = bpy.data.materials.new("EmissionShader")
    lamp.use_nodes = True
    nt = lamp.node_tree
    nt.nodes.remove(nt.nodes["Principled BSDF"])
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Color"].default_value = (0.3, 0.6, 1.0, 1.0)
    em.inputs["Strength"].default_value = 8.0
    nt.links.new(em.outputs["Emission"], nt.nodes["Material Output"].inputs["Surface"])
    sphere(0.5, (0.7, 0.3, 0.5), lamp)
    cube(0.8, (-0.8, -0.2, 0.4), material("Box", (0.8, 0.8, 0.8), 0.5))
    return {"box": (20, 50, 64, 100)}


def node_material(name, kind, **values):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.remove(nt.nodes["Principled BSDF"])
    n = nt.nodes.new(kind)
    for k, v in values.items():
        n.inputs[k].default_value = v
    if hasattr(n, "distribution") and kind != "ShaderNodeBsdfDiffuse":
        n.distribution = "GGX"
    nt.links.new(n.outputs["BSDF"], nt.nodes["Material Output"].inputs["Surface"])
    return m


def s_bsdf_nodes(sc):
    """Diffuse, Glossy and Glass BSDF nodes (not the Principled BSDF): a diffuse cube, a rough
    glossy sphere, a glass sphere, on a Principled floor; sun and world colour."""
    camera(sc, (0, -7, 3.5), (0, 0, 0.6))
    plane(mat=material("Floor", (0.6, 0.6, 0.6), 0.7))
    cube(1.0, (-1.6, 0, 0.5), node_material("Diffuse", "ShaderNodeBsdfDiffuse",
                                            Color=(0.2, 0.5, 0.8, 1.0)))
    sphere(0.6, (0.0, 0.3, 0.6), node_material("Glossy", "ShaderNodeBsdfGlossy",
                                              Color=(0.9, 0.6, 0.3, 1.0), Roughness=0.3))
    sphere(0.6, (1.6, 0, 0.6), node_material("Glass", "ShaderNodeBsdfGlass",
                                            Color=(1.0, 1.0, 1.0, 1.0), Roughness=0.0, IOR=1.45))
    light(sc, "SUN", rot=(math.radians(40), 0, math.radians(30)), energy=3.0,
          angle=math.radians(3))
    world_color(sc, (0.15, 0.18, 0.22))
    return {"box": (20, 50, 50, 80)}  # the diffuse cube


def s_world_color(sc):
    camera(sc)
    plane(mat=material("Floor", (0.8, 0.8, 0.8), 0.8))
    sphere(1.0, (0, 0, 1), material("Ball", (0.6, 0.3, 0.2), 0.3))
    world_color(sc, (0.8, 0.9, 1.0), 1.0)
    return {"box": (40, 35, 88, 85)}


def s_world_hdr(sc):
    camera(sc)
    plane(mat=material("Floor", (0.8, 0.8, 0.8), 0.8))
    sphere(1.0, (0, 0, 1), material("Ball", (0.8, 0.8, 0.8), 0.2))
    nt = sc.world.node_tree
    env = nt.nodes.new("ShaderNodeTexEnvironment")
    env.image = env_image()
    # PARITY_ENV_INTERP=Closest checks the nearest-texel dome lookup's share of the difference.
    env.interpolation = os.environ.get("PARITY_ENV_INTERP", "Linear")
    nt.links.new(env.outputs["Color"], nt.nodes["Background"].inputs["Color"])
    return {"box": (40, 35, 88, 85)}


def s_normal_map(sc):
    camera(sc, (0, -4, 5), (0, 0, 0))
    m = material("Bumpy", (0.7, 0.7, 0.7), 0.5)
    tex = m.node_tree.nodes.new("ShaderNodeTexImage")
    tex.image = bump_normal_png()
    nm = m.node_tree.nodes.new("ShaderNodeNormalMap")
    m.node_tree.links.new(tex.outputs["Color"], nm.inputs["Color"])
    # PARITY_NM=flat (diagnosis): the same material without the normal map.
    if os.environ.get("PARITY_NM") != "flat":
        m.node_tree.links.new(nm.outputs["Normal"], m.node_tree.nodes["Principled BSDF"].inputs["Normal"])
    plane(4.0, mat=m)
    light(sc, "SUN", rot=(math.radians(55), 0, math.radians(-40)), energy=3.0,
          angle=math.radians(1))
    world_color(sc, (0.05, 0.05, 0.05))
    return {"box": (32, 32, 96, 96)}


def solid_png(name, rgb8):
    path = os.path.join(OUT, name + ".png")
    write_png(path, np.tile(np.array(rgb8, np.uint8), (4, 4, 1)))
    im = bpy.data.images.load(path)
    im.colorspace_settings.name = "Non-Color"
    return im


def s_normal_tilt(sc):
    """Constant tangent-space normals tilted away from the camera by 10, 25 and 40 degrees
    (left to right) under an overhead sun: Lambert N.L = cos(tilt) in both renderers unless
    the normal is changed. Cycles' ensure_valid_reflection bends normals whose mirror
    direction of the view ray falls below the surface (here tilts beyond ~25 degrees)."""
    camera(sc, (0, -4, 5), (0, 0, 0))
    for i, deg in enumerate((10.0, 25.0, 40.0)):
        a = math.radians(deg)
        rgb = (128, round(255 * (0.5 + 0.5 * math.sin(a))), round(255 * (0.5 + 0.5 * math.cos(a))))
        m = material(f"Tilt{int(deg)}", (0.8, 0.8, 0.8), 1.0, specular=0.5)
        tex = m.node_tree.nodes.new("ShaderNodeTexImage")
        tex.image = solid_png(f"tilt{int(deg)}", rgb)
        nm = m.node_tree.nodes.new("ShaderNodeNormalMap")
        m.node_tree.links.new(tex.outputs["Color"], nm.inputs["Color"])
        m.node_tree.links.new(nm.outputs["Normal"], m.node_tree.nodes["Principled BSDF"].inputs["Normal"])
        plane(1.2, ((i - 1) * 1.3, 0, 0), m)
    light(sc, "SUN", rot=(0, 0, 0), energy=3.0, angle=0.0)
    return {"box": (88, 56, 112, 72)}  # the 40-degree plane


def s_alpha(sc):
    camera(sc, (0, -6, 4), (0, 0, 0.5))
    img = checker_png()
    fm = material("Checker", rough=0.8)
    image_texture_node(fm, img)
    plane(6.0, mat=fm)
    plane(2.0, (0, 0, 1.0), material("Veil", (0.9, 0.1, 0.1), 0.5, Alpha=0.5),
          rot=(math.radians(70), 0, 0))
    light(sc, "SUN", rot=(math.radians(30), 0, math.radians(20)), energy=3.0,
          angle=math.radians(2))
    world_color(sc, (0.1, 0.1, 0.1))
    return {"box": (40, 30, 88, 80)}  # the half-transparent plane


def s_alpha_texture(sc):
    """A cut-out 'leaf': RGBA PNG (green disc, alpha 0 outside, 0.5 in a ring) whose Alpha
    output feeds the Principled Alpha, above a grey floor under a sun."""
    camera(sc, (0, -6, 4), (0, 0, 0.5))
    n = 64
    y, x = np.mgrid[0:n, 0:n]
    r = np.hypot(x + 0.5 - n / 2, y + 0.5 - n / 2) / (n / 2)
    img = np.zeros((n, n, 4), np.uint8)
    img[..., :3] = (60, 170, 50)
    img[..., 3] = np.where(r < 0.6, 255, np.where(r < 0.9, 128, 0))
    path = os.path.join(OUT, "leaf.png")
    write_png(path, img)
    m = material("Leaf", rough=0.6)
    tex = image_texture_node(m, bpy.data.images.load(path))
    m.node_tree.links.new(tex.outputs["Alpha"], m.node_tree.nodes["Principled BSDF"].inputs["Alpha"])
    return leaf_over_floor(sc, m)


def leaf_over_floor(sc, leaf):
    """The cut-out scenes' set: a 2.5 m plane with material `leaf` tilted 60 degrees above a grey
    floor, a 2-degree sun and a dim world; returns the check box."""
    plane(6.0, mat=material("Floor", (0.6, 0.6, 0.6), 0.7))
    plane(2.5, (0, 0, 1.2), leaf, rot=(math.radians(60), 0, 0))
    light(sc, "SUN", rot=(math.radians(30), 0, math.radians(20)), energy=3.0,
          angle=math.radians(2))
    world_color(sc, (0.1, 0.1, 0.1))
    return {"box": (40, 20, 88, 75)}

def s_mix_transparent(sc):
    """The cut-out leaf through the older setup: Mix Shader (Transparent BSDF, Principled BSDF)
    with Fac = Image Alpha."""
    camera(sc, (0, -6, 4), (0, 0, 0.5))
    leaf = os.path.join(OUT, "leaf.png")
    if not os.path.isfile(leaf):
        s_alpha_texture(sc)  # writes it
        reset()
    m = material("Leaf", rough=0.6)
    nt = m.node_tree
    tex = image_texture_node(m, bpy.data.images.load(leaf))
    mix = nt.nodes.new("ShaderNodeMixShader")
    tr_node = nt.nodes.new("ShaderNodeBsdfTransparent")
    nt.links.new(tex.outputs["Alpha"], mix.inputs["Fac"])
    nt.links.new(tr_node.outputs["BSDF"], mix.inputs[1])
    nt.links.new(nt.nodes["Principled BSDF"].outputs["BSDF"], mix.inputs[2])
    nt.links.new(mix.outputs["Shader"], nt.nodes["Material Output"].inputs["Surface"])
    return leaf_over_floor(sc, m)


def s_subsurf_custom(sc):
    camera(sc, (0, -6, 3), (0, 0, 0.8))
    plane(mat=material("Floor", (0.6, 0.6, 0.6), 0.7))
    c = cube(1.2, (-1.0, 0, 0.8), material("Clay", (0.7, 0.5, 0.3), 0.5))
    mod = c.modifiers.new("Subsurf", "SUBSURF")
    mod.levels = mod.render_levels = 2
    bpy.ops.object.shade_smooth()
    # A flat low-poly cylinder made round by custom normals (radial, ignoring the caps).
    bpy.ops.mesh.primitive_cylinder_add(vertices=12, radius=0.6, depth=1.4, location=(1.0, 0, 0.7))
    cy = link(bpy.context.active_object, material("Blue", (0.2, 0.3, 0.8), 0.4))
    me = cy.data
    me.use_auto_smooth = True
    for p in me.polygons:  # before normals_split_custom_set: smooth flags define its fans
        p.use_smooth = True
    normals = []
    for loop in me.loops:
        co = me.vertices[loop.vertex_index].co
        normals.append(Vector((co.x, co.y, 0)).normalized())
    # caps keep a vertical normal
    for p in me.polygons:
        if abs(p.normal.z) > 0.9:
            for li in p.loop_indices:
                normals[li] = Vector((0, 0, 1 if p.normal.z > 0 else -1))
    me.normals_split_custom_set(normals)
    light(sc, "AREA", loc=(0, -3, 4), target=(0, 0, 0.5), energy=600.0, shape="RECTANGLE",
          size=2.0, size_y=0.8)
    world_color(sc, (0.05, 0.05, 0.05))
    return {"box": (20, 40, 108, 90)}


def s_area_in_room(sc):
    """A closed room (cube 4 x 4 x 3 seen from inside) lit by a square area lamp just under the
    ceiling pointing down, out of frame: Cycles' area lamp emits from its front only."""
    camera(sc, (0, -1.9, 1.2), (0, 0, 0.9), lens=20.0)
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0, 0, 1.5))
    room = bpy.context.active_object
    room.scale = (4.0, 4.0, 3.0)
    link(room, material("Walls", (0.7, 0.7, 0.7), 0.8))
    sphere(0.5, (0.6, 0.8, 0.5), material("Ball", (0.7, 0.3, 0.2), 0.5))
    light(sc, "AREA", loc=(0, -1.2, 2.9), rot=(0, 0, 0), energy=200.0, shape="SQUARE", size=1.0)
    return {"box": (40, 50, 90, 100)}


def s_lamps_in_view(sc):
    """Open discrepancy (renderer): a point lamp (r 0.3) and a square area lamp inside the
    frame. Cycles 3.4's lamps are invisible to camera rays; principled's SphereLight and the
    area emitter quad are seen (the lamp's radiance, hundreds of times the scene's)."""
    camera(sc, (0, -7, 4), (0, 0, 0.6))
    plane(mat=material("Floor", (0.8, 0.8, 0.8), 0.7))
    light(sc, "POINT", loc=(-1.5, 0.5, 2.5), energy=300.0, shadow_soft_size=0.3)
    light(sc, "AREA", loc=(1.5, 0.5, 3), target=(0, 0, 0), energy=300.0, shape="SQUARE",
          size=1.0)
    return {"box": (30, 70, 98, 120)}  # the floor (no lamp in it)


# ---- light transport of emitters and lamps behind rough glass ------------------------------
def s_lamp_in_rough_glass(sc):
    """A point lamp (r 0.1) inside a warm-tinted rough glass sphere (Principled Base Color
    (0.9, 0.75, 0.6), Transmission 1, Roughness 0.4, IOR 1.45) over a floor: every light path
    leaves through the rough interface (next-event estimation through rough transmission)."""
    camera(sc, (0, -6, 3), (0, 0, 0.8))
    plane(mat=material("Floor", (0.7, 0.7, 0.7), 0.6))
    # PARITY_GLASS_ROUGHNESS (diagnosis): another roughness for the glass.
    rough = float(os.environ.get("PARITY_GLASS_ROUGHNESS", "0.4"))
    sphere(1.0, (0, 0, 1.0), material("Frosted", (0.9, 0.75, 0.6), rough, Transmission=1.0,
                                      IOR=1.45))
    light(sc, "POINT", loc=(0, 0, 1.0), energy=20.0, shadow_soft_size=0.1)
    return {"box": (20, 80, 108, 120)}  # the floor around the sphere's foot


def emission_image():
    """8 x 8 sRGB PNG, left half warm (255, 160, 80), right half blue (40, 80, 255)."""
    path = os.path.join(OUT, "emission2.png")
    img = np.zeros((8, 8, 3), np.uint8)
    img[:, :4] = (255, 160, 80)
    img[:, 4:] = (40, 80, 255)
    write_png(path, img)
    return bpy.data.images.load(path)


def s_emission_texture(sc):
    """A 2 m upright plane whose Principled Emission is an Image Texture (two colours, EXTEND),
    strength 4, the only light, over a diffuse floor: textured emission sampled by NEE."""
    camera(sc, (0, -6, 4), (0, 0, 0.5))
    plane(mat=material("Floor", (0.8, 0.8, 0.8), 0.9))
    m = material("Screen", (0, 0, 0), 0.5, specular=0.0, Emission_Strength=4.0)
    tex = image_texture_node(m, emission_image(), socket="Emission")
    tex.extension = "EXTEND"
    plane(2.0, (0, 1.0, 1.2), m, rot=(math.radians(90), 0, 0))
    return {"box": (20, 70, 108, 110)}  # the lit floor in front of the screen


def emission_material(name, rgb, strength):
    return material(name, (0, 0, 0), 0.5, specular=0.0, Emission=(*rgb, 1.0),
                    Emission_Strength=strength)


def s_emission_two_slots(sc):
    """One cube with two material slots, both emissive (warm on x < 0, blue on x > 0): the only
    light, over a floor with a grey sphere."""
    camera(sc)
    plane(mat=material("Floor", (0.8, 0.8, 0.8), 0.8))
    c = cube(0.8, (0.6, 0.6, 0.4), emission_material("Warm", (1.0, 0.5, 0.2), 6.0))
    c.data.materials.append(emission_material("Cold", (0.2, 0.4, 1.0), 6.0))
    for p in c.data.polygons:
        p.material_index = 1 if p.center.x > 0.0 else 0
    sphere(0.6, (-0.8, -0.3, 0.6), material("Ball", (0.8, 0.8, 0.8), 0.5))
    return {"box": (20, 50, 64, 100)}


def s_emission_instanced(sc):
    """An emissive sphere (r 0.25) in a collection seen only through four collection-instance
    empties: the instanced copies are the only light (no world light, no lamp)."""
    camera(sc)
    plane(mat=material("Floor", (0.8, 0.8, 0.8), 0.8))
    coll = bpy.data.collections.new("Bulbs")
    sc.collection.children.link(coll)
    bulb = sphere(0.25, (0, 0, 0), emission_material("Bulb", (1.0, 0.8, 0.5), 10.0), seg=32,
                  rings=16)
    for c in list(bulb.users_collection):
        c.objects.unlink(bulb)
    coll.objects.link(bulb)
    sc.collection.children.unlink(coll)  # only its instances are rendered
    for i, (x, y, z) in enumerate(((-1.5, 0.5, 0.6), (1.5, 0.5, 0.6), (-0.5, 1.5, 1.0),
                                   (0.6, -0.8, 0.4))):
        e = bpy.data.objects.new(f"BulbInst{i}", None)
        e.instance_type = "COLLECTION"
        e.instance_collection = coll
        e.location = (x, y, z)
        sc.collection.objects.link(e)
    cube(0.7, (0, 0.2, 0.35), material("Box", (0.8, 0.8, 0.8), 0.5))
    return {"box": (30, 60, 98, 110)}


SCENES = [
    ("glass", s_glass), ("checker_point", s_checker), ("checker_mapping", s_checker_mapping),
    ("area_square", s_area_square),
    ("area_disk_metal", s_area_disk_metal), ("spot", s_spot),
    ("emission_mesh", s_emission_mesh), ("emission_shader", s_emission_shader),
    ("bsdf_nodes", s_bsdf_nodes),
    ("world_color", s_world_color),
    ("world_hdr", s_world_hdr), ("normal_map", s_normal_map), ("normal_tilt", s_normal_tilt), ("alpha", s_alpha),
    ("alpha_texture", s_alpha_texture), ("mix_transparent", s_mix_transparent),
    ("subsurf_custom", s_subsurf_custom), ("area_in_room", s_area_in_room),
    ("lamps_in_view", s_lamps_in_view),
    ("lamp_in_rough_glass", s_lamp_in_rough_glass), ("emission_texture", s_emission_texture),
    ("emission_two_slots", s_emission_two_slots), ("emission_instanced", s_emission_instanced),
]


# ---- rendering ---------------------------------------------------------------------------
def set_props(struct, **props):
    """Sets RNA properties by name, refusing names the struct does not have: Cycles' settings
    are a Python PropertyGroup, which silently keeps a misspelt attribute (this bench once set
    `filter_glossy`, not `blur_glossy`, and so compared against Filter Glossy 1)."""
    rna = struct.bl_rna.properties
    for k, v in props.items():
        if k not in rna:
            raise AttributeError(f"bench/blender_parity.py: {struct.bl_rna.identifier} has no "
                                 f"property '{k}' in Blender {bpy.app.version_string}")
        setattr(struct, k, v)


def cycles_settings(seed):
    """The Cycles settings of a fair comparison (docs/hosts.md, "Parity with Cycles")."""
    return dict(device="CPU", samples=SPP, use_adaptive_sampling=False, use_denoising=False,
                seed=seed, blur_glossy=0.0, sample_clamp_direct=0.0, sample_clamp_indirect=0.0,
                caustics_reflective=True, caustics_refractive=True, max_bounces=MAXB,
                diffuse_bounces=MAXB, glossy_bounces=MAXB, transmission_bounces=MAXB,
                transparent_max_bounces=MAXB, volume_bounces=0, pixel_filter_type="BOX",
                filter_width=1.0)


def setup_cycles(sc, seed):
    sc.render.engine = "CYCLES"
    set_props(sc.cycles, **cycles_settings(seed))
    set_props(sc.render, threads_mode="FIXED", threads=2)


def setup_principled(sc, seed):
    sc.render.engine = "PRINCIPLED"
    sc.principled.samples = SPP
    sc.principled.max_depth = MAXB
    sc.principled.seed = seed
    sc.principled.time_limit = 0.0


def render_to(sc, path):
    sc.render.filepath = path
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    dt = time.perf_counter() - t0
    return dt


def read_exr(path):
    im = bpy.data.images.load(path, check_existing=False)
    w, h = im.size
    px = np.empty(w * h * 4, np.float32)
    im.pixels.foreach_get(px)
    bpy.data.images.remove(im)
    return px.reshape(h, w, 4)[::-1, :, :3].astype(np.float64)  # top row first


LUM = np.array([0.2126, 0.7152, 0.0722])


def blur5(a):
    p = np.pad(a, 2, mode="edge")
    out = np.zeros_like(a)
    for dy in range(5):
        for dx in range(5):
            out += p[dy:dy + a.shape[0], dx:dx + a.shape[1]]
    return out / 25.0


def srgb8(x):
    x = np.clip(x, 0, 1)
    s = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return np.round(s * 255).astype(np.uint8)


def rel(a, b):
    return (a - b) / max(abs(b), 1e-9)


def main():
    only = set(A["only"].split(",")) if A["only"] else None
    rows = []
    for name, fn in SCENES:
        if only and name not in only:
            continue
        sc = reset()
        info = fn(sc)
        imgs = {}
        times = {}
        for eng, setup in (("cycles", setup_cycles), ("principled", setup_principled)):
            if eng not in A["engines"].split(","):
                continue
            for seed in (0, 1):
                path = os.path.join(OUT, f"{name}_{eng}_{seed}.exr")
                if eng == "cycles" and A["recycle"] and os.path.isfile(path):
                    times[f"{eng}{seed}"] = None
                else:
                    setup(sc, seed)
                    times[f"{eng}{seed}"] = render_to(sc, path)
                imgs[(eng, seed)] = read_exr(path)
        if len(imgs) < 4:
            print(f"parity {name}: rendered {sorted(times)}", flush=True)
            continue
        c0, c1 = imgs[("cycles", 0)], imgs[("cycles", 1)]
        p0, p1 = imgs[("principled", 0)], imgs[("principled", 1)]
        cy, pr = 0.5 * (c0 + c1), 0.5 * (p0 + p1)
        lc, lp = cy @ LUM, pr @ LUM
        mask = blur5(0.5 * (lc + lp))
        lit = mask > np.percentile(mask, 60)
        x0, y0, x1, y1 = info["box"]
        box = np.zeros_like(lit)
        box[y0:y1, x0:x1] = True
        # Noise: RMSE between the two seeds of an engine is sqrt(2) x the per-image noise;
        # the RMSE of two means-of-two images from noise alone is that / sqrt(2)... per
        # engine, so expect rmse_noise = sqrt((sc^2 + sp^2) / 2) with s = rmse(seed0, seed1)/2.
        sc_n = np.sqrt(np.mean((c0 - c1) ** 2)) / 2
        sp_n = np.sqrt(np.mean((p0 - p1) ** 2)) / 2
        row = {
            "scene": name,
            "cycles_mean": cy.reshape(-1, 3).mean(0).tolist(),
            "ours_mean": pr.reshape(-1, 3).mean(0).tolist(),
            "rel_mean": rel(lp.mean(), lc.mean()),
            "noise_rel_mean": abs(rel((c0 @ LUM).mean(), (c1 @ LUM).mean())) / math.sqrt(2),
            "rmse": float(np.sqrt(np.mean((cy - pr) ** 2))),
            "rmse_noise": float(math.sqrt(sc_n ** 2 + sp_n ** 2)),
            # Per-pixel noise of one render at SPP samples (std across the two seeds, RGB RMS).
            "std_cycles": float(np.sqrt(np.mean((c0 - c1) ** 2) / 2)),
            "std_ours": float(np.sqrt(np.mean((p0 - p1) ** 2) / 2)),
            "lit_cycles": float(lc[lit].mean()), "lit_ours": float(lp[lit].mean()),
            "rel_lit": rel(lp[lit].mean(), lc[lit].mean()),
            "box_cycles": float(lc[box].mean()), "box_ours": float(lp[box].mean()),
            "rel_box": rel(lp[box].mean(), lc[box].mean()),
            "times": times,
            "principled_settings": EXTRA_SETTINGS,
        }
        rows.append(row)
        strip = np.concatenate([srgb8(cy), srgb8(pr), srgb8(np.abs(cy - pr) * 4)], axis=1)
        write_png(os.path.join(OUT, f"{name}.png"), strip)
        print(f"parity {name:16s} cycles {row['cycles_mean'][0]:.4f} {row['cycles_mean'][1]:.4f} "
              f"{row['cycles_mean'][2]:.4f}  ours {row['ours_mean'][0]:.4f} "
              f"{row['ours_mean'][1]:.4f} {row['ours_mean'][2]:.4f}  rel {row['rel_mean']:+.2%} "
              f"(noise {row['noise_rel_mean']:.2%})  rmse {row['rmse']:.4f} "
              f"(noise {row['rmse_noise']:.4f})  lit {row['rel_lit']:+.2%}  box {row['rel_box']:+.2%}  "
              f"std cycles {row['std_cycles']:.4f} ours {row['std_ours']:.4f}",
              flush=True)
    prev = {}
    jpath = os.path.join(OUT, "parity.json")
    if os.path.isfile(jpath) and only:
        prev = {r["scene"]: r for r in json.load(open(jpath))}
    for r in rows:
        prev[r["scene"]] = r
    allrows = [prev[n] for n, _ in SCENES if n in prev]
    json.dump(allrows, open(jpath, "w"), indent=1)
    with open(os.path.join(OUT, "parity.md"), "w") as f:
        f.write("| scene | Cycles mean RGB | principled mean RGB | rel. diff (lum.) | noise | RMSE | RMSE noise | lit region | box | std Cycles | std principled |\n")
        f.write("|---|---|---|---|---|---|---|---|---|---|---|\n")
        for r in allrows:
            c, o = r["cycles_mean"], r["ours_mean"]
            f.write(f"| {r['scene']} | {c[0]:.4f} {c[1]:.4f} {c[2]:.4f} | {o[0]:.4f} {o[1]:.4f} "
                    f"{o[2]:.4f} | {r['rel_mean']:+.2%} | {r['noise_rel_mean']:.2%} | "
                    f"{r['rmse']:.4f} | {r['rmse_noise']:.4f} | {r['rel_lit']:+.2%} | "
                    f"{r['rel_box']:+.2%} | {r.get('std_cycles', float('nan')):.4f} | "
                    f"{r.get('std_ours', float('nan')):.4f} |\n")
    print("parity: wrote", jpath)


main()
