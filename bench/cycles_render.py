"""Builds a scenes/desc/*.json scene in Blender 3.4 and renders it with Cycles (the peer).

    blender -b -noaudio --factory-startup --python bench/cycles_render.py -- \
        DESC.json OUTDIR --res 128 --threads 2 --spp 4,16,64 [--seed 0] [--max-bounces 8]
        [--seeds 8,4,1]

Writes OUTDIR/cycles_<spp>.exr and OUTDIR/cycles_times.json ({spp: seconds of
bpy.ops.render.render, which includes Cycles' scene sync and BVH build}). With --seeds (one count
per --spp entry) spp[i] is rendered with seeds seed .. seed + n_i - 1 in the same process (one
scene build): seed `seed` is written as above, seed s > `seed` as OUTDIR/cycles_<spp>_seed<s>.exr
with times under the key "<spp>_seed<s>" (independent images for bench/peer_equal_time.py's
expected error).

Conversions (verified in /work/shared/reference/cycles-peer.md; listed in docs/performance.md):
  * axes: USD Y-up -> Blender Z-up, p_b = (x, -z, y); camera/light local frames identical.
  * camera: focal length and horizontalAperture -> lens and sensor_width (sensor_fit HORIZONTAL).
  * DomeLight constant L -> World Background colour L, strength 1.
  * DistantLight angle t, radiance L (intensity x color) -> Sun angle t,
    strength S = E (1 + sec(t/2)) / 2 with E = L pi sin^2(t/2).
  * Emissive quad (UsdPreviewSurface emissiveColor L) -> Emission L on the Principled BSDF,
    strength 1 (both two-sided).
  * Disney params -> Principled BSDF v1 directly (GGX, subsurface 0, Specular = Disney specular);
    clearcoatGloss g -> Clearcoat Roughness sqrt(0.1 - 0.099 g).
  * Sphere -> smooth UV sphere 256 x 128 (not an exact sphere: silhouette differs < 1e-4 r).
  * Catmull-Clark mesh -> Subdivision Surface modifier at the same level, limit surface on,
    UVs "keep boundaries" (OpenSubdiv face-varying default differs: cornersPlus1 vs Blender's).
  * Render: box filter 1 px, Standard view transform, no clamping, Filter Glossy 0, caustics on,
    adaptive sampling off, denoising off, max_bounces = principled --max-depth (both count the
    bounces after the camera hit, 0 = direct light only; principled matches since the acc branch),
    light_sampling_threshold left at Cycles' default 0.01 (unbiased: a stochastic cut of weak
    shadow rays), sampling pattern left at the 3.4 default (progressive multi-jitter).
  * Timing: cpuSeconds = process CPU of render(), all threads (sync + BVH + path tracing);
    wallSeconds also includes Cycles' background-mode waits (a 32x32 16-spp render: 1.08 s wall,
    0.10 s CPU), so compare CPU time, never wall time.
"""
import json
import math
import os
import sys
import time

import bpy
from mathutils import Matrix, Vector

argv = sys.argv[sys.argv.index("--") + 1:]
desc_path, outdir = argv[0], argv[1]
opts = dict(res=128, threads=2, spp="4,16,64", seed=0, max_bounces=8)
i = 2
while i < len(argv):
    k = argv[i].lstrip("-").replace("-", "_")
    opts[k] = argv[i + 1]
    i += 2
res, threads, seed, max_bounces = int(opts["res"]), int(opts["threads"]), int(opts["seed"]), int(opts["max_bounces"])
ladder = [int(s) for s in str(opts["spp"]).split(",")]
nseeds = [int(s) for s in str(opts.get("seeds", ",".join("1" for _ in ladder))).split(",")]
assert len(nseeds) == len(ladder), "--seeds needs one count per --spp entry"
sc = json.load(open(desc_path))
off = sc.get("offset", [0, 0, 0])
scene_dir = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(desc_path))))


def B(p):  # USD (Y up) -> Blender (Z up)
    x, y, z = p[0] + off[0], p[1] + off[1], p[2] + off[2]
    return Vector((x, -z, y))


def Bdir(d):
    return Vector((d[0], -d[2], d[1]))


bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.engine = "CYCLES"
cy = scene.cycles
cy.device = "CPU"
cy.use_adaptive_sampling = False
cy.use_denoising = False
try:
    cy.use_preview_denoising = False
except AttributeError:
    pass
cy.pixel_filter_type = "BOX"
cy.filter_width = 1.0
cy.sample_clamp_direct = 0.0
cy.sample_clamp_indirect = 0.0
cy.blur_glossy = 0.0
cy.caustics_reflective = True
cy.caustics_refractive = True
cy.max_bounces = max_bounces
cy.diffuse_bounces = max_bounces
cy.glossy_bounces = max_bounces
cy.transmission_bounces = max_bounces
cy.volume_bounces = 0
cy.transparent_max_bounces = max_bounces
cy.seed = seed
scene.render.threads_mode = "FIXED"
scene.render.threads = threads
scene.render.resolution_x = res
scene.render.resolution_y = res
scene.render.resolution_percentage = 100
scene.render.film_transparent = False
scene.view_settings.view_transform = "Standard"
scene.view_settings.look = "None"
scene.view_settings.exposure = 0
scene.view_settings.gamma = 1
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
scene.render.image_settings.color_mode = "RGBA"

# World: the sum of the dome lights (constant colours).
world = bpy.data.worlds.new("World")
scene.world = world
world.use_nodes = True
bg = world.node_tree.nodes["Background"]
dome = [0.0, 0.0, 0.0]
for l in sc["lights"]:
    if l["type"] == "dome":
        dome = [a + b for a, b in zip(dome, l["color"])]
bg.inputs["Color"].default_value = (*dome, 1.0)
bg.inputs["Strength"].default_value = 1.0

# Camera.
c = sc["camera"]
cam_data = bpy.data.cameras.new("Camera")
cam_data.lens = c["focalLength"]
cam_data.sensor_fit = "HORIZONTAL"
cam_data.sensor_width = c["horizontalAperture"]
cam_data.clip_start = 0.01
cam_data.clip_end = 1e7
cam = bpy.data.objects.new("Camera", cam_data)
scene.collection.objects.link(cam)
p, t, up = B(c["position"]), B(c["target"]), Bdir(c["up"])
z = (p - t).normalized()
x = up.cross(z).normalized()
y = z.cross(x)
cam.matrix_world = Matrix(((x[0], y[0], z[0], p[0]), (x[1], y[1], z[1], p[1]), (x[2], y[2], z[2], p[2]), (0, 0, 0, 1)))
scene.camera = cam

# Distant lights.
for l in sc["lights"]:
    if l["type"] != "distant":
        continue
    th = math.radians(l["angle"])
    L = l["intensity"]
    E = L * math.pi * math.sin(th / 2) ** 2
    S = E * (1 + 1 / math.cos(th / 2)) / 2
    sd = bpy.data.lights.new("Sun", "SUN")
    sd.angle = th
    sd.energy = S
    sd.color = l["color"]
    so = bpy.data.objects.new("Sun", sd)
    scene.collection.objects.link(so)
    # USD rotateXYZ (x first, then y, then z; row vectors) applied to the local frame; the
    # light emits along its local -Z in both.
    rx, ry, rz = (math.radians(a) for a in l["rotateXYZ"])
    Rusd = Matrix.Rotation(rz, 3, "Z") @ Matrix.Rotation(ry, 3, "Y") @ Matrix.Rotation(rx, 3, "X")
    conv = Matrix(((1, 0, 0), (0, 0, -1), (0, 1, 0)))  # USD -> Blender axes
    so.matrix_world = (conv @ Rusd).to_4x4()


def material(name, m):
    mt = bpy.data.materials.new(name)
    mt.use_nodes = True
    nt = mt.node_tree
    bsdf = nt.nodes["Principled BSDF"]
    bsdf.distribution = "GGX"
    bsdf.inputs["Base Color"].default_value = (*m["baseColor"], 1.0)
    bsdf.inputs["Metallic"].default_value = m["metallic"]
    bsdf.inputs["Roughness"].default_value = m["roughness"]
    bsdf.inputs["Specular"].default_value = m["specular"]
    bsdf.inputs["Specular Tint"].default_value = m["specularTint"]
    bsdf.inputs["Subsurface"].default_value = 0.0  # subsurface 1 differs by design: not peered
    bsdf.inputs["Sheen"].default_value = m["sheen"]
    bsdf.inputs["Sheen Tint"].default_value = m["sheenTint"]
    bsdf.inputs["Clearcoat"].default_value = m["clearcoat"]
    bsdf.inputs["Clearcoat Roughness"].default_value = math.sqrt(max(0.0, 0.1 - 0.099 * m["clearcoatGloss"]))
    bsdf.inputs["Emission"].default_value = (*m["emission"], 1.0)
    bsdf.inputs["Emission Strength"].default_value = 1.0
    if "texture" in m:
        tex = nt.nodes.new("ShaderNodeTexImage")
        tex.image = bpy.data.images.load(os.path.join(scene_dir, m["texture"]))
        tex.image.colorspace_settings.name = "sRGB"
        tex.interpolation = "Linear"
        uv = nt.nodes.new("ShaderNodeUVMap")
        uv.uv_map = "st"
        nt.links.new(uv.outputs["UV"], tex.inputs["Vector"])
        nt.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    return mt


mats = {name: material(name, m) for name, m in sc["materials"].items()}


def mesh_object(name, pts, faces, mat, smooth=False):
    me = bpy.data.meshes.new(name)
    me.from_pydata([B(p) for p in pts], [], faces)
    me.update()
    for poly in me.polygons:
        poly.use_smooth = smooth
    ob = bpy.data.objects.new(name, me)
    ob.data.materials.append(mats[mat])
    scene.collection.objects.link(ob)
    return ob


sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from scenegen import mesh_of  # noqa: E402  (same quads and boxes as the .usda)

subdiv_level = int(opts.get("refine_level", 3))
for o in sc["objects"]:
    if o["type"] == "sphere":
        bpy.ops.mesh.primitive_uv_sphere_add(segments=256, ring_count=128, radius=o["radius"], location=B(o["center"]))
        ob = bpy.context.active_object
        ob.name = o["name"]
        bpy.ops.object.shade_smooth()
        ob.data.materials.append(mats[o["material"]])
    elif o["type"] in ("quad", "box"):
        pts, faces = mesh_of(o)
        mesh_object(o["name"], pts, faces, o["material"])
    elif o["type"] == "subdiv":
        ob = mesh_object(o["name"], o["points"], o["faces"], o["material"], smooth=True)
        uvl = ob.data.uv_layers.new(name="st")
        k = 0
        for poly in ob.data.polygons:
            for j, li in enumerate(poly.loop_indices):
                uvl.data[li].uv = o["st"][o["stIndices"][poly.index][j]]
        mod = ob.modifiers.new("Subsurf", "SUBSURF")
        mod.levels = subdiv_level
        mod.render_levels = subdiv_level
        mod.uv_smooth = "PRESERVE_BOUNDARIES"

os.makedirs(outdir, exist_ok=True)
times = {}
# Cycles' sync and BVH build happen inside render() (principled's renderCpuSeconds excludes its
# own parse/sync/BVH); the render_stats handler is not called in background mode, so the
# fixed part is found by a straight-line fit of cpuSeconds against spp (bench/peer_equal_time.py).
for spp, n in zip(ladder, nseeds):
    for s in range(seed, seed + n):
        cy.samples = spp
        cy.seed = s
        key = str(spp) if s == seed else f"{spp}_seed{s}"
        path = os.path.join(outdir, f"cycles_{key}.exr")
        scene.render.filepath = path
        t0 = time.perf_counter()
        c0 = time.process_time()
        bpy.ops.render.render(write_still=True)
        c1, t1 = time.process_time(), time.perf_counter()
        times[key] = {"wallSeconds": t1 - t0, "cpuSeconds": c1 - c0, "spp": spp, "seed": s}
        print(f"cycles: {sc['name']} {spp} spp seed {s} {times[key]['wallSeconds']:.2f}s", flush=True)
json.dump(times, open(os.path.join(outdir, "cycles_times.json"), "w"), indent=1)
