#!/usr/bin/env python3
"""Unit tests of the principled Python module (plugins/python), plain unittest.

Run: PYTHONPATH=build/lib/python /usr/bin/python3 tests/python/test_module.py -v
"""
import math
import os
import tempfile
import unittest

import numpy as np

import principled

IDENTITY = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]


def translate(x, y, z):
    return [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, x, y, z, 1]


def plane_scene(two_meshes=True, texture=None):
    """Z-up: a 4x4 plane at z=0 (albedo 0.5), a small quad at z=1, a camera 5 above looking
    down -Z, a delta distant light straight down with E = pi (so the plane's radiance is 0.5)."""
    b = principled.SceneBuilder()
    b.set_stage_metadata("Z", 1.0)
    pts = [-2, -2, 0, 2, -2, 0, 2, 2, 0, -2, 2, 0]
    b.add_mesh("/World/Plane/Geom", pts, [4], [0, 1, 2, 3],
               normals=[0, 0, 1] * 4, st=[0, 0, 1, 0, 1, 1, 0, 1], normals_interpolation="vertex",
               st_interpolation="vertex")
    b.add_material("/World/Looks/Grey", diffuseColor=(0.5, 0.5, 0.5), roughness=1.0,
                   specular=0.0, metallic=0.0)
    if texture:
        b.set_material_texture("/World/Looks/Grey", "diffuseColor", texture, "rgb")
    b.bind_material("/World/Plane/Geom", "/World/Looks/Grey")
    if two_meshes:
        q = [-0.25, -0.25, 1, 0.25, -0.25, 1, 0.25, 0.25, 1, -0.25, 0.25, 1]
        b.add_mesh("/World/Box/Geom", q, [4], [0, 1, 2, 3])
        b.set_transform("/World/Box", translate(1.0, 0.0, 0.0))
        b.add_material("/World/Looks/Red", diffuseColor=(0.8, 0.1, 0.1), specular=0.0)
        b.bind_material("/World/Box/Geom", "/World/Looks/Red")
    b.add_prim("/World/Cam", "Camera")
    b.set_transform("/World/Cam", translate(0, 0, 5))
    b.set_attribute("/World/Cam", "float", "focalLength", 50)
    b.set_attribute("/World/Cam", "float", "horizontalAperture", 36)
    b.set_attribute("/World/Cam", "float", "verticalAperture", 36)
    b.add_prim("/World/Sun", "DistantLight")
    b.set_attribute("/World/Sun", "float", "inputs:intensity", math.pi)
    b.set_attribute("/World/Sun", "float", "inputs:angle", 0.0)
    return b


class ModuleTest(unittest.TestCase):
    def make(self, spp=4, res=(64, 64)):
        d = principled.Delegate()
        d.resolution = res
        d.set_setting("convergedSamplesPerPixel", spp)
        for a in ("color", "cameraDepth", "primId", "normal"):
            d.bind_aov(a)
        return d

    def test_registry_and_help(self):
        names = [r["display_name"] for r in principled.renderers()]
        self.assertIn("Embree", names)
        self.assertEqual(principled.abi_version(), principled.ABI_VERSION)
        self.assertIn("numpy", principled.Delegate.aov.__doc__)
        self.assertIn("SceneBuilder", principled.__doc__)

    def test_errors_become_exceptions(self):
        with principled.Delegate() as d:
            with self.assertRaises(principled.Error) as ctx:
                d.open_file("/nonexistent/scene.usda")
            self.assertIn("prdOpenStageFile", str(ctx.exception))
            self.assertIsInstance(ctx.exception, RuntimeError)
            with self.assertRaises(principled.Error) as ctx:
                d.bind_aov("noSuchAov")
            self.assertEqual(ctx.exception.status, "PRD_ERROR_NOT_FOUND")
            with self.assertRaises(principled.Error):
                d.set_setting("noSuchSetting", 1)
        with self.assertRaises(principled.Error):
            principled.Delegate("noSuchRenderer")
        b = principled.SceneBuilder()
        with self.assertRaises(principled.Error) as ctx:
            b.add_mesh("/World/M", [0, 0, 0] * 3, [3], [0, 1, 7])
        self.assertIn("out of range", str(ctx.exception))
        closed = principled.Delegate()
        closed.close()
        with self.assertRaises(principled.Error):
            closed.render_pass()

    def test_settings_and_aovs_listed(self):
        with principled.Delegate() as d:
            keys = [s["key"] for s in d.settings()]
            self.assertIn("convergedSamplesPerPixel", keys)
            d.set_setting("convergedSamplesPerPixel", 3)
            self.assertEqual(d.get_setting("convergedSamplesPerPixel"), "3")
            aovs = {a["name"]: a for a in d.aovs()}
            self.assertEqual(aovs["primId"]["format"], "int32")
            self.assertEqual(aovs["color"]["channels"], 4)

    def test_builder_scene_analytic_and_ids(self):
        with self.make(spp=8) as d:
            d.open_builder(plane_scene())
            passes = d.render()
            self.assertGreaterEqual(passes, 1)
            self.assertTrue(d.progress()[0])
            color = d.aov("color", copy=True)
            self.assertEqual(color.shape, (64, 64, 4))
            self.assertEqual(color.dtype, np.float32)
            self.assertTrue(np.isfinite(color).all())
            # Lit Lambert plane: albedo 0.5 * E/pi = 0.5 near the image centre (head-on).
            centre = color[28:36, 28:36, :3]
            self.assertAlmostEqual(float(centre.mean()), 0.5, delta=0.02)
            depth = d.aov("cameraDepth")
            self.assertAlmostEqual(float(depth[32, 32, 0]), 5.0, delta=0.02)
            ids = d.aov("primId")
            self.assertEqual(ids.dtype, np.int32)
            plane_id, box_id = int(ids[32, 32, 0]), int(ids[32, 54, 0])
            self.assertNotEqual(plane_id, box_id)
            self.assertEqual({plane_id, box_id}, {0, 1})
            normal = d.aov("normal")
            np.testing.assert_allclose(normal[32, 32], [0, 0, 1], atol=1e-5)

    def test_zero_copy_view(self):
        with self.make(spp=1) as d:
            d.open_builder(plane_scene(two_meshes=False))
            d.render_pass()
            v1 = d.aov("color")
            v2 = d.aov("color")
            self.assertFalse(v1.flags.writeable)
            self.assertFalse(v1.flags.owndata)
            self.assertEqual(v1.__array_interface__["data"][0], v2.__array_interface__["data"][0])
            c = d.aov("color", copy=True)
            self.assertTrue(c.flags.writeable)
            self.assertNotEqual(c.__array_interface__["data"][0], v1.__array_interface__["data"][0])

    def test_incremental_edits(self):
        with self.make(spp=2) as d:
            d.open_builder(plane_scene())
            d.render()
            before = d.stats()
            grey = d.aov("color", copy=True)
            d.set_attribute("/World/Looks/Grey/Surface", "inputs:diffuseColor", (1.0, 0.0, 0.0))
            d.render()
            after = d.stats()
            self.assertEqual(after["blasBuilds"], before["blasBuilds"], "material edit built a BVH")
            red = d.aov("color", copy=True)
            self.assertGreater(red[32, 32, 0], grey[32, 32, 0] * 1.5)
            self.assertLess(red[32, 32, 1], 0.01)
            # Transform edit: moves the instance, rebuilds no mesh.
            d.set_transform("/World/Box", translate(-1.0, 0.0, 0.0))
            d.render()
            moved = d.stats()
            self.assertEqual(moved["meshesRebuilt"], after["meshesRebuilt"])
            ids = d.aov("primId")
            self.assertEqual(ids[32, 54, 0], ids[5, 5, 0])  # the box left this pixel
            self.assertNotEqual(ids[32, 10, 0], ids[5, 5, 0])  # and arrived here
            # Light edit: darker, no BVH build.
            d.set_attribute("/World/Sun", "inputs:intensity", math.pi / 2)
            d.render()
            self.assertEqual(d.stats()["blasBuilds"], after["blasBuilds"])
            dark = d.aov("color", copy=True)
            self.assertAlmostEqual(float(dark[5, 5, 0]) / float(red[5, 5, 0]), 0.5, delta=0.05)

    def test_add_remove_and_rebind(self):
        with self.make(spp=2) as d:
            d.open_builder(plane_scene(two_meshes=False))
            d.render()
            plane_id = int(d.aov("primId")[32, 32, 0])
            # A red quad added at z=1 over the centre, with a material made through the module.
            d.add_prim("/World/Looks/Red", "Material")
            d.add_prim("/World/Looks/Red/S", "Shader")
            d.set_attribute("/World/Looks/Red/S", "info:id", "UsdPreviewSurface")
            d.set_attribute("/World/Looks/Red/S", "inputs:diffuseColor", (1.0, 0.0, 0.0))
            d.connect("/World/Looks/Red", "outputs:surface", "/World/Looks/Red/S.outputs:surface")
            d.add_prim("/World/Quad", "Mesh")
            d.set_attribute("/World/Quad", "points",
                            [-0.5, -0.5, 1, 0.5, -0.5, 1, 0.5, 0.5, 1, -0.5, 0.5, 1])
            d.set_attribute("/World/Quad", "faceVertexCounts", [4])
            d.set_attribute("/World/Quad", "faceVertexIndices", [0, 1, 2, 3])
            d.bind_material("/World/Quad", "/World/Looks/Red")
            d.render()
            quad_id = int(d.aov("primId")[32, 32, 0])
            self.assertNotEqual(quad_id, plane_id)
            red = d.aov("color", copy=True)
            self.assertGreater(red[32, 32, 0], 5 * red[32, 32, 1])
            # Rebinding the plane to red only re-syncs the plane.
            before = d.stats()["blasBuilds"]
            d.bind_material("/World/Plane/Geom", "/World/Looks/Red")
            d.render()
            self.assertEqual(d.stats()["blasBuilds"], before)
            self.assertGreater(d.aov("color")[5, 5, 0], 5 * d.aov("color")[5, 5, 1])
            # Removing the quad: its primId disappears.
            d.remove_prim("/World/Quad")
            d.render()
            self.assertNotIn(quad_id, set(np.unique(d.aov("primId"))))
            with self.assertRaises(principled.Error) as e:
                d.remove_prim("/World/Quad")
            self.assertIn("/World/Quad", str(e.exception))
            with self.assertRaises(principled.Error) as e:
                d.bind_material("/World/Plane/Geom", "/World/Sun")
            self.assertIn("expected a Material", str(e.exception))

    def test_texture_and_usda_roundtrip(self):
        with tempfile.TemporaryDirectory() as tmp:
            # A 2x1 texture: left half green, right half blue, as a binary PPM is not read by
            # every OIIO build; write a tiny uncompressed TGA-free path: use .exr if OIIO
            # writes it via numpy? Keep it simple: the module does not write images, so
            # author an ASCII PPM (OpenImageIO reads P3).
            tex = os.path.join(tmp, "tex.ppm")
            with open(tex, "w") as f:
                f.write("P3\n2 1\n255\n0 255 0  0 0 255\n")
            b = plane_scene(two_meshes=False, texture=tex)
            text = b.to_usda()
            self.assertIn("UsdUVTexture", text)
            self.assertIn('upAxis = "Z"', text)
            with self.make(spp=2) as d:
                d.open_string(text, "roundtrip")
                d.render()
                c = d.aov("color", copy=True)
                left, right = c[32, 12, :3], c[32, 52, :3]
                self.assertGreater(left[1], 5 * left[2])
                self.assertGreater(right[2], 5 * right[1])
                self.assertEqual(d.take_warnings(), [])


if __name__ == "__main__":
    unittest.main()
