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

#: Object types whose evaluated mesh is exported (export.MeshData) and edited incrementally.
#: Metaballs (META) are not: one metaball's edit changes its family's base object.
MESH_TYPES = ("MESH", "CURVE", "SURFACE", "FONT")

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

    def full_sync(self, depsgraph, width, height, view_camera=None, bake_resolution=None):
        """Translates the whole depsgraph and opens it (a full rebuild). bake_resolution (final
        renders): bake procedural material inputs with Cycles at that size (bake.py)."""
        self.resize(width, height)
        self.film_transparent = bool(depsgraph.scene.render.film_transparent)
        baker = None
        if bake_resolution:
            from . import bake

            baker = bake.Baker(bake_resolution)
        ex = export.SceneExport(self.p, depsgraph, self.texture_dir, width, height,
                                view_camera=view_camera, baker=baker)
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
                     "horizontalApertureOffset", "verticalApertureOffset", "fStop", "focusDistance",
                     "principled:apertureBlades", "principled:apertureRotation"):
                self.delegate.set_attribute("/World/ViewCamera", k, v)
        self.camera_matrix = matrix.copy()

    def apply_updates(self, depsgraph, updates):
        """Applies depsgraph updates through the delegate's edit calls where it can.

        Material: every surface input is re-set (material tables only, no BVH build);
        a change in which inputs are texture-linked rebuilds. Light: intensity/color/angle/
        radius/cone or the area emitter's radiance. Object transform only: set_transform on its
        Xform (no mesh rebuild). World color: the dome light's color (a world texture: rebuild).
        Image (painted, reloaded): its pixels file is written again, or its own file checked,
        and the delegate re-reads texture files (reload_textures); an image that now needs
        another file rebuilds.

        Geometry (edit-mode data, modifiers, sculpting, material slots) of an exported mesh-like
        object: only that object's evaluated mesh is re-exported (export.MeshData, as the full
        export does) and written to its Geom_<slot> meshes: points and normals when the
        triangles are unchanged, faceVertexCounts/Indices too when not, st when it changed,
        material:binding when the slot's material changed; slots that appear become new Mesh
        prims, slots that vanish are removed. The export has no prototypes (one mesh copy per
        instance Xform), so every copy of an instanced object is rewritten.
        Added objects (mesh-like, lights; cameras in the viewport) get their prims through
        add_prim; deleted (or hidden) objects' prims are removed. New untextured materials are
        added through the edit calls.

        A full rebuild remains for: instancers (collection instances, particle/geometry-node
        instances: their instance set may change) and their collections, removing an object
        that is also instanced, metaballs, a new or changed mesh whose textured material needs
        an st the edit calls cannot give the faceVarying interpolation of (new Mesh prims, a UV
        map added or removed), new textured materials, the scene camera (final renders), world
        textures, material link changes. Returns a dict of what was done: counts of
        materials, lights, transforms, world, geometry (objects re-exported), added, removed,
        and rebuild."""
        ex = self.export
        done = {"materials": 0, "lights": 0, "transforms": 0, "world": 0, "geometry": 0,
                "added": 0, "removed": 0, "textures": 0, "rebuild": False}
        if ex is None:
            return done | {"rebuild": True}
        rebuild = False
        textures = None     # "changed": texture files to read again (only those that changed)
        membership = False  # objects may have been added, deleted, hidden or shown
        geometry = {}       # object name -> evaluated object whose mesh changed
        unknown = []        # objects not in the export: added below, or only instanced
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
                        if obj.name not in ex.lights:
                            if obj.name in ex.top_objects:
                                rebuild = True  # an unsupported type until now
                            else:
                                membership = True  # a new lamp: added below
                        elif not self._update_light(obj):
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
                if idd.name not in ex.top_objects and idd.name not in ex.object_xforms:
                    membership = True  # a new object (or one only instanced): see below
                    unknown.append(idd.name)
                    continue
                if idd.name in ex.instancers:
                    rebuild = True  # its instances may have changed with it
                    continue
                if idd.type == "LIGHT" and u.is_updated_geometry and not u.is_updated_transform:
                    # Light data edits tag the object's "geometry": parameters only.
                    if not self._update_light(idd):
                        rebuild = True
                    continue
                if idd.type == "CAMERA" and u.is_updated_geometry:
                    rebuild = rebuild or ex.camera_path == "/World/Camera"
                    continue
                if u.is_updated_geometry:
                    if idd.type in MESH_TYPES:
                        geometry[idd.name] = idd
                    elif idd.type not in ("EMPTY", "CAMERA", "LIGHT") or idd.is_instancer:
                        rebuild = True  # metaballs, armatures, ...: not tracked
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
                            if obj.name not in ex.top_objects:
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
                    if not xfs and obj.name in ex.top_objects and obj.type not in MESH_TYPES:
                        continue  # an empty (not an instancer): nothing drawn
                    if not xfs and obj.name in geometry:
                        continue  # no triangles before: the geometry sync adds its Xform
                    if not xfs or len(xfs) != 1:
                        rebuild = True  # instanced/new objects: instancer matrices unknown here
                        continue
                    self.delegate.set_transform(xfs[0], export.usd_matrix(obj.matrix_world))
                    done["transforms"] += 1
            elif isinstance(idd, bpy.types.Collection):
                # Membership or visibility of objects changed. A collection that may be
                # instanced: its instances change with it (rebuild).
                if ex.instancers and idd.original != depsgraph.scene.collection.original:
                    rebuild = True
                membership = True
            elif isinstance(idd, bpy.types.Scene):
                membership = True
            elif isinstance(idd, bpy.types.Image):
                # Painted, reloaded or regenerated: its texture file is written again (or, read
                # from its own file, checked for a change on disk) and the delegate re-reads it.
                what = ex.textures.refresh(idd.original)
                if what == "moved":
                    rebuild = True
                elif what is not None:
                    textures = "changed"
            # Mesh datablock edits come with is_updated_geometry on every object using it.
        if not rebuild:
            for name, obj in geometry.items():
                if not self._sync_geometry(depsgraph, obj):
                    rebuild = True
                    break
                done["geometry"] += 1
        if not rebuild and membership:
            counts = self._sync_membership(depsgraph)
            if counts is None:
                rebuild = True
            else:
                done["added"], done["removed"] = counts
                # An object edited that is not among the depsgraph's own objects: seen only
                # through instances the export did not give a mesh (no triangles until now).
                rebuild = any(n not in ex.top_objects for n in unknown)
        if textures and not rebuild:
            done["textures"] = int(self.delegate.reload_textures(only_changed=True))
        done["rebuild"] = rebuild
        self.last_update = done
        return done

    # ---- incremental geometry and object edits (apply_updates) -------------------------
    def _sync_geometry(self, depsgraph, obj):
        """Re-exports one object's evaluated mesh into every Xform holding a copy of it.
        False: the caller rebuilds."""
        ex = self.export
        name = obj.name
        if obj.type not in MESH_TYPES or obj.is_instancer or name in ex.instancers:
            return False
        xfs = ex.object_xforms.get(name, [])
        if not xfs:
            if name not in ex.top_objects:
                return False
            return self._add_mesh_object(depsgraph, obj)  # had no triangles until now
        try:
            md = export.MeshData(obj.original.evaluated_get(depsgraph))
        except RuntimeError:
            return False
        ex.meshes[name] = md
        for xf in xfs:
            if not self._write_parts(xf, obj, md):
                return False
        return True

    def _material_path(self, material):
        """The material prim of a Blender material, added through the edit calls if it is
        new (untextured only: None for a textured one, the caller rebuilds)."""
        ex = self.export
        key = material.name if material is not None else "__default__"
        if key in ex.materials:
            return ex.materials[key][0]
        inputs, links, warns = export.material_params(material, ex.textures)
        if links:
            return None
        mapping = export.uv_mapping(material, []) if material is not None else None
        d = self.delegate
        if not ex.materials:
            d.add_prim("/World/Looks", "Xform")
        path = "/World/Looks/" + ex._unique(export.usd_name(key, "Mat"))
        shader = path + "/Surface"
        d.add_prim(path, "Material")
        d.add_prim(shader, "Shader")
        d.set_attribute(shader, "info:id", "UsdPreviewSurface")
        d.connect(path, "outputs:surface", shader + ".outputs:surface")
        for k, v in inputs.items():
            n = len(v) if isinstance(v, (list, tuple)) else 1
            t = ("int" if k == "useSpecularWorkflow" else "normal3f" if k == "normal"
                 else "color3f" if n == 3 else "float")
            d.set_attribute_typed(shader, "inputs:" + k, t, v)
        ex.warnings += warns
        ex.st_mappings[key] = mapping
        ex.materials[key] = (path, export.link_signature(links, mapping))
        return path

    def _write_parts(self, xf, obj, md):
        """Writes MeshData md into the Geom_<slot> meshes under xf (adding and removing slots)."""
        ex = self.export
        d = self.delegate
        info = ex.xform_info[xf]
        parts = info["parts"]
        seen = set()
        for slot, idx, nrm, st in md.parts:
            mat = None
            if 0 <= slot < len(obj.material_slots):
                mat = obj.material_slots[slot].material
            mpath = self._material_path(mat)
            if mpath is None:
                return False
            key = mat.name if mat is not None else "__default__"
            st = export.transform_st(st, ex.st_mappings.get(key))
            textured = len(ex.materials[key][1]) > 1
            seen.add(slot)
            gp = parts.get(slot)
            if gp is not None:
                if not self._update_mesh(gp, md.points, idx, nrm, st, mpath, textured):
                    return False
                continue
            if textured:
                return False  # a new prim's st could not be faceVarying (see apply_updates)
            gp = f"{xf}/Geom_{slot}"
            d.add_prim(gp, "Mesh")
            d.set_attribute_typed(gp, "doubleSided", "bool", 1)
            ex.prim_state[gp] = {"layout": "expanded", "idx": None, "npts": 0, "st": None,
                                 "mat": None}
            self._update_mesh(gp, md.points, idx, nrm, st, mpath, textured)
            parts[slot] = gp
            ex.mesh_index[gp] = len(ex.mesh_prims)
            ex.mesh_prims.append((gp, info["name"], info["pass_index"]))
        for slot in [s for s in parts if s not in seen]:
            self._remove_mesh(parts.pop(slot))
        return True

    def _update_mesh(self, gp, points, idx, nrm, st, mpath, textured):
        """One Geom_<slot> mesh: points + normals when its triangles are unchanged, the
        topology too otherwise. Builder-written meshes ('indexed': all the object's points,
        faceVarying normals/st) keep their layout; meshes added through the edit calls
        ('expanded': one point per triangle corner, vertex normals, since an edit cannot
        author the faceVarying interpolation) keep theirs."""
        d = self.delegate
        stt = self.export.prim_state[gp]
        tris = len(idx) // 3
        if stt["layout"] == "expanded":
            if stt["npts"] != len(idx):
                d.set_attribute_typed(gp, "faceVertexCounts", "int[]",
                                      np.full(tris, 3, np.int32))
                d.set_attribute_typed(gp, "faceVertexIndices", "int[]",
                                      np.arange(len(idx), dtype=np.int32))
            d.set_attribute_typed(gp, "points", "point3f[]", points.reshape(-1, 3)[idx].ravel())
            d.set_attribute_typed(gp, "normals", "normal3f[]", nrm)
            stt["npts"] = len(idx)
        else:
            npts = len(points) // 3
            if (st is None) != (stt["st"] is None):
                return False  # a UV map added/removed: st's interpolation (rebuild)
            topo = npts == stt["npts"] and np.array_equal(idx, stt["idx"])
            if not topo:
                d.set_attribute(gp, "faceVertexCounts", np.full(tris, 3, np.int32))
                d.set_attribute(gp, "faceVertexIndices", idx)
            d.set_attribute(gp, "points", points)
            d.set_attribute(gp, "normals", nrm)
            if st is not None and (not topo or not np.array_equal(st, stt["st"])):
                d.set_attribute(gp, "primvars:st", st)
            stt.update(idx=idx, npts=npts, st=st)
        if mpath != stt["mat"]:
            d.bind_material(gp, mpath)
            stt["mat"] = mpath
        return True

    def _remove_mesh(self, gp):
        ex = self.export
        self.delegate.remove_prim(gp)
        i = ex.mesh_index.pop(gp, None)
        if i is not None:
            ex.mesh_prims[i] = (None, None, 0)  # primIds are not reused
        ex.prim_state.pop(gp, None)

    def _add_mesh_object(self, depsgraph, obj):
        ex = self.export
        name = obj.name
        if obj.is_instancer:
            return False
        try:
            md = export.MeshData(obj.original.evaluated_get(depsgraph))
        except RuntimeError as e:
            ex.warnings.append(f"object '{name}': {e}")
            ex.top_objects.add(name)
            return True
        ex.top_objects.add(name)
        if md.triangles == 0:
            return True
        ex.meshes[name] = md
        xf = "/World/" + ex._unique(export.usd_name(name, "Obj"))
        self.delegate.add_prim(xf, "Xform")
        self.delegate.set_transform(xf, export.usd_matrix(obj.matrix_world))
        ex.object_xforms.setdefault(name, []).append(xf)
        ex.xform_info[xf] = {"name": name, "source": name, "parent": None, "parts": {},
                             "pass_index": int(obj.pass_index)}
        return self._write_parts(xf, obj, md)

    def _add_light(self, obj):
        """A new lamp as the prim SceneExport._light writes, through the edit calls."""
        from mathutils import Matrix

        ex = self.export
        d = self.delegate
        name, mw = obj.name, obj.matrix_world
        ex.top_objects.add(name)
        kind, lp = export.light_params(obj.data, mw)
        if kind is None:
            ex.warnings.append(f"light '{name}': type {obj.data.type} not supported")
            return True
        xf = "/World/" + ex._unique(export.usd_name(name, "Light"))
        loc, rot, _ = mw.decompose()
        rigid = export.usd_matrix(Matrix.Translation(loc) @ rot.to_matrix().to_4x4())
        f = lambda attr, v: d.set_attribute_typed(xf, attr, "float", v)  # noqa: E731
        if kind == "sun":
            d.add_prim(xf, "DistantLight")
            d.set_transform(xf, rigid)
            f("inputs:intensity", lp["intensity"])
            f("inputs:angle", lp["angle"])
            d.set_attribute_typed(xf, "inputs:color", "color3f", lp["color"])
        elif kind in ("point", "spot"):
            d.add_prim(xf, "SphereLight")
            d.set_transform(xf, rigid)
            f("inputs:radius", lp["radius"])
            f("inputs:intensity", lp["intensity"])
            d.set_attribute_typed(xf, "inputs:color", "color3f", lp["color"])
            if kind == "spot":
                sh = lp["shaping"]
                f("inputs:shaping:cone:angle", sh["angle"])
                f("inputs:shaping:cone:softness", sh["softness"])
                f("inputs:shaping:focus", sh["focus"])
        elif kind == "portal":  # as SceneExport._light: sized by width/height, placed by mw
            d.add_prim(xf, "PortalLight")
            d.set_transform(xf, export.usd_matrix(mw))
            f("inputs:width", lp["size"][0])
            f("inputs:height", lp["size"][1])
            if lp["disk"]:
                ex.warnings.append(f"light '{name}': a round portal is exported as a rectangle")
        else:
            d.add_prim(xf, "DiskLight" if lp["disk"] else "RectLight")
            d.set_transform(xf, export.usd_matrix(export.area_light_matrix(lp, mw)))
            if lp["disk"]:
                f("inputs:radius", 0.5)
            else:
                f("inputs:width", lp["size"][0])
                f("inputs:height", lp["size"][1])
            f("inputs:intensity", 1.0)
            d.set_attribute_typed(xf, "inputs:color", "color3f", lp["radiance"])
            ex.area_disks[name] = lp["disk"]
        if lp.get("shadows") is False:  # Cycles' Cast Shadow off: UsdLux ShadowAPI
            d.set_attribute_typed(xf, "inputs:shadow:enable", "bool", 0)
        if kind != "portal":
            for attr, v in export.light_lobe_scales(obj).items():
                d.set_attribute_typed(xf, attr, "float", v)
        ex.lights[name] = (kind, xf, [xf])
        return True

    def _remove_object(self, name):
        ex = self.export
        if name in ex.instancers or name == ex.camera_object:
            return False
        if name in ex.instanced:
            return False  # also instanced: its instance copies stay or go with the instancer
        xfs = ex.object_xforms.get(name, [])
        for xf in xfs:
            for gp in ex.xform_info.pop(xf)["parts"].values():
                i = ex.mesh_index.pop(gp, None)
                if i is not None:
                    ex.mesh_prims[i] = (None, None, 0)
                ex.prim_state.pop(gp, None)
            self.delegate.remove_prim(xf)  # the Xform and its meshes
        ex.object_xforms.pop(name, None)
        ex.meshes.pop(name, None)
        if name in ex.lights:
            self.delegate.remove_prim(ex.lights.pop(name)[1])
            ex.area_disks.pop(name, None)
        ex.top_objects.discard(name)
        return True

    def _sync_membership(self, depsgraph):
        """Objects added to / removed from the depsgraph since the export -> (added, removed),
        or None when the caller must rebuild."""
        ex = self.export
        current = {o.name: o for o in depsgraph.objects}
        removed = [n for n in ex.top_objects if n not in current]
        added = [o for n, o in current.items() if n not in ex.top_objects]
        for name in removed:
            if not self._remove_object(name):
                return None
        for obj in added:
            if obj.is_instancer:
                return None
            if obj.type in MESH_TYPES:
                if not self._add_mesh_object(depsgraph, obj):
                    return None
            elif obj.type == "LIGHT":
                self._add_light(obj)
            elif obj.type == "CAMERA":
                if ex.camera_path == "/World/Camera":
                    return None  # it may be the scene camera (final render sessions)
                ex.top_objects.add(obj.name)
            elif obj.type == "EMPTY":
                ex.top_objects.add(obj.name)
            else:
                return None  # metaballs, volumes, grease pencil, ...: a rebuild decides
        return len(added), len(removed)

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
        elif kind == "portal":
            d.set_attribute(xf, "inputs:width", lp["size"][0])
            d.set_attribute(xf, "inputs:height", lp["size"][1])
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
        if "shadows" in lp:
            d.set_attribute_typed(xf, "inputs:shadow:enable", "bool", 1 if lp["shadows"] else 0)
            scales = export.light_lobe_scales(obj)
            for attr in ("inputs:diffuse", "inputs:specular"):
                d.set_attribute_typed(xf, attr, "float", scales.get(attr, 1.0))
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
