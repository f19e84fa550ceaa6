# SPDX-License-Identifier: Apache-2.0
"""Headless Blender test of the camera conversion: depth of field against Cycles 3.4.

blender -b -noaudio --factory-startup --python tests/blender/test_camera.py -- \
    [--module-dir build/lib/python]

Blender's camera depth of field (Depth of Field > F-Stop, Focus Distance or Focus Object) becomes
UsdGeomCamera fStop / focusDistance; the lens is millimetres on the add-on's metre stage, so the
delegate's aperture radius lens * 1e-3 / (2 fStop) is Cycles' round aperture. Rendered check: an
emissive half-plane (x >= 0) 4 m in front of a 50 mm f/0.5 camera focused at 1 m, seen by
PRINCIPLED and by CYCLES: the edge profiles (column means) agree, and they differ from the same
render without depth of field (so the check can fail). The focus object variant focuses on an
empty 4 m away: the edge is sharp again. Cycles' Film > Exposure becomes the camera's
UsdGeomCamera exposure (stops): a quarter of the light in both renderers. Exit code 0 = pass.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402
import numpy as np  # noqa: E402

import test_render as tr  # noqa: E402  (argument parsing, module path, check())

check = tr.check
W, H = 128, 16
SPP = 64


def scene_with_edge():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = W, H
    scene.render.resolution_percentage = 100
    world = bpy.data.worlds.new("World")
    world.use_nodes = False
    world.color = (0, 0, 0)
    scene.world = world
    mat = bpy.data.materials.new("Glow")
    mat.use_nodes = True
    nt = mat.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Strength"].default_value = 1.0
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    nt.links.new(em.outputs["Emission"], out.inputs["Surface"])
    # A 20 m square whose left edge is on the camera axis, 4 m ahead (camera looks down -Z).
    bpy.ops.mesh.primitive_plane_add(size=20.0, location=(10.0, 0.0, -4.0))
    bpy.context.object.data.materials.append(mat)
    cam_data = bpy.data.cameras.new("Cam")
    cam_data.lens = 50.0
    cam_data.sensor_fit = "HORIZONTAL"
    cam_data.sensor_width = 36.0
    cam = bpy.data.objects.new("Cam", cam_data)
    scene.collection.objects.link(cam)
    scene.camera = cam
    return scene, cam


def render(scene, engine):
    """Column means of the red channel (the edge profile)."""
    if engine == "CYCLES":
        img = tr.render_cycles(scene, "camera-cycles", SPP)
    else:
        scene.render.engine = engine
        scene.principled.samples = SPP
        img = tr.render_combined(scene)
    return img[..., 0].mean(axis=0)


def render_image(scene, size=None):
    """The add-on's Combined pass (top row first); size: the (width, height) of a render region."""
    scene.render.engine = "PRINCIPLED"
    scene.principled.samples = SPP
    captured = {}
    tr.session.CAPTURE = captured
    try:
        bpy.ops.render.render()
    finally:
        tr.session.CAPTURE = None
    w, h = size or (W, H)
    return captured["Combined"].reshape(h, w, 4)[::-1]


def rms(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)))


def all_tests():
    scene, cam = scene_with_edge()
    sharp = render(scene, "PRINCIPLED")
    check(sharp[: W // 2 - 1].max() < 0.02 and sharp[W // 2 + 1:].min() > 0.98,
          f"no depth of field: a sharp edge (left max {sharp[:W // 2 - 1].max():.3f}, "
          f"right min {sharp[W // 2 + 1:].min():.3f})")
    cam.data.dof.use_dof = True
    cam.data.dof.aperture_fstop = 0.5
    cam.data.dof.focus_distance = 1.0
    ours, cycles = render(scene, "PRINCIPLED"), render(scene, "CYCLES")
    # Blur radius R |1/z - 1/f| on the unit-distance window: 0.05 m * |1/4 - 1/1| = 0.0375,
    # i.e. 0.0375 / (36 / 50) * 128 = 6.7 px.
    d, blur = rms(ours, cycles), rms(ours, sharp)
    check(d < 0.01 and blur > 0.05,
          f"f/0.5 focused at 1 m: principled vs Cycles edge profile RMS {d:.4f} (< 0.01); "
          f"vs no depth of field {blur:.4f} (> 0.05)")
    # Three blades: a triangular aperture (Cycles' corners at rotation + pi/3 + 2 pi k/3); its edge
    # spread differs from the round one's, and must match Cycles' on both sides of the edge.
    cam.data.dof.aperture_blades = 3
    cam.data.dof.aperture_rotation = 0.3
    tri, tri_cycles = render(scene, "PRINCIPLED"), render(scene, "CYCLES")
    check(rms(tri, tri_cycles) < 0.01 and rms(tri, ours) > 2 * rms(tri, tri_cycles),
          f"3 blades: principled vs Cycles RMS {rms(tri, tri_cycles):.4f} (< 0.01); "
          f"vs the round aperture {rms(tri, ours):.4f}")
    cam.data.dof.aperture_blades = 0
    focus = bpy.data.objects.new("Focus", None)
    scene.collection.objects.link(focus)
    focus.location = (3.0, 1.0, -4.0)
    cam.data.dof.focus_object = focus
    refocused = render(scene, "PRINCIPLED")
    check(rms(refocused, sharp) < 0.01,
          f"focus object on the plane: sharp again (RMS vs no depth of field {rms(refocused, sharp):.4f})")
    # A render region (border): only its pixels are traced, and Blender receives a result of the
    # region's size equal, pixel for pixel, to that region of the full image (sampling is per pixel).
    full = render_image(scene)
    scene.render.use_border, scene.render.use_crop_to_border = True, True
    # Edges as Blender truncates them: x 0.3 * 128 = 38.4 -> 38, 0.7 * 128 = 89.6 -> 89 (51
    # wide; rounding would give 52 and fail), y 0.2 * 16 = 3.2 -> 3, 0.9 * 16 = 14.4 -> 14.
    scene.render.border_min_x, scene.render.border_max_x = 0.3, 0.7
    scene.render.border_min_y, scene.render.border_max_y = 0.2, 0.9
    part = render_image(scene, (51, 11))
    same = part.shape == (11, 51, 4) and np.array_equal(part, full[16 - 14:16 - 3, 38:89])
    check(same, f"render region 0.3-0.7 x 0.2-0.9: result {part.shape}, equal to the full image's region: {same}")
    # Without cropping Blender places the region in the full frame; the rest stays empty.
    scene.render.use_crop_to_border = False
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.filepath = os.path.join(tr.A["out"] or "/tmp", "principled-region.exr")
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(scene.render.filepath)
    saved = np.empty(img.size[0] * img.size[1] * 4, np.float32)
    img.pixels.foreach_get(saved)
    saved = saved.reshape(img.size[1], img.size[0], 4)[::-1]
    bpy.data.images.remove(img)
    inside = np.zeros((H, W), bool)
    inside[2:13, 38:89] = True
    check(saved.shape == (H, W, 4) and np.allclose(saved[inside], full[inside], atol=1e-6) and
          not saved[~inside].any(),
          f"render region without cropping: a {saved.shape} image with the region in place and "
          f"nothing outside it")
    scene.render.use_border = False
    # Film > Exposure 0.25 becomes the camera's exposure -2 stops: the image a quarter as bright,
    # as in Cycles.
    scene.cycles.film_exposure = 0.25
    dim, dim_cycles = render(scene, "PRINCIPLED"), render(scene, "CYCLES")
    right = slice(W // 2 + 8, W)
    check(abs(dim[right].mean() - 0.25 * refocused[right].mean()) < 0.01 and
          abs(dim[right].mean() - dim_cycles[right].mean()) < 0.01,
          f"film exposure 0.25: principled {dim[right].mean():.4f}, Cycles {dim_cycles[right].mean():.4f}, "
          f"a quarter of {refocused[right].mean():.4f}")


tr.run_main(all_tests)
