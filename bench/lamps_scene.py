#!/usr/bin/python3
"""Writes the many-lamp scene of docs/performance.md section 5f (spatial light pick):

    bench/lamps_scene.py [OUTDIR]      (default build/bench/lamps)

OUTDIR/lamps.usda: a grey floor under 16 sphere lamps (radius 0.1, intensities 200/400/600)
0.6 above it on a 4 x 4 grid of pitch 5, seen from above by an orthographic camera (20 x 20 units).
"""
import os
import sys

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
    out = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "bench", "lamps"))
    os.makedirs(out, exist_ok=True)
    lamps = []
    for k in range(16):
        x, z = -7.5 + 5 * (k // 4), -7.5 + 5 * (k % 4)
        lamps.append('def SphereLight "L%d"\n{\n    float inputs:radius = 0.1\n    float inputs:intensity = %g\n'
                     '    double3 xformOp:translate = (%g, 0.6, %g)\n    uniform token[] xformOpOrder = ["xformOp:translate"]\n}\n'
                     % (k, 200 * (1 + k % 3), x, z))
    path = os.path.join(out, "lamps.usda")
    open(path, "w").write(HEAD + "".join(lamps))
    print(path)


if __name__ == "__main__":
    main()
