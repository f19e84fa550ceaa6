# SPDX-License-Identifier: Apache-2.0
"""Viewport test of the principled add-on: Blender with a window (under Xvfb and Mesa's
software OpenGL) renders the test scene in a 3D view set to Rendered shading, so Blender itself
calls view_update and view_draw. After a few redraws the test edits the sphere's material,
then moves the sphere, and checks that the drawn image changes, that neither edit rebuilt the
scene, that the material edit built no BVH and the move rebuilt no mesh.

xvfb-run -a -s "-screen 0 800x600x24" blender --factory-startup -noaudio \
    --python tests/blender/test_viewport.py -- --module-dir build/lib/python
"""
import os
import sys
import time
import traceback

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402
import numpy as np  # noqa: E402

import test_render as T  # noqa: E402
from principled_blender import session  # noqa: E402

if bpy.app.background:
    # ctest treats exit code 77 as skipped (SKIP_RETURN_CODE).
    print("SKIP: the viewport test needs a window: no display server could be started "
          "(install xvfb for xvfb-run; run it without -b)")
    sys.stdout.flush()
    os._exit(77)

T.principled_blender.register()
scene, plane, sphere, sun, cam, mat, smat = T.build_scene(reset=False)
scene.principled.preview_samples = 8
session.CAPTURE = {}
area = next(a for a in bpy.context.screen.areas if a.type == "VIEW_3D")
space = area.spaces.active
space.shading.type = "RENDERED"
space.region_3d.view_perspective = "CAMERA"
for a in bpy.context.screen.areas:
    a.tag_redraw()

state = {"step": 0, "t0": time.perf_counter(), "mark": 0, "edit_time": 0.0}
draws = lambda: session.CAPTURE.get("view_draw", [])  # noqa: E731
results = {}


def finish():
    fails = T.failures
    print(f"{len(fails)} failure(s)")
    sys.stdout.flush()
    os._exit(1 if fails else 0)


def converged_since(mark):
    d = draws()[mark:]
    return len(d) >= 2 and d[-1]["converged"]


def step():
    try:
        if time.perf_counter() - state["t0"] > 90:
            T.check(False, f"viewport test timed out at step {state['step']} "
                           f"({len(draws())} draws)")
            finish()
        d = draws()
        if state["step"] == 0 and converged_since(0):
            T.check(len(d) >= 2, f"view_draw called progressively ({len(d)} draws to converge)")
            state["before"] = d[-1]
            state["mark"] = len(d)
            state["edit_time"] = time.perf_counter()
            smat.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = \
                (0.1, 0.2, 0.9, 1)
            state["step"] = 1
        elif state["step"] == 1 and converged_since(state["mark"]):
            after = d[state["mark"]:]
            first = after[0]["time"] - state["edit_time"]
            print(f"viewport: first redraw {1000 * first:.0f} ms after the material edit "
                  f"(its render pass {1000 * after[0]['pass_seconds']:.0f} ms at "
                  f"{after[0]['size']}; {len(after)} draws to converge, pass times "
                  f"{[round(1000 * x['pass_seconds']) for x in after]} ms)")
            b, a = state["before"], d[-1]
            T.check(a["rebuilds"] == b["rebuilds"], "material edit: no scene rebuild")
            T.check(a["stats"]["blasBuilds"] == b["stats"]["blasBuilds"],
                    "material edit: no BVH build (stats)")
            diff = float(np.abs(a["color"] - b["color"]).max())
            T.check(diff > 0.05, f"drawn image changed after the material edit ({diff:.3f})")
            state["before"] = a
            state["mark"] = len(d)
            state["edit_time"] = time.perf_counter()
            sphere.location.x = -1.5
            state["step"] = 2
        elif state["step"] == 2 and converged_since(state["mark"]):
            b, a = state["before"], d[-1]
            first = d[state["mark"]]["time"] - state["edit_time"]
            print(f"viewport: first redraw {1000 * first:.0f} ms after the transform edit")
            T.check(a["rebuilds"] == b["rebuilds"], "transform edit: no scene rebuild")
            T.check(a["stats"]["meshesRebuilt"] == b["stats"]["meshesRebuilt"],
                    "transform edit: no mesh rebuilt (stats)")
            diff = float(np.abs(a["color"] - b["color"]).max())
            T.check(diff > 0.05, f"drawn image changed after the move ({diff:.3f})")
            finish()
        for a in bpy.context.screen.areas:
            a.tag_redraw()
    except Exception:
        traceback.print_exc()
        T.failures.append("exception")
        finish()
    return 0.05


bpy.app.timers.register(step, first_interval=0.5)
