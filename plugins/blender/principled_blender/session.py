# SPDX-License-Identifier: Apache-2.0
"""A principled delegate driven from a Blender depsgraph: full sync, incremental updates (the
viewport's view_update), passes and Blender-side pass conversion. No bpy.types here, so the
update logic is testable headless."""
import math
import os
import tempfile

import numpy as np

from . import export

# Blender pass name -> (principled AOV, channels, chan_id, type). Combined and Depth/IndexOB
# are derived specially; the rest are copied.
PASSES = [
    ("Depth", "position", 1, "Z", "VALUE"),
    ("Normal", "normal", 3, "XYZ", "VECTOR"),
    ("IndexOB", "primId", 1, "X", "VALUE"),
    ("Diffuse", "diffuse", 3, "RGB", "COLOR"),
    ("Glossy", "specular", 3, "RGB", "COLOR"),
    ("Emit", "emission", 3, "RGB", "COLOR"),
    ("Sheen", "sheen", 3, "RGB", "COLOR"),
    ("Clearcoat", "clearcoat", 3, "RGB", "COLOR"),
    ("Transmission", "transmission", 3, "RGB", "COLOR"),
    ("Albedo", "albedo", 3, "RGB", "COLOR"),
    ("Position", "position", 3, "XYZ", "VECTOR"),
    ("InstanceId", "instanceId", 1, "X", "VALUE"),
    ("MaterialId", "materialId", 1, "X", "VALUE"),
    ("Samples", "sampleCount", 1, "X", "VALUE"),
    ("Variance", "variance", 1, "X", "VALUE"),
]

#: Tests set a dict here: the engine stores every pass it wrote, read back from Blender's
#: render result buffers (name -> flat float32 array, rows bottom to top).
CAPTURE = None

#: Cycles' depth for pixels that hit nothing.
BACKGROUND_DEPTH = 1.0e10


def import_principled():
    try:
        import principled  # noqa: F401
    except ImportError:
        extra = os.environ.get("PRINCIPLED_PYTHON_PATH")
        if not extra:
            raise
        import sys

        sys.path.insert(0, extra)
        import principled  # noqa: F811
    return principled


class Session:
    """Owns one principled.Delegate and the SceneExport it was populated from."""

    def __init__(self, settings=None, aovs=("color",)):
        self.p = import_principled()
        self.delegate = self.p.Delegate()
        self.texture_dir = tempfile.mkdtemp(prefix="principled-blender-")
        self.export = None
        self.settings = dict(settings or {})
        for k, v in self.settings.items():
            self.delegate.set_setting(k, v)
        self.aovs = list(dict.fromkeys(aovs))
        for a in self.aovs:
            self.delegate.bind_aov(a)
        self.width = self.height = 0
        self.rebuilds = 0
        self.last_update = {}
        self.camera_matrix = None
        self.film_transparent = False

    def close(self, keep_textures=False):
        if self.delegate is not None:
            self.delegate.close()
        self.delegate = None
        if not keep_textures and self.texture_dir:
            import shutil

            shutil.rmtree(self.texture_dir, ignore_errors=True)
            self.texture_dir = None

    # ---- sync --------------------------------------------------------------------------
    def resize(self, width, height):
        if (width, height) != (self.width, self.height):
            self.delegate.resolution = (width, height)
            self.width, self.height = width, height

    def full_sync(self, depsgraph, width, height, view_camera=None):
        """Translates the whole depsgraph and opens it (a full rebuild)."""
        self.resize(width, height)
        self.film_transparent = bool(depsgraph.scene.render.film_transparent)
        ex = export.SceneExport(self.p, depsgraph, self.texture_dir, width, height,
                                view_camera=view_camera)
        builder = ex.build()
        self.delegate.open_builder(builder)
        if ex.camera_path:
            self.delegate.camera = ex.camera_path
        self.export = ex
        self.rebuilds += 1
        self.builder = builder  # builder.to_usda(): the stage as text (debugging, tests)
        if view_camera is None and depsgraph.scene.camera is not None:
            self.camera_matrix = depsgraph.scene.camera.matrix_world.copy()
        return ex.warnings

    def set_view_camera(self, matrix, params):
        """Viewport camera edits: transform and lens without a rebuild."""
        from mathutils import Matrix

        loc, rot, _ = matrix.decompose()
        m = Matrix.Translation(loc) @ rot.to_matrix().to_4x4()
        self.delegate.set_transform("/World/ViewCamera", export.usd_matrix(m))
        for k, v in params.items():
            if k in ("focalLength", "horizontalAperture", "verticalAperture",
                     "horizontalApertureOffset", "verticalApertureOffset"):
                self.delegate.set_attribute("/World/ViewCamera", k, v)
        self.camera_matrix = matrix.copy()

    def apply_updates(self, depsgraph, updates):
        """Applies depsgraph updates through the delegate's edit calls where it can.

        Material: every surface input is re-set (material tables only, no BVH build);
        a change in which inputs are texture-linked rebuilds. Light: intensity/color/angle/
        radius/cone or the area emitter's radiance. Object transform only: set_transform on each of its instance
        Xforms (no mesh rebuild). World color: the dome light's color (a world texture: rebuild). Anything else that
        changes geometry or the set of objects: a full rebuild (the ABI cannot change
        topology or add prims yet). Returns a dict of what was done."""
        ex = self.export
        done = {"materials": 0, "lights": 0, "transforms": 0, "world": 0, "rebuild": False}
        if ex is None:
            return done | {"rebuild": True}
        rebuild = False
        import bpy

        for u in updates:
            idd = u.id
            if isinstance(idd, bpy.types.Material):
                entry = ex.materials.get(idd.name)
                if entry is None:
                    continue
                path, sig = entry
                inputs, links, _ = export.material_params(idd.original, ex.textures)
                if export.link_signature(links, export.uv_mapping(idd.original, [])) != sig:
                    rebuild = True
                    continue
                for k, v in inputs.items():
                    self.delegate.set_attribute(path + "/Surface", "inputs:" + k, v)
                done["materials"] += 1
            elif isinstance(idd, bpy.types.Light):
                for obj in depsgraph.objects:
                    if obj.type == "LIGHT" and obj.data.original == idd.original:
                        if not self._update_light(obj):
                            rebuild = True
                        else:
                            done["lights"] += 1
            elif isinstance(idd, bpy.types.World):
                wp, _ = export.world_params(idd)
                if wp["texture"] or ex.world_texture:
                    rebuild = True  # a texture (or its removal): the dome is re-exported
                    continue
                self.delegate.set_attribute("/World/Environment", "inputs:color", wp["color"])
                done["world"] += 1
            elif isinstance(idd, bpy.types.Object):
                if idd.type == "LIGHT" and u.is_updated_geometry and not u.is_updated_transform:
                    # Light data edits tag the object's "geometry": parameters only.
                    if not self._update_light(idd):
                        rebuild = True
                    continue
                if idd.type == "CAMERA" and u.is_updated_geometry:
                    rebuild = rebuild or ex.camera_path == "/World/Camera"
                    continue
                if u.is_updated_geometry:
                    rebuild = True
                    continue
                if u.is_updated_transform:
                    obj = idd
                    if obj.type == "CAMERA":
                        if ex.camera_path == "/World/Camera":
                            rebuild = True  # camera params and transform: cheap to redo
                        continue
                    if obj.type == "LIGHT":
                        entry = ex.lights.get(obj.name)
                        if entry is None:
                            rebuild = True
                            continue
                        kind, xf, _ = entry
                        mw = obj.matrix_world
                        if kind in ("sun", "point", "spot"):  # UsdLux lights: no scale
                            from mathutils import Matrix

                            loc, rot, _s = mw.decompose()
                            mw = Matrix.Translation(loc) @ rot.to_matrix().to_4x4()
                        elif kind == "area":
                            mw = export.area_light_matrix(
                                export.light_params(obj.data, mw)[1], mw)
                        self.delegate.set_transform(xf, export.usd_matrix(mw))
                        done["transforms"] += 1
                        continue
                    xfs = ex.object_xforms.get(obj.name)
                    if not xfs or len(xfs) != 1:
                        rebuild = True  # instanced/new objects: instancer matrices unknown here
                        continue
                    self.delegate.set_transform(xfs[0], export.usd_matrix(obj.matrix_world))
                    done["transforms"] += 1
            elif isinstance(idd, (bpy.types.Mesh, bpy.types.Collection, bpy.types.Scene)):
                # Mesh datablock edits come with is_updated_geometry on the object; collection
                # or scene membership changes: a rebuild.
                if isinstance(idd, bpy.types.Collection) or \
                        (isinstance(idd, bpy.types.Scene) and u.is_updated_geometry):
                    rebuild = True
        done["rebuild"] = rebuild
        self.last_update = done
        return done

    def _update_light(self, obj):
        ex = self.export
        entry = ex.lights.get(obj.name)
        if entry is None:
            return False
        kind, xf, targets = entry
        new_kind, lp = export.light_params(obj.data, obj.matrix_world)
        if new_kind != kind:
            return False
        d = self.delegate
        if kind == "sun":
            d.set_attribute(xf, "inputs:intensity", lp["intensity"])
            d.set_attribute(xf, "inputs:angle", lp["angle"])
            d.set_attribute(xf, "inputs:color", lp["color"])
        elif kind in ("point", "spot"):
            d.set_attribute(xf, "inputs:radius", lp["radius"])
            d.set_attribute(xf, "inputs:intensity", lp["intensity"])
            d.set_attribute(xf, "inputs:color", lp["color"])
            if kind == "spot":
                sh = lp["shaping"]
                d.set_attribute(xf, "inputs:shaping:cone:angle", sh["angle"])
                d.set_attribute(xf, "inputs:shaping:cone:softness", sh["softness"])
                d.set_attribute(xf, "inputs:shaping:focus", sh["focus"])
        else:
            if lp["disk"] != ex.area_disks.get(obj.name):
                return False  # Rect <-> Disk: another prim type
            d.set_attribute(xf, "inputs:color", lp["radiance"])
            if lp["disk"]:
                d.set_transform(xf, export.usd_matrix(
                    export.area_light_matrix(lp, obj.matrix_world)))
            else:
                d.set_attribute(xf, "inputs:width", lp["size"][0])
                d.set_attribute(xf, "inputs:height", lp["size"][1])
        return True

    # ---- results -----------------------------------------------------------------------
    def blender_pass(self, name, aov_name, channels):
        """A Blender pass as a (height*width, channels) float32 array, rows bottom to top."""
        d = self.delegate
        if name == "Combined":
            img = d.aov("color")
            if not self.film_transparent:
                # Cycles' alpha is 1 everywhere unless Film > Transparent; the delegate's is
                # the coverage (0 where the ray saw the dome), which made the background of a
                # saved RGBA image transparent.
                img = np.array(img, dtype=np.float32)
                img[:, :, 3] = 1.0
        elif name == "Depth":
            # Cycles' Depth is the camera-space Z distance (planar), 1e10 where nothing hit.
            pos = d.aov("position")
            hit = d.aov("primId")[:, :, 0] >= 0
            m = self.camera_matrix
            c = np.array(m.translation, np.float32)
            fwd = -np.array(m.col[2][:3], np.float32)
            fwd /= max(float(np.linalg.norm(fwd)), 1e-12)
            z = (pos - c) @ fwd
            img = np.where(hit, z, BACKGROUND_DEPTH).astype(np.float32)[:, :, None]
        elif name == "IndexOB":
            ids = d.aov("primId")[:, :, 0]
            table = np.array([pi for (_p, _n, pi) in self.export.mesh_prims] + [0], np.float32)
            safe = np.where((ids >= 0) & (ids < len(table) - 1), ids, len(table) - 1)
            img = table[safe][:, :, None]
        else:
            img = d.aov(aov_name)
        img = np.asarray(img, dtype=np.float32)
        if img.shape[2] != channels:
            img = img[:, :, :channels]
        return np.ascontiguousarray(img[::-1]).reshape(-1, channels)

    def required_aovs(self, pass_names):
        need = ["color", "primId"]
        for (name, aov, *_rest) in PASSES:
            if name in pass_names:
                need.append(aov)
        return list(dict.fromkeys(need))

    def bind(self, names):
        for a in names:
            if a not in self.aovs:
                self.delegate.bind_aov(a)
                self.aovs.append(a)
