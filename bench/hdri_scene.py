#!/usr/bin/python3
"""Writes the HDRI-lit test scene of docs/performance.md section 5f (MIS compensation):

    bench/hdri_scene.py [OUTDIR]      (default build/bench/hdri)

OUTDIR/sky.hdr: a 256x128 lat-long sky (0.35-0.8 bluish, brighter toward the zenith), a ground
of 0.1, a 3x3-texel sun of ~3000 at 35 degrees elevation and a 10x20-texel window of 8, written
as Radiance RGBE. OUTDIR/hdri_ball.usda: fig_specular0's ball (roughness 0.4, specular 0.5, so
no caustic fireflies) and ground, lit by that dome only. OUTDIR/room_{skyonly,sunpatch,overcast}.usda:
a closed 10x4x10 room with a 3x2 window, camera inside: the sun outside the window's view
(sky only), the sun shining in (a patch on the floor), and the sky without sun or window patch
(OUTDIR/overcast.hdr). These are the interiors, where BSDF sampling rarely finds the window, in
which MIS compensation can lose. room_*_portal.usda: the same with a UsdLux PortalLight filling
the window (delegate/portalSampling.h).
"""
import math
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def write_hdr(path, img):
    """Radiance RGBE, flat (uncompressed) scanlines, top row first."""
    h, w, _ = img.shape
    m = img.max(axis=-1)
    nz = m > 1e-32
    mant, exp = np.frexp(np.where(nz, m, 1.0))
    scale = np.where(nz, mant * 256.0 / np.where(nz, m, 1.0), 0.0)
    rgbe = np.zeros((h, w, 4), np.uint8)
    rgbe[..., :3] = np.clip(img * scale[..., None], 0, 255).astype(np.uint8)
    rgbe[..., 3] = np.where(nz, exp + 128, 0).astype(np.uint8)
    with open(path, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w))
        f.write(rgbe.tobytes())


def sky(w=256, h=128):
    img = np.zeros((h, w, 3))
    for y in range(h):
        elevation = 90.0 - math.degrees(math.pi * (y + 0.5) / h)
        if elevation > 0:
            t = elevation / 90.0
            img[y, :] = np.array([0.35 + 0.25 * t, 0.5 + 0.25 * t, 0.8 + 0.2 * t]) * (1.0 - 0.5 * t)
        else:
            img[y, :] = [0.12, 0.1, 0.08]
    sy, sx = int((90 - 35) / 180 * h), int(0.3 * w)
    img[sy - 1:sy + 2, sx - 1:sx + 2] = [3000, 2800, 2500]
    img[40:50, 150:170] = [8, 8, 8]
    return img


def quad(name, pts, color=(0.7, 0.7, 0.7)):
    p = ", ".join("(%g, %g, %g)" % t for t in pts)
    return ("    def Mesh \"%s\"\n    {\n        int[] faceVertexCounts = [4]\n        int[] faceVertexIndices = [0, 1, 2, 3]\n"
            "        point3f[] points = [%s]\n        color3f[] primvars:displayColor = [(%g, %g, %g)]\n"
            "        uniform bool doubleSided = 1\n    }\n") % (name, p, *color)


def room(hdr, rotate_y, portal=False):
    walls = [quad("Floor", [(-5, 0, -5), (-5, 0, 5), (5, 0, 5), (5, 0, -5)]),
             quad("Ceiling", [(-5, 4, -5), (5, 4, -5), (5, 4, 5), (-5, 4, 5)]),
             quad("Back", [(-5, 0, 5), (-5, 4, 5), (5, 4, 5), (5, 0, 5)]),
             quad("Left", [(-5, 0, -5), (-5, 4, -5), (-5, 4, 5), (-5, 0, 5)], (0.7, 0.3, 0.3)),
             quad("Right", [(5, 0, -5), (5, 0, 5), (5, 4, 5), (5, 4, -5)], (0.3, 0.7, 0.3)),
             # the front wall (z = -5) around a window x in [-1.5, 1.5], y in [1, 3]
             quad("W1", [(-5, 0, -5), (5, 0, -5), (5, 1, -5), (-5, 1, -5)]),
             quad("W2", [(-5, 3, -5), (5, 3, -5), (5, 4, -5), (-5, 4, -5)]),
             quad("W3", [(-5, 1, -5), (-1.5, 1, -5), (-1.5, 3, -5), (-5, 3, -5)]),
             quad("W4", [(1.5, 1, -5), (5, 1, -5), (5, 3, -5), (1.5, 3, -5)])]
    head = ("#usda 1.0\n(\n    upAxis = \"Y\"\n)\ndef Xform \"World\"\n{\n"
            "    def Camera \"Camera\"\n    {\n        float focalLength = 18\n        float horizontalAperture = 36\n"
            "        float verticalAperture = 36\n        double3 xformOp:translate = (0, 2, 4.5)\n"
            "        uniform token[] xformOpOrder = [\"xformOp:translate\"]\n    }\n"
            "    def DomeLight \"Sky\"\n    {\n        asset inputs:texture:file = @%s@\n"
            "        float3 xformOp:rotateXYZ = (0, %g, 0)\n        uniform token[] xformOpOrder = [\"xformOp:rotateXYZ\"]\n    }\n") % (hdr, rotate_y)
    # The window's portal: light passes along its local -Z, turned to +Z (into the room).
    window = ("    def PortalLight \"Window\"\n    {\n        float inputs:width = 3\n        float inputs:height = 2\n"
              "        double3 xformOp:translate = (0, 2, -5)\n        float xformOp:rotateY = 180\n"
              "        uniform token[] xformOpOrder = [\"xformOp:translate\", \"xformOp:rotateY\"]\n    }\n")
    return head + "".join(walls) + (window if portal else "") + "}\n"


def main():
    out = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "bench", "hdri"))
    os.makedirs(out, exist_ok=True)
    hdr = os.path.join(out, "sky.hdr")
    write_hdr(hdr, sky())
    s = open(os.path.join(ROOT, "scenes", "fig_specular0.usda")).read()
    # The sun prim becomes an inert scope; the constant dome gets the texture.
    s = s.replace('def DistantLight "Sun0"', 'def Scope "NoSun"')
    s = s.replace("color3f inputs:color = (0.33, 0.39, 0.51)", "asset inputs:texture:file = @%s@" % hdr)
    i = s.find('def Material "Ball"')
    ball = s[i:].replace("float inputs:roughness = 0.02", "float inputs:roughness = 0.4", 1)
    ball = ball.replace("float inputs:specular = 0\n", "float inputs:specular = 0.5\n", 1)
    scene = os.path.join(out, "hdri_ball.usda")
    open(scene, "w").write(s[:i] + ball)
    print(scene)
    overcast = sky()
    overcast[overcast > 5] = 0.0  # no sun, no window patch: the gradient sky and ground only
    for y in range(overcast.shape[0]):
        if overcast[y, 0, 0] == 0.0:
            overcast[y] = sky()[y, 0]
    write_hdr(os.path.join(out, "overcast.hdr"), overcast)
    for name, map_, rot in [("skyonly", hdr, 0), ("sunpatch", hdr, 180), ("overcast", os.path.join(out, "overcast.hdr"), 0)]:
        for portal in (False, True):
            path = os.path.join(out, "room_%s%s.usda" % (name, "_portal" if portal else ""))
            open(path, "w").write(room(map_, rot, portal))
            print(path)


if __name__ == "__main__":
    main()
