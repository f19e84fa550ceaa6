# SPDX-License-Identifier: Apache-2.0
"""Headless Blender test of the add-on's Cycles bakes of procedural inputs (bake.py).

blender -b -noaudio --factory-startup --python tests/blender/test_bake.py -- \
    [--module-dir build/lib/python]

Two planes under an overhead delta sun (strength pi: a Lambert plane's radiance is its
albedo) seen by an overhead orthographic camera, world black:
- left: Principled Base Color <- Color Ramp (dark blue | orange) <- Wave texture bands;
- right: Principled Alpha <- Checker Fac through a Math node (a scalar input, red channel).
Final renders with "Bake Procedural Textures" on and off are compared with Cycles: the mean
absolute difference with baking must be a small fraction of the one without (socket values).
Also checked: the materials' node trees, the objects' material slots and bpy.data's
materials/images/objects/scenes are unchanged by the render; a second render of the unchanged
scene bakes nothing (session cache); editing the ramp bakes again; a plane without UVs keeps
the socket value with a warning.
Off the main thread (interactive F12, simulated) nothing is baked; the Bake Procedural
Textures operator fills the cache such a render then uses.
Export level: four scalar inputs take two bakes (three packed one per channel), each
texture holding its own value; bakes per (material, object) for a two-slot grid, a shared material, an
instanced copy (shares its object's bake) and a text object (not baked, warned).
Mix Shader of two BSDFs with a constant Fac (export.mix_shader_params): blended inputs, checked
against Cycles for Diffuse/Diffuse and Principled (baked base colour)/Diffuse.
Exit code 0 = pass.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402
import numpy as np  # noqa: E402

import test_render as tr  # noqa: E402  (argument parsing, module path, check())
from principled_blender import bake, export  # noqa: E402

check = tr.check
W, H = 100, 50
SAMPLES = 64


def scene_setup():
    # 20 px per unit: each plane is 40 x 40 px
    return tr.overhead_sun_scene(W, H, SAMPLES, 5.0)


def plane(x, name):
    bpy.ops.mesh.primitive_plane_add(size=2.0, location=(x, 0, 0))
    obj = bpy.context.active_object
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    b = m.node_tree.nodes["Principled BSDF"]
    b.inputs["Specular"].default_value = 0.0
    b.inputs["Roughness"].default_value = 1.0
    obj.data.materials.append(m)
    return obj, m, m.node_tree, b


def build():
    scene = scene_setup()
    _o, ramp_mat, nt, b = plane(-1.2, "RampWave")
    wave = nt.nodes.new("ShaderNodeTexWave")
    wave.inputs["Scale"].default_value = 1.5
    wave.inputs["Distortion"].default_value = 0.0
    ramp = nt.nodes.new("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].color = (0.02, 0.05, 0.3, 1)
    ramp.color_ramp.elements[1].color = (0.9, 0.45, 0.05, 1)
    nt.links.new(wave.outputs["Fac"], ramp.inputs["Fac"])
    nt.links.new(ramp.outputs["Color"], b.inputs["Base Color"])
    b.inputs["Base Color"].default_value = (0.8, 0.8, 0.8, 1)  # what the old export used
    _o, alpha_mat, nt, b = plane(1.2, "CheckerAlpha")
    b.inputs["Base Color"].default_value = (0.6, 0.6, 0.6, 1)
    ck = nt.nodes.new("ShaderNodeTexChecker")
    ck.inputs["Scale"].default_value = 2.0
    mth = nt.nodes.new("ShaderNodeMath")
    mth.operation = "MULTIPLY_ADD"
    mth.inputs[1].default_value = 0.6
    mth.inputs[2].default_value = 0.2  # alpha 0.2 | 0.8
    nt.links.new(ck.outputs["Fac"], mth.inputs[0])
    nt.links.new(mth.outputs["Value"], b.inputs["Alpha"])
    return scene, (ramp_mat, alpha_mat)


def tree_state(m):
    nt = m.node_tree
    return (len(nt.nodes), sorted(n.name for n in nt.nodes),
            sorted((ln.from_node.name, ln.from_socket.identifier, ln.to_node.name,
                    ln.to_socket.identifier) for ln in nt.links),
            nt.nodes.active.name if nt.nodes.active else None,
            [e.color[:] for n in nt.nodes if n.type == "VALTORGB"
             for e in n.color_ramp.elements])


def data_state():
    """Names in bpy.data (less the Render Result image any render creates)."""
    return {k: sorted(x.name for x in getattr(bpy.data, k) if x.name != "Render Result")
            for k in ("materials", "images", "objects", "scenes", "meshes")}


def slots_state():
    return {o.name: [(s.link, s.material.name if s.material else None)
                     for s in o.material_slots] for o in bpy.data.objects}


class CountBakes:
    """Counts Baker._bake calls (actual Cycles bakes) during a with block."""

    def __enter__(self):
        self.n = 0
        self.orig = bake.Baker._bake
        me = self

        def counted(this, *a, **k):
            me.n += 1
            return me.orig(this, *a, **k)

        bake.Baker._bake = counted
        return self

    def __exit__(self, *exc):
        bake.Baker._bake = self.orig


def mean_abs(a, b):
    return float(np.abs(a[:, :, :3] - b[:, :, :3]).mean())


def test_bake_vs_cycles():
    scene, mats = build()
    trees = [tree_state(m) for m in mats]
    data, slots = data_state(), slots_state()
    bake.CACHE.clear()
    with CountBakes() as c1:
        baked = tr.render_combined(scene)
    check(c1.n == 2, f"first render: {c1.n} Cycles bakes (2: Base Color, Alpha)")
    check([tree_state(m) for m in mats] == trees,
          "node trees unchanged by the bake (nodes, links, active node, ramp colours)")
    after = data_state()
    check(after == data, "bpy.data materials/images/objects/scenes/meshes unchanged "
          f"({ {k: (data[k], v) for k, v in after.items() if v != data[k]} })")
    check(slots_state() == slots, "objects' material slots unchanged")
    with CountBakes() as c2:
        again = tr.render_combined(scene)
    check(c2.n == 0, f"second render of the unchanged scene: {c2.n} bakes (session cache)")
    check(mean_abs(again, baked) < 1e-6, "the cached bake renders the same image")
    scene.principled.bake_procedural = False
    old = tr.render_combined(scene)
    scene.principled.bake_procedural = True
    cyc = tr.render_cycles(scene, "bake", SAMPLES)
    scene.render.engine = "PRINCIPLED"
    for name, sl in (("Base Color <- Color Ramp <- Wave", np.s_[5:45, 6:46]),
                     ("Alpha <- Math <- Checker", np.s_[5:45, 54:94])):
        d_new = mean_abs(baked[sl], cyc[sl])
        d_old = mean_abs(old[sl], cyc[sl])
        ref = float(cyc[sl][:, :, :3].mean())
        print(f"     {name}: mean |add-on - Cycles| baked {d_new:.4f}, socket value {d_old:.4f} "
              f"(Cycles mean {ref:.4f})")
        check(d_new < 0.08 * ref and d_old > 4 * d_new,
              f"{name}: baked {d_new / ref:.1%} of the mean off Cycles (< 8 %), the socket "
              f"value {d_old / ref:.1%} (> 4x)")
    # An edit of the ramp: the node-tree fingerprint changes, so it bakes again.
    ramp = next(n for n in mats[0].node_tree.nodes if n.type == "VALTORGB")
    ramp.color_ramp.elements[1].color = (0.1, 0.9, 0.1, 1)
    with CountBakes() as c3:
        edited = tr.render_combined(scene)
    left = edited[5:45, 6:46, :3].mean(axis=(0, 1))
    check(c3.n == 1 and left[1] > left[0] * 2,
          f"ramp edit: {c3.n} bake (the edited material only), plane now green {left.round(3)}")


class StubBuilder:
    """A SceneBuilder stand-in recording material inputs, textures and bindings."""

    def __init__(self):
        self.inputs, self.textures, self.bindings = {}, {}, {}

    def __getattr__(self, name):
        return lambda *a, **k: None

    def set_material_input(self, path, k, v):
        self.inputs[(path, k)] = v

    def set_material_texture(self, path, k, file, channel):
        self.textures[(path, k)] = (file, channel)

    def bind_material(self, prim, material):
        self.bindings[prim] = material


def stub_export(resolution=32):
    b = StubBuilder()
    ex = export.SceneExport(type("P", (), {"SceneBuilder": staticmethod(lambda: b)}),
                            bpy.context.evaluated_depsgraph_get(),
                            os.path.join(tr.A["out"] or "/tmp", "principled-bake-tex"), W, H,
                            baker=bake.Baker(resolution))
    ex.build()
    return ex, b


def test_slots_shared_instances():
    """Export-level: a plane with two procedural materials in two slots, a second plane sharing
    one of them, a collection instance of the first plane, a text object with a procedural
    material: bakes per (material, object), one material prim per pair, instances reuse theirs,
    non-mesh objects keep the socket value (warned)."""
    scene, mats = build()
    ramp_mat, alpha_mat = mats
    a = next(o for o in bpy.data.objects if o.active_material == ramp_mat)
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=4, y_subdivisions=4, size=1.0,
                                    location=(0, 2, 0))
    grid = bpy.context.active_object  # two slots, both procedural, half the faces each
    grid.data.materials.append(ramp_mat)
    grid.data.materials.append(alpha_mat)
    for p in grid.data.polygons:
        p.material_index = int(p.center.x > 0)
    coll = bpy.data.collections.new("Inst")
    coll.objects.link(a.copy())
    inst = bpy.data.objects.new("Instancer", None)
    inst.instance_type, inst.instance_collection = "COLLECTION", coll
    inst.location = (0, -2, 0)
    scene.collection.objects.link(inst)
    bpy.ops.object.text_add(location=(0, 4, 0))
    txt = bpy.context.active_object
    txt.data.materials.append(ramp_mat)
    bake.CACHE.clear()
    with CountBakes() as c:
        ex, b = stub_export()
    keys = sorted(ex.bakes)
    copy = coll.objects[0].name  # the instanced copy of the plane (same mesh and matrix)
    want = sorted([("RampWave", a.name), ("CheckerAlpha", "Plane.001"), ("RampWave", grid.name),
                   ("CheckerAlpha", grid.name), ("RampWave", txt.name), ("RampWave", copy)])
    check(keys == want, f"bakes per (material, object): {keys}")
    # The instanced copy has the plane's mesh and matrix: it shares the plane's bake (the
    # cache key). The text object is not baked.
    check(c.n == 4, f"{c.n} Cycles bakes (4: RampWave on Plane, CheckerAlpha on Plane.001, both "
          "on the grid; the instanced copy reuses the plane's)")
    check(any("FONT" in w and "RampWave" in w for w in ex.warnings),
          "a text object with a procedural material: warned, socket value")
    tex = {p: k for (p, k) in b.textures}
    grid_mats = sorted({m for prim, m in b.bindings.items() if grid.name in prim})
    check(len(grid_mats) == 2 and all(m in tex for m in grid_mats),
          f"the grid's two slots: two textured material prims {grid_mats}")
    ramp_prims = sorted({m for prim, m in b.bindings.items()
                         if m.startswith("/World/Looks/RampWave")})
    check(len(ramp_prims) == 4 and all(m.replace("/World/Looks/", "").isidentifier()
                                       for m in ramp_prims),
          f"RampWave: one prim per object (plane, grid, text, instanced copy) {ramp_prims}")


def test_interactive_prebake():
    """An interactive F12 renders off the main thread, where Cycles cannot bake (simulated:
    Baker.available() False): without the cache the inputs keep their socket values; after the
    Bake Procedural Textures operator (main thread) the render uses its bakes, baking nothing."""
    scene, mats = build()
    bake.CACHE.clear()
    available = bake.Baker.__dict__["available"]  # the staticmethod itself
    bake.Baker.available = staticmethod(lambda: False)
    try:
        with CountBakes() as c1:
            cold = tr.render_combined(scene)
        bake.Baker.available = available
        with CountBakes() as c2:
            r = bpy.ops.principled.bake_procedural()
        bake.Baker.available = staticmethod(lambda: False)
        with CountBakes() as c3:
            warm = tr.render_combined(scene)
    finally:
        bake.Baker.available = available
    ramp = np.s_[5:45, 6:46]
    cold_c, warm_c = cold[ramp][:, :, :3].mean(), warm[ramp][:, :, :3].std()
    check(c1.n == 0 and abs(cold_c - 0.8) < 0.02,
          f"off the main thread, empty cache: {c1.n} bakes, the ramp plane at the socket value "
          f"(mean {cold_c:.3f} ~ 0.8)")
    check("FINISHED" in r and c2.n == 2, f"the operator baked {c2.n} inputs ({r})")
    check(c3.n == 0 and warm_c > 0.1,
          f"off the main thread after the operator: {c3.n} bakes, the ramp shows (std {warm_c:.3f})")


def read_pfm(path):
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF"
        w, h = (int(x) for x in f.readline().split())
        f.readline()
        return np.frombuffer(f.read(), "<f4").reshape(h, w, 3)


def test_packed_scalars():
    """Four scalar inputs fed by Math nodes (constants 0.3, 0.6, 0.9 and a Clearcoat Roughness
    0.2): two Cycles bakes (three scalars share one, one per channel), each texture holds its
    own value (Clearcoat Roughness as gloss (0.1 - 0.04) / 0.099)."""
    scene_setup()
    _o, m, nt, b = plane(0, "Scalars")
    want = {"Roughness": ("roughness", 0.3), "Metallic": ("metallic", 0.6),
            "Specular": ("specular", 0.9),
            "Clearcoat Roughness": ("clearcoatGloss", (0.1 - 0.04) / 0.099)}
    for name, v in (("Roughness", 0.3), ("Metallic", 0.6), ("Specular", 0.9),
                    ("Clearcoat Roughness", 0.2)):
        mth = nt.nodes.new("ShaderNodeMath")
        mth.operation = "ADD"
        mth.inputs[0].default_value, mth.inputs[1].default_value = v - 0.1, 0.1
        nt.links.new(mth.outputs[0], b.inputs[name])
    bake.CACHE.clear()
    with CountBakes() as c:
        ex, bld = stub_export()
    check(c.n == 2, f"four scalar inputs: {c.n} Cycles bakes (2: three packed + one)")
    got = {k: (read_pfm(f)[:, :, 0].mean(), ch) for (_p, k), (f, ch) in bld.textures.items()}
    for name, (usd, v) in want.items():
        g, ch = got.get(usd, (float("nan"), None))
        check(abs(g - v) < 1e-4 and ch == "r",
              f"{name} -> {usd}: baked {g:.4f} = {v:.4f}, channel {ch}")


def test_no_uvs():
    scene, mats = build()
    obj = next(o for o in bpy.data.objects if o.active_material == mats[0])
    obj.data.uv_layers.remove(obj.data.uv_layers[0])
    ex = export.SceneExport(None, bpy.context.evaluated_depsgraph_get(),
                            os.path.join(tr.A["out"] or "/tmp", "principled-bake-tex"), W, H,
                            baker=bake.Baker(64))

    class B:  # a SceneBuilder stand-in recording the material inputs
        def __init__(self):
            self.inputs, self.textures = {}, {}

        def __getattr__(self, name):
            return lambda *a, **k: None

        def set_material_input(self, path, k, v):
            self.inputs[(path, k)] = v

        def set_material_texture(self, path, k, file, channel):
            self.textures[(path, k)] = file

    b = B()
    ex.p = type("P", (), {"SceneBuilder": staticmethod(lambda: b)})
    ex.build()
    uv_warn = [w for w in ex.warnings if "no UV map" in w]
    check(len(uv_warn) == 1, f"plane without UVs: one warning ({uv_warn[:1]})")
    tex_inputs = sorted(k for (_p, k) in b.textures)
    check(tex_inputs == ["opacity"],
          f"only the plane with UVs gets a baked texture ({tex_inputs})")
    # A bake that fails inside Cycles' operator (an unknown UV map): BakeError, and the
    # temporary copies are gone all the same.
    data, trees = data_state(), [tree_state(m) for m in mats]
    bk = bake.Baker(32)
    obj = next(o for o in bpy.data.objects if o.active_material == mats[1])
    b = mats[1].node_tree.nodes["Principled BSDF"]
    try:
        bk.bake(obj, mats[1], b.name, b.inputs["Alpha"].identifier, ("x", "fail"), "NoSuchUV")
        raised = None
    except bake.BakeError as e:
        raised = str(e)
    finally:
        bk.close()
    check(raised is not None and data_state() == data and
          [tree_state(m) for m in mats] == trees,
          f"failed bake: BakeError ({raised}), bpy.data and node trees unchanged")


def test_mix_shader():
    """Mix Shader cheap case (export.mix_shader_params): inputs blended linearly by a constant
    Fac. Left: Diffuse red / Diffuse blue at Fac 0.3 (exact for two Lambert lobes). Right:
    Principled with a baked Color Ramp base colour / Diffuse grey at Fac 0.4 (the baked texture
    scaled by 0.6 plus 0.4 grey). Overhead sun and camera: Burley diffuse is Lambert there."""
    scene = scene_setup()
    _o, m1, nt, b = plane(-1.2, "MixDiffuse")
    mix = nt.nodes.new("ShaderNodeMixShader")
    mix.inputs["Fac"].default_value = 0.3
    d1, d2 = nt.nodes.new("ShaderNodeBsdfDiffuse"), nt.nodes.new("ShaderNodeBsdfDiffuse")
    d1.inputs["Color"].default_value = (0.8, 0.1, 0.1, 1)
    d2.inputs["Color"].default_value = (0.1, 0.2, 0.8, 1)
    nt.links.new(d1.outputs[0], mix.inputs[1])
    nt.links.new(d2.outputs[0], mix.inputs[2])
    nt.links.new(mix.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
    inputs, links, warns = export.material_params(m1, None)
    want = [0.7 * 0.8 + 0.3 * 0.1, 0.7 * 0.1 + 0.3 * 0.2, 0.7 * 0.1 + 0.3 * 0.8]
    check(np.allclose(inputs["diffuseColor"], want) and
          any("approximation" in w for w in warns),
          f"Mix Shader of two Diffuse BSDFs: diffuseColor {np.round(inputs['diffuseColor'], 4)}"
          f" = {np.round(want, 4)}, warned as an approximation")
    # Nested cut-out: Mix(0.5, Mix(0.25, Transparent, Principled P), Diffuse D). Cycles:
    # 0.375 T + 0.125 P + 0.5 D, i.e. opacity 0.625 and a visible surface 0.2 P + 0.8 D.
    mt = bpy.data.materials.new("NestedCutout")
    mt.use_nodes = True
    t = mt.node_tree
    p = t.nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = (0.2, 0.4, 0.6, 1)
    tr_ = t.nodes.new("ShaderNodeBsdfTransparent")
    inner, outer = t.nodes.new("ShaderNodeMixShader"), t.nodes.new("ShaderNodeMixShader")
    inner.inputs[0].default_value, outer.inputs[0].default_value = 0.25, 0.5
    dd = t.nodes.new("ShaderNodeBsdfDiffuse")
    dd.inputs["Color"].default_value = (1, 0, 0, 1)
    t.links.new(tr_.outputs[0], inner.inputs[1])
    t.links.new(p.outputs[0], inner.inputs[2])
    t.links.new(inner.outputs[0], outer.inputs[1])
    t.links.new(dd.outputs[0], outer.inputs[2])
    t.links.new(outer.outputs[0], t.nodes["Material Output"].inputs["Surface"])
    inputs, _l, _w = export.material_params(mt, None)
    check(abs(inputs["opacity"] - 0.625) < 1e-6 and
          np.allclose(inputs["diffuseColor"], [0.84, 0.08, 0.12]),
          f"nested Transparent mix: opacity {inputs['opacity']:.4f} = 0.625, colour "
          f"{np.round(inputs['diffuseColor'], 4).tolist()} = 0.2 P + 0.8 D (opacity-weighted)")
    _o, m2, nt, b = plane(1.2, "MixBaked")
    ramp = nt.nodes.new("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].color = (0.02, 0.05, 0.3, 1)
    ramp.color_ramp.elements[1].color = (0.9, 0.45, 0.05, 1)
    wave = nt.nodes.new("ShaderNodeTexWave")
    wave.inputs["Distortion"].default_value = 0.0
    nt.links.new(wave.outputs["Fac"], ramp.inputs["Fac"])
    nt.links.new(ramp.outputs["Color"], b.inputs["Base Color"])
    mix = nt.nodes.new("ShaderNodeMixShader")
    mix.inputs["Fac"].default_value = 0.4
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (0.5, 0.5, 0.5, 1)
    nt.links.new(b.outputs[0], mix.inputs[1])
    nt.links.new(d.outputs[0], mix.inputs[2])
    nt.links.new(mix.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
    ours = tr.render_combined(scene)
    cyc = tr.render_cycles(scene, "bake-mix", SAMPLES)
    scene.render.engine = "PRINCIPLED"
    for name, sl in (("Diffuse/Diffuse Fac 0.3", np.s_[5:45, 6:46]),
                     ("Principled (baked ramp)/Diffuse Fac 0.4", np.s_[5:45, 54:94])):
        d_ = mean_abs(ours[sl], cyc[sl])
        ref = float(cyc[sl][:, :, :3].mean())
        check(d_ < 0.05 * ref, f"Mix Shader {name}: mean |add-on - Cycles| {d_:.4f} "
              f"({d_ / ref:.1%} of Cycles' mean {ref:.4f}, < 5 %)")


tr.run_main(test_bake_vs_cycles, test_interactive_prebake, test_no_uvs, test_packed_scalars,
            test_slots_shared_instances, test_mix_shader)
