# SPDX-License-Identifier: Apache-2.0
"""Saves the add-on test scene (tests/blender/test_render.py) as a .blend file, its plane
texture packed, for command-line renders:

blender -b -noaudio --factory-startup --python tests/blender/make_scene.py -- --out DIR
BLENDER_USER_SCRIPTS=... blender -b DIR/scene.blend -E PRINCIPLED -f 1
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402

import test_render  # noqa: E402

out = test_render.A["out"] or "."
os.makedirs(out, exist_ok=True)
test_render.principled_blender.register()
scene = test_render.build_scene()[0]
bpy.data.images["PlaneTex"].pack()
scene.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
scene.render.filepath = os.path.join(os.path.abspath(out), "render_")
path = os.path.join(os.path.abspath(out), "scene.blend")
bpy.ops.wm.save_as_mainfile(filepath=path)
print("saved", path)
