#!/usr/bin/python3
"""Writes the many-lamp scene of docs/performance.md section 5f (spatial light pick):

    bench/lamps_scene.py [OUTDIR] [--side N --pitch P] [--height H --cone DEG]
        (defaults build/bench/lamps, 4, 5, 0.6, none)

OUTDIR/lamps.usda (lamps_N.usda for another side): a grey floor under N x N sphere lamps
(radius 0.1, intensities 200/400/600) 0.6 above it on a grid of pitch P centred on the origin,
seen from above by an orthographic camera (20 x 20 units). With more than 64 lamps the spatial
pick goes through the light tree (delegate/lightTree.h). With --cone, the lamps are spot lights
aimed straight down (UsdLux ShapingAPI cone of that half angle) at height H, written to
spots_N.usda.
"""
import argparse
import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

HEAD = '''#usda 1.0
(
    upAxis = "Y"
)
def Mesh "Plane" (prepend apiSchemas = ["MaterialBindingAPI"])
{
    uniform token subdivisionScheme = "none"
    int[] faceVertexCounts = [4]
    int[] faceVertexIndices = [0, 1, 2, 3]
    point3f[] points = [(-50, 0, -50), (-50, 0, 50), (50, 0, 50), (50, 0, -50)]
    rel material:binding = </Mat>
}
def Material "Mat"
{
    token outputs:surface.connect = </Mat/S.outputs:surface>
    def Shader "S"
    {
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor = (0.5, 0.5, 0.5)
        float inputs:roughness = 0.6
        token outputs:surface
    }
}
def Camera "Cam"
{
    token projection = "orthographic"
    float horizontalAperture = 200
    float verticalAperture = 200
    float2 clippingRange = (0.001, 1000)
    double3 xformOp:translate = (0, 20, 0)
    float xformOp:rotateX = -90
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
}
'''


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("outdir", nargs="?", default=os.path.join(ROOT, "build", "bench", "lamps"))
    ap.add_argument("--side", type=int, default=4, help="lamps per side of the grid")
    ap.add_argument("--pitch", type=float, default=5.0, help="grid spacing in scene units")
    ap.add_argument("--height", type=float, default=0.6, help="lamp height above the floor")
    ap.add_argument("--cone", type=float, default=None, help="spot cone half angle in degrees")
    a = ap.parse_args()
    out = os.path.abspath(a.outdir)
    os.makedirs(out, exist_ok=True)
    lamps = []
    first = -0.5 * a.pitch * (a.side - 1)
    for k in range(a.side * a.side):
        x, z = first + a.pitch * (k // a.side), first + a.pitch * (k % a.side)
        if a.cone is None:
            lamps.append('def SphereLight "L%d"\n{\n    float inputs:radius = 0.1\n    float inputs:intensity = %g\n'
                         '    double3 xformOp:translate = (%g, %g, %g)\n    uniform token[] xformOpOrder = ["xformOp:translate"]\n}\n'
                         % (k, 200 * (1 + k % 3), x, a.height, z))
        else:
            lamps.append('def SphereLight "L%d" (prepend apiSchemas = ["ShapingAPI"])\n{\n    float inputs:radius = 0.1\n'
                         '    float inputs:intensity = %g\n    float inputs:shaping:cone:angle = %g\n'
                         '    double3 xformOp:translate = (%g, %g, %g)\n    float xformOp:rotateX = -90\n'
                         '    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]\n}\n'
                         % (k, 200 * (1 + k % 3), a.cone, x, a.height, z))
    if a.cone is not None:
        path = os.path.join(out, "spots_%d.usda" % a.side)
    else:
        path = os.path.join(out, "lamps.usda" if a.side == 4 else "lamps_%d.usda" % a.side)
    open(path, "w").write(HEAD + "".join(lamps))
    print(path)


if __name__ == "__main__":
    main()
