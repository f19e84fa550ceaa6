# SPDX-License-Identifier: Apache-2.0
"""Manual comparison with Cycles 3.4 (not in ctest: ~1 min): the add-on test scene at 192x128,
256 spp, box filter, Standard view, no denoising, rendered by PRINCIPLED and by CYCLES.

blender -b -noaudio --factory-startup --python tests/blender/compare_cycles.py -- \
    --module-dir build/lib/python
"""
import os
import sys
import time
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy, numpy as np
import test_render as T
T.principled_blender.register()
scene = T.build_scene()[0]
scene.render.resolution_x, scene.render.resolution_y = 192, 128
scene.render.image_settings.file_format = "OPEN_EXR"
scene.view_settings.view_transform = "Standard"
scene.view_settings.look = "None"
def render(engine, spp):
    scene.render.engine = engine
    scene.principled.samples = spp
    scene.principled.max_depth = 8
    if engine == "CYCLES":
        c = scene.cycles
        c.samples = spp; c.use_denoising = False; c.use_adaptive_sampling = False
        c.pixel_filter_type = "BOX"; c.filter_width = 1.0; c.max_bounces = 8
        c.sample_clamp_indirect = 0; c.blur_glossy = 0; c.device = "CPU"
        scene.render.threads_mode = "FIXED"; scene.render.threads = 2
    path = os.path.join(T.A["out"] or "/tmp", f"principled-cmp-{engine}.exr")
    scene.render.filepath = path
    t0 = time.perf_counter(); bpy.ops.render.render(write_still=True); dt = time.perf_counter() - t0
    img = bpy.data.images.load(path); px = np.empty(img.size[0]*img.size[1]*4, np.float32); img.pixels.foreach_get(px)
    return px.reshape(img.size[1], img.size[0], 4)[::-1], dt
p, tp = render("PRINCIPLED", 256)
c, tc = render("CYCLES", 256)
H, W = p.shape[:2]
reg = (slice(H//2-8, H//2+8), slice(W//2-24, W//2-8))
print(f"RESULT principled 256spp {tp:.2f}s  cycles 256spp {tc:.2f}s")
print("RESULT plane region principled", p[reg][..., :3].mean((0,1)), "cycles", c[reg][..., :3].mean((0,1)), "analytic", T.ALBEDO)
sph = (slice(H//2-20, H//2-6), slice(W//2+30, W//2+40))
print("RESULT sphere region principled", p[sph][..., :3].mean((0,1)), "cycles", c[sph][..., :3].mean((0,1)))
d = p[..., :3] - c[..., :3]
print("RESULT whole image mean principled", p[..., :3].mean(), "cycles", c[..., :3].mean(), "RMSE", float(np.sqrt((d**2).mean())))
os._exit(0)
