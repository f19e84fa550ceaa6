# SPDX-License-Identifier: Apache-2.0
"""Incremental geometry and object edits of the viewport session (Session.apply_updates),
headless: the test scene of test_render.py is synced once, then edited through Blender's data
API with apply_updates driven from depsgraph_update_post (as view_update does):

1. a vertex of the (textured) plane and of the (subdivided) sphere moves; the plane's texture
   is painted over (its file re-written and re-read),
2. a Subdivision modifier on the plane and an Array modifier on the sphere (topology change,
   the plane's st re-exported),
3. a new cube with a new material, and a new point light,
4. the sphere is deleted; the added cube is edited (vertex + Bevel), hidden and shown again,
5. (a second scene) a mesh shared by a linked duplicate and two collection instances is edited
   (every copy rewritten); deleting an instancer rebuilds (a documented fallback).

Each edit must take the incremental path (no rebuild: the dict apply_updates returns and the
session's rebuild counter), and the image rendered with a fixed seed must match the image of a
fresh full export of the same scene.

blender -b -noaudio --factory-startup --python tests/blender/test_geometry_edits.py -- \
    --module-dir build/lib/python
"""
import contextlib
import os
import sys
import traceback

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402
import numpy as np  # noqa: E402

import test_render as T  # noqa: E402
from principled_blender import session  # noqa: E402

SETTINGS = {"convergedSamplesPerPixel": 16, "seed": 7, "maxDepth": 4, "defaultLighting": 0}


def render(s):
    s.delegate.render()
    return s.delegate.aov("color", copy=True)


def fresh_image():
    """The same scene through a full export into a new delegate."""
    s = session.Session(settings=SETTINGS)
    try:
        s.full_sync(bpy.context.evaluated_depsgraph_get(), T.W, T.H)
        return render(s)
    finally:
        s.close()


def compare(what, s, log, n0, expect):
    entries = log[n0:]
    rebuilt = any(e["rebuild"] for e in entries)
    T.check(entries and not rebuilt and s.rebuilds == 1,
            f"{what}: incremental, no rebuild ({entries}, rebuilds {s.rebuilds})")
    for key, n in expect.items():
        got = sum(e[key] for e in entries)
        T.check(got >= n, f"{what}: {key} = {got} (>= {n})")
    a = render(s)
    b = fresh_image()
    diff = np.abs(a[:, :, :3] - b[:, :, :3])
    mean = float(diff.mean() / max(float(b[:, :, :3].mean()), 1e-9))
    T.check(mean < 0.01 and float(diff.max()) < 0.25,
            f"{what}: image matches a fresh full export (mean abs diff {100 * mean:.3f}% of "
            f"the mean, max {float(diff.max()):.4f})")
    return a


@contextlib.contextmanager
def edit_session():
    """A viewport session whose depsgraph updates, once listen() is called, are applied and
    logged (one apply_updates() result each); an exception in the body is a test failure."""
    s = session.Session(settings=SETTINGS)
    log = []

    def handler(_scene, depsgraph):
        log.append(s.apply_updates(depsgraph, depsgraph.updates))

    try:
        yield s, log, lambda: bpy.app.handlers.depsgraph_update_post.append(handler)
    except Exception:
        traceback.print_exc()
        T.failures.append("exception")
    finally:
        if handler in bpy.app.handlers.depsgraph_update_post:
            bpy.app.handlers.depsgraph_update_post.remove(handler)
        s.close()


def main():
    T.principled_blender.register()
    scene, plane, sphere, sun, cam, mat, smat = T.build_scene()
    dg = bpy.context.evaluated_depsgraph_get()
    with edit_session() as (s, log, listen):
        s.full_sync(dg, T.W, T.H)
        img0 = render(s)
        listen()

        n0 = len(log)
        plane.data.vertices[0].co.z += 1.0
        plane.data.update()
        sphere.data.vertices[0].co.z += 0.3
        sphere.data.update()
        bpy.context.view_layer.update()
        img = compare("vertex move", s, log, n0, {"geometry": 2})
        T.check(float(np.abs(img - img0).max()) > 0.05, "the vertex move changed the image")

        # The plane's generated texture painted over (pixels set, as Texture Paint does): its
        # pixels file is written again and the delegate re-reads it; no rebuild.
        n0 = len(log)
        tex = bpy.data.images["PlaneTex"]
        px = np.empty(len(tex.pixels), np.float32)
        tex.pixels.foreach_get(px)
        px.reshape(-1, 4)[:, :3] = (0.1, 0.6, 0.9)
        tex.pixels.foreach_set(px)
        tex.update()
        tex.update_tag()  # what painting does: the depsgraph sends the Image as updated
        bpy.context.view_layer.update()
        img = compare("texture painted", s, log, n0, {"textures": 1})
        T.check(float(np.abs(img - img0).max()) > 0.05, "the painted texture changed the image")

        n0 = len(log)
        plane.modifiers.new("Subdiv", "SUBSURF").levels = 1
        arr = sphere.modifiers.new("Array", "ARRAY")
        arr.count = 2
        arr.relative_offset_displace = (0.0, 1.2, 0.0)
        bpy.context.view_layer.update()
        compare("modifiers (topology)", s, log, n0, {"geometry": 2})

        n0 = len(log)
        bpy.ops.mesh.primitive_cube_add(size=0.8, location=(-1.5, -1.0, 0.4))
        cube = bpy.context.active_object
        cube.name = "NewCube"
        cm = bpy.data.materials.new("CubeMat")
        cm.use_nodes = True
        cm.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = \
            (0.1, 0.7, 0.2, 1)
        cube.data.materials.append(cm)
        bpy.ops.object.light_add(type="POINT", location=(-1.0, 1.0, 1.5))
        bpy.context.active_object.data.energy = 200.0
        bpy.context.view_layer.update()
        compare("added cube + point light", s, log, n0, {"added": 2})

        n0 = len(log)
        bpy.data.objects.remove(sphere)
        bpy.context.view_layer.update()
        compare("deleted sphere", s, log, n0, {"removed": 1})

        n0 = len(log)
        cube.data.vertices[0].co.x -= 0.3  # an added (expanded-layout) mesh edited again
        cube.data.update()
        cube.modifiers.new("Bevel", "BEVEL")
        bpy.context.view_layer.update()
        compare("edited added cube", s, log, n0, {"geometry": 1})

        n0 = len(log)
        cube.hide_viewport = True  # hidden: its prims are removed; shown again: added
        bpy.context.view_layer.update()
        compare("hidden cube", s, log, n0, {"removed": 1})
        n0 = len(log)
        cube.hide_viewport = False
        bpy.context.view_layer.update()
        compare("shown cube", s, log, n0, {"added": 1})


def test_shared_meshes():
    """An object instanced twice by collection instances and a linked duplicate sharing its
    mesh: a vertex move rewrites every copy without a rebuild; deleting an instancer rebuilds
    (documented fallback)."""
    scene, plane, sphere, sun, cam, mat, smat = T.build_scene()
    twin = sphere.copy()  # linked duplicate: the same Mesh datablock
    twin.name = "Twin"
    twin.location = (1.5, 1.6, 0.75)
    scene.collection.objects.link(twin)
    coll = bpy.data.collections.new("Props")
    scene.collection.children.link(coll)
    ball = plane.copy()
    ball.data = sphere.data
    ball.modifiers.clear()
    ball.name = "Shared"
    ball.location = (0, 0, 0.75)
    coll.objects.link(ball)
    scene.collection.children.unlink(coll)  # only seen through its instances
    empties = []
    for i, y in enumerate((-1.6, 0.0)):
        e = bpy.data.objects.new(f"Inst{i}", None)
        e.instance_type = "COLLECTION"
        e.instance_collection = coll
        e.location = (-1.5, y, 0)
        scene.collection.objects.link(e)
        empties.append(e)
    with edit_session() as (s, log, listen):
        s.full_sync(bpy.context.evaluated_depsgraph_get(), T.W, T.H)
        T.check(len(s.export.object_xforms.get("Shared", [])) == 2,
                "instanced object: two copies exported")
        render(s)
        listen()
        n0 = len(log)
        for v in sphere.data.vertices[:40]:
            v.co.z += 0.25
        sphere.data.update()
        bpy.context.view_layer.update()
        compare("shared mesh (linked duplicate + 2 instances) edited", s, log, n0,
                {"geometry": 3})
        n0 = len(log)
        bpy.data.objects.remove(empties[1])
        bpy.context.view_layer.update()
        T.check(any(e["rebuild"] for e in log[n0:]), "deleting an instancer: a rebuild")


def report():
    print(f"{len(T.failures)} failure(s)")
    sys.stdout.flush()
    os._exit(1 if T.failures else 0)


main()
test_shared_meshes()
report()
