# SPDX-License-Identifier: Apache-2.0
"""Headless Blender test of the add-on's spot lights and world environment texture.

blender -b -noaudio --factory-startup --python tests/blender/test_lights_world.py -- \
    [--module-dir build/lib/python]

- Spot: the conversion of spot_size/spot_blend (export.spot_shaping) against Cycles 3.4's
  edge, then an F12 render of a spot over a Lambertian plane seen by an orthographic camera:
  inside the cone the plane has the closed-form radiance albedo * I cos(t)^2 cos(t) / (pi d^2)
  (I = P/(4 pi), one cos(t) from Cycles' spot attenuation), the edge follows the ShapingAPI
  smoothstep, outside the cone it is black.
- World: an equirectangular image whose left half (u < 0.5) is red, right half blue and top
  quarter green, on a Background of strength 2: a camera looking +Y sees red, -Y blue, +Z
  green (Blender's orientation); with a Mapping node rotating 90 degrees about Z, a camera
  looking +X sees red and -X blue.
Exit code 0 = pass.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402
import numpy as np  # noqa: E402

import test_render as tr  # noqa: E402  (argument parsing, module path, check())
from principled_blender import export, session  # noqa: E402

check = tr.check


render_combined = tr.render_combined


def empty_scene(w, h, spp):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "PRINCIPLED"
    scene.render.resolution_x, scene.render.resolution_y = w, h
    scene.render.resolution_percentage = 100
    scene.principled.samples = spp
    scene.principled.max_depth = 2
    return scene


def cycles_edge(t, half, blend):
    """Cycles 3.4 spot_light_attenuation without its cos(t): smoothstep in cos t."""
    cos_h = math.cos(half)
    if math.cos(t) <= cos_h:
        return 0.0
    m = blend * (1.0 - cos_h)
    x = (math.cos(t) - cos_h) / m if m > 0 else 1.0
    x = min(x, 1.0)
    return x * x * (3 - 2 * x)


def usd_edge(t, angle, softness):
    """ShapingAPI cone (delegate/lightShaping.h): 1 - smoothstep(angle (1 - s), angle, t)."""
    start = angle * (1.0 - softness)
    if t <= start:
        return 1.0
    if t >= angle:
        return 0.0
    x = (t - start) / (angle - start)
    return 1.0 - x * x * (3 - 2 * x)


def test_spot_conversion():
    for size_deg, blend in ((45.0, 0.15), (60.0, 0.3), (120.0, 1.0), (30.0, 0.0)):
        size = math.radians(size_deg)
        sh = export.spot_shaping(size, blend)
        half = 0.5 * size
        check(abs(sh["angle"] - size_deg / 2) < 1e-9 and sh["focus"] == 1.0,
              f"spot {size_deg} deg: cone angle = spot_size/2, focus 1 (Cycles' cos)")
        ang = math.radians(sh["angle"])
        t_in = ang * (1.0 - sh["softness"])
        inner = math.cos(half) + blend * (1.0 - math.cos(half))
        check(abs(math.cos(t_in) - inner) < 1e-9,
              f"spot {size_deg} deg blend {blend}: the edge starts where Cycles' does")
        # Largest difference of the two edge curves (reported in docs/hosts.md).
        ts = np.linspace(0.0, half, 2001)
        diff = max(abs(usd_edge(t, ang, sh["softness"]) - cycles_edge(t, half, blend)) for t in ts)
        print(f"spot {size_deg:5.1f} deg blend {blend:.2f}: softness {sh['softness']:.4f}, "
              f"max |ShapingAPI edge - Cycles edge| = {diff:.4f}")


def test_spot_render():
    W = H = 64
    scene = empty_scene(W, H, 64)
    world = bpy.data.worlds.new("Black")
    world.use_nodes = False
    world.color = (0, 0, 0)
    scene.world = world
    bpy.ops.mesh.primitive_plane_add(size=20.0, location=(0, 0, 0))
    plane = bpy.context.active_object
    mat = bpy.data.materials.new("White")
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    albedo = 0.8
    bsdf.inputs["Base Color"].default_value = (albedo, albedo, albedo, 1)
    bsdf.inputs["Specular"].default_value = 0.0
    bsdf.inputs["Roughness"].default_value = 1.0
    plane.data.materials.append(mat)
    h, P, size, blend = 2.0, 100.0, math.radians(60.0), 0.3
    bpy.ops.object.light_add(type="SPOT", location=(0, 0, h))  # points down its -Z
    spot = bpy.context.active_object
    spot.data.energy = P
    spot.data.shadow_soft_size = 0.01
    spot.data.spot_size = size
    spot.data.spot_blend = blend
    bpy.ops.object.camera_add(location=(0, 0, 5), rotation=(0, 0, 0))
    cam = bpy.context.active_object
    cam.data.type = "ORTHO"
    cam.data.ortho_scale = 4.0
    scene.camera = cam
    img = render_combined(scene)[:, :, 0]
    # Pixel centres on the plane (orthographic, 4 units wide, +Y up in the image).
    c = (np.arange(W) + 0.5) * 4.0 / W - 2.0
    x, y = np.meshgrid(c, -c)
    rho = np.hypot(x, y)
    t = np.arctan2(rho, h)
    sh = export.spot_shaping(size, blend)
    ang, soft = math.radians(sh["angle"]), sh["softness"]
    edge = np.vectorize(lambda a: usd_edge(a, ang, soft))(t)
    # E = I(t) cos(t) / d^2, d = h / cos t, I(t) = P/(4 pi) cos(t) edge(t); L = albedo E / pi.
    expect = albedo / math.pi * P / (4 * math.pi) * np.cos(t) ** 4 / h ** 2 * edge
    t_in = ang * (1 - soft)
    inner = t < t_in - math.radians(1.0)
    err = abs(img[inner].mean() / expect[inner].mean() - 1)
    check(err < 0.02, f"spot: inside the cone at the closed form ({100 * err:.2f}% off)")
    ring = (t > t_in + math.radians(1.0)) & (t < ang - math.radians(1.0))
    err = abs(img[ring].mean() / expect[ring].mean() - 1)
    check(ring.sum() > 50 and err < 0.04,
          f"spot: the soft edge follows the ShapingAPI smoothstep ({100 * err:.2f}% off, "
          f"{int(ring.sum())} px)")
    cyc = np.vectorize(lambda a: cycles_edge(a, 0.5 * size, blend))(t)
    print(f"spot: edge ring mean {img[ring].mean():.4f}, ShapingAPI {expect[ring].mean():.4f}, "
          f"Cycles' curve {(expect[ring] / np.maximum(edge[ring], 1e-9) * cyc[ring]).mean():.4f}")
    outside = t > ang + math.radians(1.0)
    check(outside.sum() > 500 and float(img[outside].max()) < 1e-6,
          f"spot: black outside the cone (max {float(img[outside].max()):.2e})")


def env_world(scene, rotation_z=None):
    w, h = 64, 32
    img = bpy.data.images.new("Sky", w, h, float_buffer=True)
    px = np.zeros((h, w, 4), np.float32)  # rows bottom to top (Blender)
    px[:, :, 3] = 1
    u = (np.arange(w) + 0.5) / w
    v = (np.arange(h) + 0.5) / h
    px[:, u < 0.5, 0] = 1.0           # left half red
    px[:, u >= 0.5, 2] = 1.0          # right half blue
    px[v > 0.75, :, :3] = (0, 1, 0)   # top quarter (around +Z) green
    img.pixels.foreach_set(px.ravel())
    world = bpy.data.worlds.new("Sky")
    world.use_nodes = True
    nt = world.node_tree
    bg = nt.nodes["Background"]
    bg.inputs["Strength"].default_value = 2.0
    env = nt.nodes.new("ShaderNodeTexEnvironment")
    env.image = img
    nt.links.new(env.outputs["Color"], bg.inputs["Color"])
    if rotation_z is not None:
        coord = nt.nodes.new("ShaderNodeTexCoord")
        mapping = nt.nodes.new("ShaderNodeMapping")
        mapping.inputs["Rotation"].default_value = (0.0, 0.0, rotation_z)
        nt.links.new(coord.outputs["Generated"], mapping.inputs["Vector"])
        nt.links.new(mapping.outputs["Vector"], env.inputs["Vector"])
    scene.world = world


def ball_world(scene):
    """A Mirror Ball environment: right half red, left half blue, top quarter green."""
    n = 64
    img = bpy.data.images.new("Ball", n, n, float_buffer=True)
    px = np.zeros((n, n, 4), np.float32)  # rows bottom to top (Blender)
    px[:, :, 3] = 1
    c = (np.arange(n) + 0.5) / n
    px[:, c >= 0.5, 0] = 1.0
    px[:, c < 0.5, 2] = 1.0
    px[c > 0.75, :, :3] = (0, 1, 0)
    img.pixels.foreach_set(px.ravel())
    world = bpy.data.worlds.new("BallSky")
    world.use_nodes = True
    nt = world.node_tree
    env = nt.nodes.new("ShaderNodeTexEnvironment")
    env.image = img
    env.projection = "MIRROR_BALL"
    nt.links.new(env.outputs["Color"], nt.nodes["Background"].inputs["Color"])
    scene.world = world


def look(cam, rotation):
    cam.rotation_euler = rotation
    bpy.context.view_layer.update()


def sky_camera(scene):
    """A narrow (100 mm) camera at the origin looking at the sky, the scene's camera."""
    bpy.ops.object.camera_add(location=(0, 0, 0))
    cam = bpy.context.active_object
    cam.data.lens = 100.0
    scene.camera = cam
    return cam


def test_world_texture():
    scene = empty_scene(8, 8, 4)
    env_world(scene)
    cam = sky_camera(scene)
    r90 = math.pi / 2
    views = {"+Y": ((r90, 0, 0), (2, 0, 0)), "-Y": ((r90, 0, math.pi), (0, 0, 2)),
             "+Z": ((math.pi, 0, 0), (0, 2, 0))}
    for name, (rot, want) in views.items():
        look(cam, rot)
        rgb = render_combined(scene)[:, :, :3].reshape(-1, 3).mean(axis=0)
        check(np.allclose(rgb, want, atol=1e-3),
              f"world texture: camera looking {name} sees {want} ({np.round(rgb, 4).tolist()})")
    # Mapping node rotating the lookup by +90 degrees about Z: +X now sees what +Y saw.
    env_world(scene, rotation_z=r90)
    for name, rot, want in (("+X", (r90, 0, -r90), (2, 0, 0)), ("-X", (r90, 0, r90), (0, 0, 2))):
        look(cam, rot)
        rgb = render_combined(scene)[:, :, :3].reshape(-1, 3).mean(axis=0)
        check(np.allclose(rgb, want, atol=1e-3),
              f"world texture + Mapping Z 90: looking {name} sees {want} "
              f"({np.round(rgb, 4).tolist()})")


def test_mirror_ball_world():
    """A Mirror Ball world texture exports as a mirroredBall dome: each view sees the colour
    Cycles 3.4 sees (+X red, -X blue, +Z green)."""
    scene = empty_scene(8, 8, 4)
    ball_world(scene)
    cam = sky_camera(scene)
    r90 = math.pi / 2
    for name, rot, want in (("+X", (r90, 0, -r90), (1, 0, 0)), ("-X", (r90, 0, r90), (0, 0, 1)),
                            ("+Z", (math.pi, 0, 0), (0, 1, 0))):
        look(cam, rot)
        ours = render_combined(scene)[:, :, :3].reshape(-1, 3).mean(axis=0)
        theirs = tr.render_cycles(scene, "ball-" + name, 4)[:, :, :3].reshape(-1, 3).mean(axis=0)
        scene.render.engine = "PRINCIPLED"
        check(np.allclose(ours, want, atol=0.02) and np.allclose(theirs, want, atol=0.02),
              f"mirror ball world: looking {name} sees {want}: principled "
              f"{np.round(ours, 3).tolist()}, Cycles {np.round(theirs, 3).tolist()}")


def test_light_edits():
    """Every light type exports and renders; viewport edits of a spot's cone, a point's power
    and the world colour go through the delegate's edit calls (no rebuild) and show."""
    scene = empty_scene(48, 48, 4)
    world = bpy.data.worlds.new("Grey")
    world.use_nodes = False
    world.color = (0.05, 0.05, 0.05)
    scene.world = world
    bpy.ops.mesh.primitive_plane_add(size=20.0)
    lights = {}
    for kind, loc in (("POINT", (-3, 3, 1)), ("SPOT", (0, 0, 3)), ("AREA", (3, -3, 1))):
        bpy.ops.object.light_add(type=kind, location=loc)
        lights[kind] = bpy.context.active_object
    bpy.ops.object.light_add(type="AREA", location=(-3, -3, 1))
    lights["AREA"].data.shape = "RECTANGLE"
    bpy.context.active_object.data.shape = "ELLIPSE"
    lights["SPOT"].data.energy = 300.0
    lights["SPOT"].data.spot_size = math.radians(40)
    bpy.ops.object.camera_add(location=(0, 0, 12))
    scene.camera = bpy.context.active_object
    dg = bpy.context.evaluated_depsgraph_get()
    s = session.Session(settings={"convergedSamplesPerPixel": 4})
    log = []

    def handler(_scene, depsgraph):
        log.append(s.apply_updates(depsgraph, depsgraph.updates))

    try:
        s.bind(["color", "primId"])
        warnings = s.full_sync(dg, 48, 48)
        kinds = sorted(k for (k, _xf, _t) in s.export.lights.values())
        check(kinds == ["area", "area", "point", "spot"], f"all light types exported ({kinds})")
        check(not [w for w in warnings if "light" in w], f"no light warnings ({warnings})")
        s.delegate.render()
        base = s.delegate.aov("color", copy=True)
        check(np.isfinite(base).all() and base[:, :, :3].mean() > 0, "lights render")
        bpy.app.handlers.depsgraph_update_post.append(handler)
        lights["SPOT"].data.spot_size = math.radians(80)
        lights["POINT"].data.energy *= 4
        world.color = (0.2, 0.2, 0.2)
        bpy.context.view_layer.update()
        check(log and not any(e["rebuild"] for e in log) and sum(e["lights"] for e in log) >= 2
              and sum(e["world"] for e in log) >= 1,
              f"spot cone, point power and world colour edited without a rebuild ({log})")
        s.delegate.render()
        after = s.delegate.aov("color", copy=True)
        check(after[:, :, :3].mean() > base[:, :, :3].mean() * 1.1, "the edits show")
    finally:
        if handler in bpy.app.handlers.depsgraph_update_post:
            bpy.app.handlers.depsgraph_update_post.remove(handler)
        s.close()


def test_portal():
    """A Cycles portal lamp exports as a UsdLux PortalLight: it emits nothing (the image of a
    floor under a world seen through nothing but the sky is the same with and without it, within
    noise) and the delegate counts no extra light."""
    lamp = None

    def render(with_portal):
        nonlocal lamp
        scene = empty_scene(32, 32, 64)
        world = bpy.data.worlds.new("Sky")
        world.use_nodes = False
        world.color = (0.5, 0.5, 0.5)
        scene.world = world
        bpy.ops.mesh.primitive_plane_add(size=4.0)
        if with_portal:
            bpy.ops.object.light_add(type="AREA", location=(0, 0, 2))
            lamp = bpy.context.active_object
            lamp.data.shape = "RECTANGLE"
            lamp.data.size, lamp.data.size_y = 1.0, 1.0
            lamp.data.energy = 1000.0  # ignored: a portal emits nothing
            lamp.data.cycles.is_portal = True
        bpy.ops.object.camera_add(location=(0, 0, 6))
        scene.camera = bpy.context.active_object
        dg = bpy.context.evaluated_depsgraph_get()
        s = session.Session(settings={"convergedSamplesPerPixel": 64})
        try:
            s.bind(["color"])
            warnings = s.full_sync(dg, 32, 32)
            s.delegate.render()
            result = s.delegate.aov("color", copy=True), warnings, dict(s.delegate.stats())
            if with_portal:
                # Live edits: a portal lamp added in the viewport is a portal too; turning a lamp
                # into (or out of) a portal changes the prim type, so the session rebuilds.
                check(s.export.lights[lamp.name][0] == "portal", "the lamp exports as a portal")
                bpy.ops.object.light_add(type="AREA", location=(1, 0, 2))
                added = bpy.context.active_object
                added.data.energy = 1000.0
                added.data.cycles.is_portal = True
                s._add_light(added)
                check(s.export.lights[added.name][0] == "portal", "a portal added live is a portal")
                lamp.data.cycles.is_portal = False
                check(not s._update_light(lamp), "turning a portal into a lamp asks for a rebuild")
            return result
        finally:
            s.close()

    plain, _, stats_plain = render(False)
    portal, warnings, stats_portal = render(True)
    check(not [w for w in warnings if "light" in w], f"no light warnings ({warnings})")
    check(stats_portal.get("lights") == stats_plain.get("lights"),
          f"the portal is not a light ({stats_portal.get('lights')} against {stats_plain.get('lights')})")
    a, b = portal[:, :, :3].mean(), plain[:, :, :3].mean()
    check(abs(a - b) < 0.02 * b, f"the portal emits nothing (mean {a:.4f} against {b:.4f})")


tr.run_main(test_spot_conversion, test_spot_render, test_world_texture, test_mirror_ball_world, test_light_edits,
            test_portal)
