#!/usr/bin/env python3
"""One scene description, two renderers (issue 7).

Each scene is a small JSON description (scenes/desc/NAME.json): camera, lights, objects and
Disney 2012 material parameters, in USD conventions (Y up, metres, radiance units). From it we
emit
  * scenes/NAME.usda                 -- for principled (UsdPreviewSurface + Disney extras), and
  * a Blender Python script          -- the same scene for Cycles 3.4 (bench/cycles_render.py
                                        reads the JSON inside Blender; see the conversions there
                                        and in docs/performance.md).

    python3 bench/scenegen.py            # (re)writes scenes/desc/*.json, scenes/*.usda, texture
"""
import json
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = os.path.join(ROOT, "scenes")

# The seed article's reference material: Disney 2012 base colour (0.82, 0.67, 0.16) sRGB.
GOLD = [0.646, 0.415, 0.0177]
REFERENCE = dict(baseColor=GOLD, metallic=0.0, roughness=0.02, specular=0.5)


def mat(**kw):
    m = dict(baseColor=[0.18, 0.18, 0.18], metallic=0.0, roughness=0.5, specular=0.5,
             subsurface=0.0, sheen=0.0, sheenTint=0.5, clearcoat=0.0, clearcoatGloss=1.0,
             specularTint=0.0, emission=[0.0, 0.0, 0.0])
    m.update(kw)
    return m


# Lights of the default scene: a 0.53 degree sun (intensity 50000: irradiance about 3.4) and a
# blue sky dome of radiance (0.55, 0.65, 0.85) x 0.6.
SUN = dict(type="distant", angle=0.53, intensity=50000.0, color=[1, 1, 1], rotateXYZ=[-50, 35, 0])
SKY = dict(type="dome", color=[0.55 * 0.6, 0.65 * 0.6, 0.85 * 0.6])
GROUND = dict(type="quad", name="Ground", corners=[[-12, 0, -12], [-12, 0, 12], [12, 0, 12], [12, 0, -12]],
              material="Ground")
GROUND_MAT = mat(baseColor=[0.35, 0.35, 0.35], roughness=0.8)


def camera(pos, target, focal=24.0, aperture=20.955):
    return dict(position=pos, target=target, up=[0, 1, 0], focalLength=focal, horizontalAperture=aperture)


def figure(name, params):
    """One sphere of the seed figure set on the ground, the default scene's lights."""
    return dict(name=name, doc=f"Seed figure set: {name} ({params}).",
                camera=camera([0, 0.9, 3.2], [0, 0.5, 0], focal=35.0),
                lights=[SUN, SKY],
                objects=[GROUND, dict(type="sphere", name="Ball", center=[0, 0.5, 0], radius=0.5, material="Ball")],
                materials={"Ground": GROUND_MAT, "Ball": mat(**params)},
                peer=params.get("subsurface", 0) == 0)


def row(name, doc, mats, spacing=1.15, radius=0.5, lights=None, ground=True, cam=None):
    """Spheres on a grid in the x-y plane (left to right, bottom to top), floating above the
    ground, framed by a square camera looking down -z."""
    n = len(mats)
    cols = math.ceil(math.sqrt(n))
    rows = math.ceil(n / cols)
    objs = [GROUND] if ground else []
    materials = {"Ground": GROUND_MAT} if ground else {}
    for i, m in enumerate(mats):
        x = (i % cols - (cols - 1) / 2) * spacing
        y = radius + 0.1 + (rows - 1 - i // cols) * spacing
        objs.append(dict(type="sphere", name=f"S{i}", center=[round(x, 4), round(y, 4), 0], radius=radius,
                         material=f"M{i}"))
        materials[f"M{i}"] = m
    extent = max(cols, rows) * spacing
    focal = 35.0
    dist = (extent / 2 + 0.3) * focal / (20.955 / 2)
    cy = radius + 0.1 + (rows - 1) * spacing / 2
    return dict(name=name, doc=doc, camera=cam or camera([0, cy + 0.3, dist], [0, cy, 0], focal=focal),
                lights=lights if lights is not None else [SUN, SKY], objects=objs, materials=materials, peer=True)


def lerp(a, b, t):
    if isinstance(a, list):
        return [round(x + (y - x) * t, 5) for x, y in zip(a, b)]
    return round(a + (b - a) * t, 5)


def cornell():
    """Cornell box 2 x 2 x 2 (walls: white, red left, green right), an emissive ceiling quad
    (two-sided emission radiance 12, 0.5 x 0.5), a rough-metal sphere and a glossy box."""
    W, R, G = [0.73, 0.73, 0.73], [0.65, 0.05, 0.05], [0.12, 0.45, 0.15]
    q = lambda name, c, m: dict(type="quad", name=name, corners=c, material=m)
    objs = [
        q("Floor", [[-1, 0, -1], [-1, 0, 1], [1, 0, 1], [1, 0, -1]], "White"),
        q("Ceiling", [[-1, 2, -1], [1, 2, -1], [1, 2, 1], [-1, 2, 1]], "White"),
        q("Back", [[-1, 0, -1], [1, 0, -1], [1, 2, -1], [-1, 2, -1]], "White"),
        q("Left", [[-1, 0, -1], [-1, 2, -1], [-1, 2, 1], [-1, 0, 1]], "Red"),
        q("Right", [[1, 0, -1], [1, 0, 1], [1, 2, 1], [1, 2, -1]], "Green"),
        q("Light", [[-0.25, 1.999, -0.25], [0.25, 1.999, -0.25], [0.25, 1.999, 0.25], [-0.25, 1.999, 0.25]], "Light"),
        dict(type="sphere", name="Ball", center=[-0.4, 0.35, 0.25], radius=0.35, material="RoughMetal"),
        dict(type="box", name="Box", center=[0.4, 0.45, -0.3], size=[0.55, 0.9, 0.55], rotateY=20, material="Glossy"),
    ]
    mats = {"White": mat(baseColor=W, roughness=1.0, specular=0.0),
            "Red": mat(baseColor=R, roughness=1.0, specular=0.0),
            "Green": mat(baseColor=G, roughness=1.0, specular=0.0),
            "Light": mat(baseColor=[0, 0, 0], roughness=1.0, specular=0.0, emission=[12.0, 12.0, 12.0]),
            "RoughMetal": mat(baseColor=[0.9, 0.9, 0.9], metallic=1.0, roughness=0.3),
            "Glossy": mat(baseColor=[0.8, 0.8, 0.8], roughness=0.15)}
    return dict(name="cornell", doc="Cornell box lit by an emissive quad (UsdPreviewSurface emissiveColor).",
                camera=camera([0, 1, 3.9], [0, 1, 0], focal=35.0, aperture=24.0), lights=[], objects=objs,
                materials=mats, peer=True)


def furnace():
    mats = [mat(baseColor=[1, 1, 1], roughness=1.0, specular=0.0),  # Lambert-like white
            mat(baseColor=[1, 1, 1], roughness=0.5),                  # white plastic
            mat(baseColor=[1, 1, 1], metallic=1.0, roughness=0.5),    # white rough metal
            mat(baseColor=[1, 1, 1], metallic=1.0, roughness=1.0),    # white very rough metal
            mat(baseColor=[1, 1, 1], roughness=0.3, sheen=1.0, clearcoat=1.0, clearcoatGloss=0.5)]
    s = row("furnace", "White furnace: a white dome of radiance 1, no ground; white spheres (diffuse, "
            "plastic, rough metal r=0.5 and 1, sheen+clearcoat) should vanish into the background "
            "where energy is conserved.", mats, lights=[dict(type="dome", color=[1, 1, 1])], ground=False)
    return s


def textured_subdiv():
    """A Catmull-Clark torus cage (24 x 12 quads) with a checker texture on st."""
    R, r, nu, nv = 0.7, 0.3, 24, 12
    pts, st_vals, faces, st_idx = [], [], [], []
    for i in range(nu):
        for j in range(nv):
            u, v = 2 * math.pi * i / nu, 2 * math.pi * j / nv
            pts.append([round((R + r * math.cos(v)) * math.cos(u), 6), round(r * math.sin(v) + 0.3 + r, 6),
                        round((R + r * math.cos(v)) * math.sin(u), 6)])
    for i in range(nu + 1):
        for j in range(nv + 1):
            st_vals.append([round(i / nu, 6), round(j / nv, 6)])
    for i in range(nu):
        for j in range(nv):
            a, b = i * nv + j, ((i + 1) % nu) * nv + j
            c, d = ((i + 1) % nu) * nv + (j + 1) % nv, i * nv + (j + 1) % nv
            faces.append([a, d, c, b])
            sa, sb = i * (nv + 1) + j, (i + 1) * (nv + 1) + j
            st_idx.append([sa, sa + 1, sb + 1, sb])
    obj = dict(type="subdiv", name="Torus", points=pts, faces=faces, st=st_vals, stIndices=st_idx,
               material="Checker", center=[0, 0, 0])
    m = mat(baseColor=[0.8, 0.8, 0.8], roughness=0.35, texture="textures/checker.png")
    return dict(name="textured_subdiv", doc="Textured subdivision model: Catmull-Clark torus (288-quad cage), "
                "checker texture on st. Refine level: adaptive (-1) by default; --refine-level 6 gives 2.36 M triangles.",
                camera=camera([0, 1.6, 2.6], [0, 0.45, 0], focal=30.0), lights=[SUN, SKY],
                objects=[GROUND, obj], materials={"Ground": GROUND_MAT, "Checker": m}, peer=True)


def subdiv_extreme():
    """Catmull-Clark double cone of triangles: two vertices of valence 24 (apex and bottom
    centre) and an infinitely sharp crease (sharpness 10) around the 24-vertex rim."""
    n = 24
    pts = [[0.0, 1.3, 0.0], [0.0, 0.35, 0.0]]
    for i in range(n):
        a = 2 * math.pi * i / n
        pts.append([round(0.6 * math.cos(a), 6), 0.7, round(0.6 * math.sin(a), 6)])
    faces = []
    for i in range(n):
        r0, r1 = 2 + i, 2 + (i + 1) % n
        faces.append([0, r1, r0])
        faces.append([1, r0, r1])
    crease = [2 + i for i in range(n)] + [2]
    obj = dict(type="subdiv", name="Cone", points=pts, faces=faces, material="Red",
               creases=dict(indices=crease, lengths=[len(crease)], sharpnesses=[10.0]))
    return dict(name="subdiv_extreme", doc="Subdivision at extreme valence and crease: a Catmull-Clark double cone "
                "of 48 triangles, two valence-24 vertices and a sharpness-10 crease around the rim.",
                camera=camera([0, 1.5, 2.6], [0, 0.75, 0], focal=35.0), lights=[SUN, SKY],
                objects=[GROUND, obj], materials={"Ground": GROUND_MAT, "Red": mat(baseColor=[0.6, 0.1, 0.08], roughness=0.3)},
                peer=False)


def all_scenes():
    s = [figure("fig_reference", REFERENCE),
         figure("fig_metallic1", dict(REFERENCE, metallic=1.0)),
         figure("fig_roughness02", dict(REFERENCE, roughness=0.2)),
         figure("fig_specular0", dict(REFERENCE, specular=0.0)),
         figure("fig_subsurface1", dict(REFERENCE, subsurface=1.0)),
         figure("fig_sheen1", dict(REFERENCE, sheen=1.0)),
         figure("fig_clearcoat_rough_metal", dict(REFERENCE, metallic=1.0, roughness=0.7, clearcoat=1.0,
                                                  clearcoatGloss=0.05))]
    rubber = mat(baseColor=[0.05, 0.05, 0.05], metallic=0.0, roughness=0.9, specular=0.5)
    metal = mat(baseColor=GOLD, metallic=1.0, roughness=0.2, specular=0.5)
    s.append(row("rubber_to_metal", "Rubber-to-metal interpolation: every parameter lerped linearly from black "
                 "rubber (metallic 0, roughness 0.9) to gold metal (metallic 1, roughness 0.2) in 7 steps (left to right, top row first).",
                 [{k: lerp(rubber[k], metal[k], t / 6) for k in rubber} for t in range(7)]))
    s.append(row("roughness_sweep", "Roughness sweep 0..1 in 11 steps (left to right, top row first) on a white-ish metal "
                 "(metallic 1, base 0.9); exercises the delta-mirror threshold at r = 0.",
                 [mat(baseColor=[0.9, 0.9, 0.9], metallic=1.0, roughness=i / 10) for i in range(11)],
                 spacing=1.05))
    s.append(row("low_roughness", "Stability as roughness -> 0: metal spheres (base 0.9) at roughness 0, 0.005, "
                 "0.01, 0.02, 0.03, 0.05, 0.1, 0.2, 0.3 (left to right, top row first), lit by the sky dome and the "
                 "ground only (no sun, so no sub-pixel highlight dominates the error).",
                 [mat(baseColor=[0.9, 0.9, 0.9], metallic=1.0, roughness=r) for r in
                  (0.0, 0.005, 0.01, 0.02, 0.03, 0.05, 0.1, 0.2, 0.3)], lights=[SKY]))
    s.append(cornell())
    s.append(furnace())
    s.append(textured_subdiv())
    s.append(subdiv_extreme())
    s.append(dict(figure("far_origin", REFERENCE), name="far_origin",
                  doc="fig_reference translated by 1e5 units (float precision at large coordinates).",
                  offset=[1e5, 0, 1e5]))
    return s


# ---------------------------------------------------------------------------------------------
# USDA emission.
def fmt(v):
    return "(" + ", ".join(f"{x:.6g}" for x in v) + ")"


def look_at_matrix(pos, target, up):
    """USD row-vector matrix: rows are the camera's x, y, z axes then the translation
    (the camera looks down its -z)."""
    import numpy as np
    p, t, u = (np.array(x, float) for x in (pos, target, up))
    z = p - t
    z /= np.linalg.norm(z)
    x = np.cross(u, z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    return [list(x) + [0], list(y) + [0], list(z) + [0], list(p) + [1]]


def matrix_str(m):
    return "( " + ", ".join("(" + ", ".join(f"{v:.9g}" for v in r) + ")" for r in m) + " )"


def add(v, o):
    return [a + b for a, b in zip(v, o)]


def to_usda(sc):
    off = sc.get("offset", [0, 0, 0])
    out = ['#usda 1.0', '(', f'    doc = """{sc["doc"]} Generated by bench/scenegen.py from scenes/desc/{sc["name"]}.json."""',
           '    defaultPrim = "World"', '    upAxis = "Y"', '    metersPerUnit = 1', ')', '', 'def Xform "World"', '{']
    c = sc["camera"]
    out += ['    def Camera "Camera"', '    {', f'        float focalLength = {c["focalLength"]}',
            f'        float horizontalAperture = {c["horizontalAperture"]}',
            f'        float verticalAperture = {c["horizontalAperture"]}',
            '        float2 clippingRange = (0.01, 1000000)',
            f'        matrix4d xformOp:transform = {matrix_str(look_at_matrix(add(c["position"], off), add(c["target"], off), c["up"]))}',
            '        uniform token[] xformOpOrder = ["xformOp:transform"]', '    }']
    for i, l in enumerate(sc["lights"]):
        if l["type"] == "dome":
            out += [f'    def DomeLight "Dome{i}"', '    {', f'        color3f inputs:color = {fmt(l["color"])}',
                    '        float inputs:intensity = 1', '    }']
        elif l["type"] == "distant":
            out += [f'    def DistantLight "Sun{i}"', '    {', f'        float inputs:angle = {l["angle"]}',
                    f'        float inputs:intensity = {l["intensity"]}', f'        color3f inputs:color = {fmt(l["color"])}',
                    f'        float3 xformOp:rotateXYZ = {fmt(l["rotateXYZ"])}',
                    '        uniform token[] xformOpOrder = ["xformOp:rotateXYZ"]', '    }']
    for o in sc["objects"]:
        bind = ['        prepend apiSchemas = ["MaterialBindingAPI"]']
        rel = f'        rel material:binding = </World/Looks/{o["material"]}>'
        if o["type"] == "sphere":
            out += [f'    def Sphere "{o["name"]}" (', *bind, '    )', '    {', f'        double radius = {o["radius"]}',
                    f'        double3 xformOp:translate = {fmt(add(o["center"], off))}',
                    '        uniform token[] xformOpOrder = ["xformOp:translate"]', rel, '    }']
        elif o["type"] in ("quad", "box"):
            pts, faces = mesh_of(o)
            out += [f'    def Mesh "{o["name"]}" (', *bind, '    )', '    {', '        uniform token subdivisionScheme = "none"',
                    f'        int[] faceVertexCounts = [{", ".join(str(len(f)) for f in faces)}]',
                    f'        int[] faceVertexIndices = [{", ".join(str(i) for f in faces for i in f)}]',
                    f'        point3f[] points = [{", ".join(fmt(add(p, off)) for p in pts)}]', rel, '    }']
        elif o["type"] == "subdiv":
            out += [f'    def Mesh "{o["name"]}" (', *bind, '    )', '    {', '        uniform token subdivisionScheme = "catmullClark"',
                    f'        int[] faceVertexCounts = [{", ".join(str(len(f)) for f in o["faces"])}]',
                    f'        int[] faceVertexIndices = [{", ".join(str(i) for f in o["faces"] for i in f)}]',
                    f'        point3f[] points = [{", ".join(fmt(add(p, off)) for p in o["points"])}]']
            if "st" in o:
                out += [f'        texCoord2f[] primvars:st = [{", ".join(fmt(p) for p in o["st"])}] (',
                        '            interpolation = "faceVarying"', '        )',
                        f'        int[] primvars:st:indices = [{", ".join(str(i) for f in o["stIndices"] for i in f)}]']
            if "creases" in o:
                c_ = o["creases"]
                out += [f'        int[] creaseIndices = [{", ".join(str(i) for i in c_["indices"])}]',
                        f'        int[] creaseLengths = [{", ".join(str(i) for i in c_["lengths"])}]',
                        f'        float[] creaseSharpnesses = [{", ".join(str(i) for i in c_["sharpnesses"])}]']
            out += [rel, '    }']
    out += ['    def Scope "Looks"', '    {']
    for name, m in sc["materials"].items():
        path = f'/World/Looks/{name}'
        out += [f'        def Material "{name}"', '        {',
                f'            token outputs:surface.connect = <{path}/Surface.outputs:surface>',
                '            def Shader "Surface"', '            {', '                uniform token info:id = "UsdPreviewSurface"']
        if "texture" in m:
            out.append(f'                color3f inputs:diffuseColor.connect = <{path}/Tex.outputs:rgb>')
        else:
            out.append(f'                color3f inputs:diffuseColor = {fmt(m["baseColor"])}')
        for k in ("metallic", "roughness", "specular", "subsurface", "sheen", "sheenTint", "clearcoat",
                  "clearcoatGloss", "specularTint"):
            out.append(f'                float inputs:{k} = {m[k]:.6g}')
        if any(m["emission"]):
            out.append(f'                color3f inputs:emissiveColor = {fmt(m["emission"])}')
        out += ['                token outputs:surface', '            }']
        if "texture" in m:
            out += ['            def Shader "StReader"', '            {', '                uniform token info:id = "UsdPrimvarReader_float2"',
                    '                string inputs:varname = "st"', '                float2 outputs:result', '            }',
                    '            def Shader "Tex"', '            {', '                uniform token info:id = "UsdUVTexture"',
                    f'                asset inputs:file = @{m["texture"]}@',
                    '                token inputs:sourceColorSpace = "sRGB"',
                    '                token inputs:wrapS = "repeat"', '                token inputs:wrapT = "repeat"',
                    f'                float2 inputs:st.connect = <{path}/StReader.outputs:result>',
                    '                float3 outputs:rgb', '            }']
        out.append('        }')
    out += ['    }', '}', '']
    return "\n".join(out)


def mesh_of(o):
    """Points and faces (counter-clockwise from outside) of a quad or a box."""
    if o["type"] == "quad":
        return o["corners"], [[0, 1, 2, 3]]
    cx, cy, cz = o["center"]
    sx, sy, sz = (s / 2 for s in o["size"])
    a = math.radians(o.get("rotateY", 0))
    pts = []
    for (x, y, z) in [(-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1), (-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1)]:
        px, py, pz = x * sx, y * sy, z * sz
        pts.append([round(cx + px * math.cos(a) + pz * math.sin(a), 6), round(cy + py, 6),
                    round(cz - px * math.sin(a) + pz * math.cos(a), 6)])
    faces = [[0, 1, 2, 3], [5, 4, 7, 6], [4, 0, 3, 7], [1, 5, 6, 2], [3, 2, 6, 7], [4, 5, 1, 0]]
    return pts, faces


def write_texture():
    path = os.path.join(SCENES, "textures", "checker.png")
    if not os.path.exists(path):
        subprocess.run(["oiiotool", "--pattern", "checker:width=32:height=32:color1=0.9,0.75,0.2:color2=0.1,0.2,0.5",
                        "256x256", "3", "-d", "uint8", "-o", path], check=True)
    return path


def main():
    os.makedirs(os.path.join(SCENES, "desc"), exist_ok=True)
    write_texture()
    for sc in all_scenes():
        with open(os.path.join(SCENES, "desc", sc["name"] + ".json"), "w") as f:
            json.dump(sc, f, indent=1)
        with open(os.path.join(SCENES, sc["name"] + ".usda"), "w") as f:
            f.write(to_usda(sc))
    print("wrote", len(all_scenes()), "scenes to", SCENES, file=sys.stderr)


if __name__ == "__main__":
    main()
