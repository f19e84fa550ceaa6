# SPDX-License-Identifier: Apache-2.0
"""Edit-to-next-image latency of the viewport session for a vertex move in a scene of many
objects (not a ctest; figures in docs/hosts.md, "Viewport").

blender -b -noaudio --factory-startup --python tests/blender/bench_viewport_edit.py -- \
    --module-dir build/lib/python [--objects 200] [--edits 7] [--plugin-root plugins/blender]

The scene: N cubes (own meshes, Subdivision level 2: 192 triangles each), a sun, a camera.
A Session is synced as view_update does (viewport camera, 8 samples, 264x186). Each edit
moves one vertex of a cube (mesh.vertices[i].co, mesh.update()); the time is from the edit to
the end of the first render pass after it: view_layer.update() (depsgraph evaluation +
apply_updates from depsgraph_update_post), a full_sync when apply_updates asks for a rebuild
(what view_update does), then render_pass(). --plugin-root selects the add-on sources (an
older checkout's plugins/blender measures "before").
"""
import os
import statistics
import sys
import time

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    out = {"module_dir": os.path.join(ROOT, "build", "lib", "python"), "objects": 200,
           "edits": 7, "plugin_root": os.path.join(ROOT, "plugins", "blender")}
    for i in range(0, len(argv) - 1):
        k = argv[i].lstrip("-").replace("-", "_")
        if k in out:
            out[k] = type(out[k])(argv[i + 1])
    return out


A = args()
sys.path.insert(0, A["module_dir"])
sys.path.insert(0, A["plugin_root"])
from principled_blender import export, session  # noqa: E402

W, H = 264, 186


def build(n):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    world = bpy.data.worlds.new("World")
    world.color = (0.05, 0.05, 0.05)
    scene.world = world
    mat = bpy.data.materials.new("Grey")
    mat.use_nodes = True
    side = int(n ** 0.5 + 0.999)
    cubes = []
    for i in range(n):
        bpy.ops.mesh.primitive_cube_add(size=0.6, location=(i % side - side / 2,
                                                           i // side - side / 2, 0.3))
        c = bpy.context.active_object
        c.data.materials.append(mat)
        c.modifiers.new("Subdiv", "SUBSURF").levels = 2
        cubes.append(c)
    bpy.ops.object.light_add(type="SUN", location=(0, 0, 10))
    bpy.ops.object.camera_add(location=(0, -side * 1.2, side * 1.0), rotation=(0.8, 0, 0))
    scene.camera = bpy.context.active_object
    return scene, cubes


def main():
    scene, cubes = build(A["objects"])
    dg = bpy.context.evaluated_depsgraph_get()
    cam = scene.camera
    view = (cam.matrix_world.copy(), export.camera_params(cam.data, W, H))
    s = session.Session(settings={"convergedSamplesPerPixel": 8, "maxDepth": 4,
                                  "defaultLighting": 0})
    t0 = time.perf_counter()
    s.full_sync(dg, W, H, view_camera=view)
    s.delegate.render_pass()
    print(f"bench: {len(cubes)} objects, "
          f"{sum(m.triangles for m in s.export.meshes.values())} triangles; first image after "
          f"a full sync {1000 * (time.perf_counter() - t0):.0f} ms")
    s.delegate.render()
    plain = []
    for _ in range(5):  # a restart without an edit: the pass alone
        s.delegate.set_attribute("/World/Environment", "inputs:color", (0.05, 0.05, 0.05))
        t0 = time.perf_counter()
        s.delegate.render_pass()
        plain.append(time.perf_counter() - t0)
    print(f"bench: first pass after a restart without geometry edits: median "
          f"{1000 * statistics.median(plain):.1f} ms")
    results = []

    def handler(_scene, depsgraph):
        results.append(s.apply_updates(depsgraph, depsgraph.updates))

    bpy.app.handlers.depsgraph_update_post.append(handler)
    times, rebuilds = [], 0
    for k in range(A["edits"]):
        cube = cubes[(k * 37) % len(cubes)]
        n0 = len(results)
        t0 = time.perf_counter()
        cube.data.vertices[k % 8].co.z += 0.1
        cube.data.update()
        bpy.context.view_layer.update()
        t_update = time.perf_counter() - t0
        if any(r["rebuild"] for r in results[n0:]):
            rebuilds += 1
            s.full_sync(bpy.context.evaluated_depsgraph_get(), W, H, view_camera=view)
        s.delegate.render_pass()
        times.append(time.perf_counter() - t0)
        print(f"bench: edit {k}: {1000 * times[-1]:.1f} ms to the next image "
              f"(update {1000 * t_update:.1f} ms; {results[n0:]})")
        s.delegate.render()
    bpy.app.handlers.depsgraph_update_post.remove(handler)
    s.close()
    print(f"bench: vertex move, {len(cubes)} objects: median {1000 * statistics.median(times):.1f}"
          f" ms, min {1000 * min(times):.1f} ms, max {1000 * max(times):.1f} ms to the next "
          f"image; {rebuilds}/{len(times)} edits rebuilt (plugin {A['plugin_root']})")
    sys.stdout.flush()
    os._exit(0)


main()
