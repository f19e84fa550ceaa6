# SPDX-License-Identifier: Apache-2.0
"""Headless Blender test of the add-on's translation through shader node groups and of the
Add Shader (export.GNode/GSocket, export.add_shader_params, bake.Baker._source).

blender -b -noaudio --factory-startup --python tests/blender/test_groups.py -- \
    [--module-dir build/lib/python]

Three planes under an overhead delta sun (strength pi: a Lambert plane's radiance is its
albedo), an overhead orthographic camera, world black, each compared with Cycles:
- left: a group "Outer" on the output (through a reroute) holding a reroute and a nested group
  "Inner" holding a Principled BSDF whose Base Color comes from Outer's Color input (a group
  input reached through two group levels);
- middle: a group on the output holding Wave -> Color Ramp -> Principled Base Color, the Wave
  Scale from the group's input: a bake of a socket inside a group (exposed on temporary copies);
- right: Add Shader of a Diffuse BSDF and an Emission shader.
Before this translation all three used the viewport display colour. Then a Principled
Normal <- Bump <- Wave under a tilted sun: the baked tangent-space normal map against Cycles
(the bump was ignored before). Also checked: node trees
(the materials' and the groups') and bpy.data (node groups included) unchanged by the render.
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
W, H = 150, 50
SAMPLES = 64
COLS = {"left": np.s_[5:45, 7:47], "middle": np.s_[5:45, 55:95], "right": np.s_[5:45, 103:143]}


def scene_setup():
    # 20 px per unit: each plane is 40 x 40 px
    return tr.overhead_sun_scene(W, H, SAMPLES, 7.5)


def plane(x, name):
    bpy.ops.mesh.primitive_plane_add(size=2.0, location=(x, 0, 0))
    obj = bpy.context.active_object
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.remove(nt.nodes["Principled BSDF"])
    obj.data.materials.append(m)
    m.diffuse_color = (0.8, 0.8, 0.8, 1)  # what the export used before
    return m, nt, nt.nodes["Material Output"]


def principled(nt):
    b = nt.nodes.new("ShaderNodeBsdfPrincipled")
    b.inputs["Specular"].default_value = 0.0
    b.inputs["Roughness"].default_value = 1.0
    return b


def group(name, inputs=(), outputs=()):
    g = bpy.data.node_groups.new(name, "ShaderNodeTree")
    for kind, n in inputs:
        g.inputs.new(kind, n)
    for kind, n in outputs:
        g.outputs.new(kind, n)
    gi, go = g.nodes.new("NodeGroupInput"), g.nodes.new("NodeGroupOutput")
    return g, gi, go


def build():
    scene = scene_setup()
    # Left: Outer{ reroute, Inner{ Principled(Base Color <- input) } } on the output.
    inner, gi, go = group("Inner", [("NodeSocketColor", "Color")], [("NodeSocketShader", "BSDF")])
    b = principled(inner)
    inner.links.new(gi.outputs["Color"], b.inputs["Base Color"])
    inner.links.new(b.outputs[0], go.inputs["BSDF"])
    outer, gi, go = group("Outer", [("NodeSocketColor", "Color")], [("NodeSocketShader", "BSDF")])
    ginner = outer.nodes.new("ShaderNodeGroup")
    ginner.node_tree = inner
    rr = outer.nodes.new("NodeReroute")
    outer.links.new(gi.outputs["Color"], ginner.inputs["Color"])
    outer.links.new(ginner.outputs["BSDF"], rr.inputs[0])
    outer.links.new(rr.outputs[0], go.inputs["BSDF"])
    m1, nt, out = plane(-2.4, "GroupPrincipled")
    gn = nt.nodes.new("ShaderNodeGroup")
    gn.node_tree = outer
    gn.inputs["Color"].default_value = (0.1, 0.6, 0.2, 1)
    rr = nt.nodes.new("NodeReroute")
    nt.links.new(gn.outputs["BSDF"], rr.inputs[0])
    nt.links.new(rr.outputs[0], out.inputs["Surface"])
    # Middle: a group holding Wave -> Color Ramp -> Principled, Wave Scale from its input.
    rg, gi, go = group("RampPrincipled", [("NodeSocketFloat", "Scale")],
                       [("NodeSocketShader", "BSDF")])
    wave = rg.nodes.new("ShaderNodeTexWave")
    wave.inputs["Distortion"].default_value = 0.0
    ramp = rg.nodes.new("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].color = (0.02, 0.05, 0.3, 1)
    ramp.color_ramp.elements[1].color = (0.9, 0.45, 0.05, 1)
    b = principled(rg)
    rg.links.new(gi.outputs["Scale"], wave.inputs["Scale"])
    rg.links.new(wave.outputs["Fac"], ramp.inputs["Fac"])
    rg.links.new(ramp.outputs["Color"], b.inputs["Base Color"])
    rg.links.new(b.outputs[0], go.inputs["BSDF"])
    m2, nt, out = plane(0.0, "GroupRamp")
    gn = nt.nodes.new("ShaderNodeGroup")
    gn.node_tree = rg
    gn.inputs["Scale"].default_value = 1.5
    nt.links.new(gn.outputs["BSDF"], out.inputs["Surface"])
    # Right: Add Shader (Diffuse + Emission).
    m3, nt, out = plane(2.4, "AddDiffuseEmission")
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (0.4, 0.3, 0.2, 1)
    e = nt.nodes.new("ShaderNodeEmission")
    e.inputs["Color"].default_value = (0.1, 0.2, 0.4, 1)
    e.inputs["Strength"].default_value = 1.0
    add = nt.nodes.new("ShaderNodeAddShader")
    nt.links.new(d.outputs[0], add.inputs[0])
    nt.links.new(e.outputs[0], add.inputs[1])
    nt.links.new(add.outputs[0], out.inputs["Surface"])
    return scene, (m1, m2, m3)


def tree_state(nt):
    return (sorted((n.name, n.bl_idname, getattr(n, "node_tree", None) and n.node_tree.name)
                   for n in nt.nodes),
            sorted((ln.from_node.name, ln.from_socket.identifier, ln.to_node.name,
                    ln.to_socket.identifier) for ln in nt.links),
            [s.identifier for s in nt.outputs], [s.identifier for s in nt.inputs])


def all_trees():
    return ({m.name: tree_state(m.node_tree) for m in bpy.data.materials if m.node_tree},
            {g.name: tree_state(g) for g in bpy.data.node_groups})


def data_state():
    return {k: sorted(x.name for x in getattr(bpy.data, k) if x.name != "Render Result")
            for k in ("materials", "images", "objects", "scenes", "meshes", "node_groups")}


def mean_abs(a, b):
    return float(np.abs(a[:, :, :3] - b[:, :, :3]).mean())


def test_params():
    """Translation only: the nested group's Principled gets the outer group node's colour."""
    _scene, (m1, _m2, m3) = build()
    inputs, _links, warns = export.material_params(m1, None)
    check(np.allclose(inputs["diffuseColor"], (0.1, 0.6, 0.2)) and inputs["specular"] == 0.0,
          f"Principled in nested groups: diffuseColor {np.round(inputs['diffuseColor'], 3)} "
          "from the outer group node's input")
    node = export.shading_node(m1)
    check(node.key == export.PATH_SEP.join(["Group", "Group", "Principled BSDF"]),
          f"its key names the group nodes: {node.key.split(export.PATH_SEP)}")
    inputs, _links, _w = export.material_params(m3, None)
    check(np.allclose(inputs["diffuseColor"], (0.4, 0.3, 0.2)) and
          np.allclose(inputs["emissiveColor"], (0.1, 0.2, 0.4)),
          f"Add Shader Diffuse + Emission: diffuse {inputs['diffuseColor']}, emission "
          f"{inputs['emissiveColor']}")


def test_muted():
    """A muted link is ignored and a muted node passes its input through, as in Cycles."""
    m = bpy.data.materials.new("Muted")
    m.use_nodes = True
    nt = m.node_tree
    b = nt.nodes["Principled BSDF"]  # the one on the output
    b.inputs["Base Color"].default_value = (0.3, 0.3, 0.3, 1.0)
    rgb = nt.nodes.new("ShaderNodeRGB")
    rgb.outputs[0].default_value = (0.9, 0.1, 0.1, 1.0)
    link = nt.links.new(rgb.outputs[0], b.inputs["Base Color"])
    link.is_muted = True
    inputs, _l, _w = export.material_params(m, None)
    check(np.allclose(inputs["diffuseColor"], (0.3, 0.3, 0.3)),
          f"muted link: the socket value {np.round(inputs['diffuseColor'], 3)}")
    link.is_muted = False
    gamma = nt.nodes.new("ShaderNodeGamma")  # Color in, Color out: muted, it passes Color
    gamma.inputs["Gamma"].default_value = 4.0
    nt.links.new(rgb.outputs[0], gamma.inputs["Color"])
    nt.links.new(gamma.outputs[0], b.inputs["Base Color"])
    gamma.mute = True
    inputs, _l, _w = export.material_params(m, None)
    check(np.allclose(inputs["diffuseColor"], (0.9, 0.1, 0.1)),
          f"muted Gamma node: its input passes through {np.round(inputs['diffuseColor'], 3)}")
    bpy.data.materials.remove(m)


def test_vs_cycles():
    scene, mats = build()
    trees, data = all_trees(), data_state()
    bake.CACHE.clear()
    ours = tr.render_combined(scene)
    check(all_trees() == trees, "node trees of the materials and groups unchanged by the render")
    after = data_state()
    check(after == data, "bpy.data (node groups included) unchanged "
          f"({ {k: (data[k], v) for k, v in after.items() if v != data[k]} })")
    cyc = tr.render_cycles(scene, "groups", SAMPLES)
    scene.render.engine = "PRINCIPLED"
    # The old translation: the viewport display colour (0.8 grey) on all three.
    for name, where, tol in (("Principled in nested groups (+ reroutes)", "left", 0.03),
                             ("group with Wave -> Ramp -> Principled (baked)", "middle", 0.05),
                             ("Add Shader Diffuse + Emission", "right", 0.03)):
        sl = COLS[where]
        d = mean_abs(ours[sl], cyc[sl])
        ref = float(cyc[sl][:, :, :3].mean())
        old = float(np.abs(0.8 - cyc[sl][:, :, :3]).mean())
        print(f"     {name}: mean |add-on - Cycles| {d:.4f}, viewport colour {old:.4f} "
              f"(Cycles mean {ref:.4f})")
        check(d < tol * ref and old > 5 * d,
              f"{name}: {d / ref:.1%} of the mean off Cycles (< {tol:.0%}); the viewport colour "
              f"{old / ref:.1%}")


def test_bump():
    """Principled Normal <- Bump <- Wave under a tilted sun: baked into a tangent-space normal
    map (Cycles' NORMAL bake) against ignoring the bump (bake off)."""
    scene = scene_setup()
    sun = next(o for o in bpy.data.objects if o.type == "LIGHT")
    sun.rotation_euler = (0.0, 0.7, 0.0)
    m, nt, out = plane(0.0, "Bumped")
    b = principled(nt)
    b.inputs["Base Color"].default_value = (0.8, 0.8, 0.8, 1)
    wave = nt.nodes.new("ShaderNodeTexWave")
    wave.inputs["Scale"].default_value = 1.5
    wave.inputs["Distortion"].default_value = 0.0
    bump = nt.nodes.new("ShaderNodeBump")
    bump.inputs["Strength"].default_value = 1.0
    bump.inputs["Distance"].default_value = 0.2
    nt.links.new(wave.outputs["Fac"], bump.inputs["Height"])
    nt.links.new(bump.outputs["Normal"], b.inputs["Normal"])
    nt.links.new(b.outputs[0], out.inputs["Surface"])
    trees, data = all_trees(), data_state()
    bake.CACHE.clear()
    ours = tr.render_combined(scene)
    check(all_trees() == trees and data_state() == data,
          "node trees and bpy.data unchanged by the normal bake")
    scene.principled.bake_procedural = False
    flat = tr.render_combined(scene)
    scene.principled.bake_procedural = True
    cyc = tr.render_cycles(scene, "groups-bump", SAMPLES)
    scene.render.engine = "PRINCIPLED"
    sl = COLS["middle"]
    d, d_old = mean_abs(ours[sl], cyc[sl]), mean_abs(flat[sl], cyc[sl])
    ref = float(cyc[sl][:, :, :3].mean())
    print(f"     Bump: mean |add-on - Cycles| baked normal {d:.4f}, bump ignored {d_old:.4f} "
          f"(Cycles mean {ref:.4f})")
    # Residual: Cycles' Bump takes forward differences over the shading point's footprint (a
    # pixel in the render, a texel in the bake), which shifts the bands by part of a pixel.
    check(d < 0.15 * ref and d_old > 3 * d,
          f"Bump -> Normal baked: {d / ref:.1%} of the mean off Cycles (< 15 %), ignored "
          f"{d_old / ref:.1%} (> 3x)")


tr.run_main(test_params, test_muted, test_vs_cycles, test_bump)
