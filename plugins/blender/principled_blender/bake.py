# SPDX-License-Identifier: Apache-2.0
"""Cycles bakes of procedural shader inputs (final renders only).

A Principled BSDF input (or a Diffuse/Glossy/Glass/Emission node input, or a Normal Map's
Color) fed by anything but an Image Texture is evaluated by Cycles itself over the object's
UVs: a temporary copy of the object in a temporary scene gets a temporary copy of the material
whose output is an Emission shader of that socket's source, and `bpy.ops.object.bake(type=
'EMIT')` writes it into a float, non-colour image. The user's object, mesh and material are
never modified: everything the bake needs is a copy, removed afterwards (also on errors).
A socket inside node groups (export.GNode.key) is exposed through copies of its groups; a
Principled Normal fed by a Bump node (or any source but a Normal Map) is a NORMAL bake in the
UV map's tangent space ('normal:' + identifier).

The pixels (linear, rows bottom to top) are cached for the Blender session under a key of the
material's node tree, the object's evaluated mesh (points, UVs, matrix), the socket and the
resolution, so re-rendering an unchanged scene does not bake again.

bpy.ops must run on Blender's main thread: command-line renders (`blender -b ... -f`) and
bpy.ops.render.render() from a script call the engine there; an interactive F12 renders on a
job thread, where Baker.available() is False: it uses what CACHE holds (the operator
PRINCIPLED_OT_bake_procedural fills it from the main thread) and leaves the other inputs at
their socket values (warned).
"""
import hashlib
import threading
import time

import numpy as np

#: (material fingerprint, mesh fingerprint, node name, socket identifier, resolution) ->
#: float32 (h, w, 3) (colours) or (h, w, 1) (scalars) linear pixels, rows bottom to top. Lives
#: as long as the add-on module.
CACHE = {}
#: Bytes CACHE may hold (a 512^2 colour bake is 3 MB, a scalar 1 MB): the oldest go first.
CACHE_BYTES = 512 << 20

#: Cycles samples per texel. 4 (a filtered texel) rendered the material library no closer to
#: Cycles than 1 and baked 2-3x slower.
SAMPLES = 1
#: Pixels the bake extends each UV island by (bilinear lookups and mip levels at the edges).
MARGIN = 8

_NODE_SKIP = {"rna_type", "location", "width", "width_hidden", "height", "dimensions",
              "select", "hide", "show_options", "show_preview", "show_texture", "label",
              "use_custom_color", "color", "parent", "inputs", "outputs", "internal_links",
              "name", "type", "mute"}


def _value(v, depth, out, seen):
    import bpy

    if v is None or isinstance(v, (bool, int, float, str)):
        out.append(repr(v))
        return
    if isinstance(v, bpy.types.ID):
        out.append(type(v).__name__ + ":" + v.name_full)
        if isinstance(v, bpy.types.Image):
            out.append(repr((v.filepath, v.source, bool(v.is_dirty), tuple(v.size))))
        elif isinstance(v, bpy.types.Object):
            out.append(repr([tuple(r) for r in v.matrix_world]))
        elif isinstance(v, bpy.types.NodeTree) and v.name_full not in seen:
            seen.add(v.name_full)
            _tree(v, out, seen)
        return
    if isinstance(v, bpy.types.bpy_struct):
        if depth <= 0:
            return
        for p in v.bl_rna.properties:
            if p.identifier in ("rna_type",) or p.identifier.startswith("bl_"):
                continue
            try:
                _value(getattr(v, p.identifier), depth - 1, out, seen)
            except Exception:
                pass
        return
    try:
        items = list(v)
    except TypeError:
        out.append(repr(v))
        return
    for x in items:
        _value(x, depth - 1, out, seen)


def _tree(tree, out, seen):
    for n in tree.nodes:
        out.append(n.bl_idname + ":" + n.name + ":" + str(n.mute))
        for p in n.bl_rna.properties:
            k = p.identifier
            if k in _NODE_SKIP or k.startswith("bl_"):
                continue
            try:
                _value(getattr(n, k), 4, out, seen)
            except Exception:
                pass
        for s in n.inputs:
            if hasattr(s, "default_value"):
                _value(s.default_value, 1, out, seen)
    for link in tree.links:
        out.append("L" + repr((link.from_node.name, link.from_socket.identifier,
                               link.to_node.name, link.to_socket.identifier, link.is_muted)))


def tree_fingerprint(material):
    """A digest of everything in a material's node tree (and its groups) that can change what
    a bake of it gives: node types and settings, socket values, colour ramps, curves, links."""
    out, seen = [], set()
    if material.node_tree is not None:
        _tree(material.node_tree, out, seen)
    return hashlib.sha1("\n".join(out).encode()).hexdigest()


def mesh_fingerprint(md, matrix):
    """A digest of an exported mesh (export.MeshData: points, triangles, UVs) and its matrix:
    Position and Object-space inputs change with both."""
    h = hashlib.sha1()
    h.update(np.ascontiguousarray(md.points).tobytes())
    for slot, idx, _nrm, st in md.parts:
        h.update(str(slot).encode())
        h.update(np.ascontiguousarray(idx).tobytes())
        if st is not None:
            h.update(np.ascontiguousarray(st).tobytes())
    h.update(repr([tuple(r) for r in matrix]).encode())
    return h.hexdigest()


class BakeError(RuntimeError):
    pass


#: Group interface socket types for exposing a source socket of each type.
_INTERFACE = {"RGBA": "NodeSocketColor", "VALUE": "NodeSocketFloat", "VECTOR": "NodeSocketVector",
              "INT": "NodeSocketInt", "BOOLEAN": "NodeSocketBool", "SHADER": "NodeSocketShader"}


def _copy_groups(tree, copies, depth=0):
    """Gives every GROUP node of tree (a temporary material copy's) its own copy of its group,
    recursively, so the bake can add outputs to them without touching the user's groups.
    The copies are appended to `copies` (removed by the caller)."""
    if depth > 32:
        raise BakeError("node groups nested too deep")
    for n in tree.nodes:
        if n.type == "GROUP" and n.node_tree is not None:
            c = n.node_tree.copy()
            c.name = "principled_bake_" + n.node_tree.name
            copies.append(c)
            n.node_tree = c
            _copy_groups(c, copies, depth + 1)


def _cache_put(key, px):
    CACHE.pop(key, None)
    total = sum(v.nbytes for v in CACHE.values()) + px.nbytes
    while CACHE and total > CACHE_BYTES:
        total -= CACHE.pop(next(iter(CACHE))).nbytes
    CACHE[key] = px


OFF_THREAD = ("not in the bake cache, and an interactive render runs off Blender's main "
              "thread where Cycles cannot bake: press Render properties > principled > Bake "
              "Procedural Textures first")


class Baker:
    """Bakes sockets of one render's materials; owns the temporary scene while it lives
    (close() removes it)."""

    def __init__(self, resolution=512):
        self.resolution = int(resolution)
        self.seconds = 0.0   # time spent in Cycles bakes (cache hits excluded)
        self.baked = 0       # sockets baked
        self.reused = 0      # sockets found in CACHE
        self.off_thread = 0  # sockets not in CACHE that could not be baked (not main thread)
        self._scene = None
        self._objects = {}   # original object name -> temporary copy
        self._other = None   # the material given to slots not being baked
        self._fingerprints = {}

    @staticmethod
    def available():
        return threading.current_thread() is threading.main_thread()

    def material_key(self, material):
        k = material.name_full
        if k not in self._fingerprints:
            self._fingerprints[k] = tree_fingerprint(material)
        return self._fingerprints[k]

    def bake(self, obj, material, node_name, socket_identifier, mesh_key, uv_name,
             scalar=False):
        """Linear float32 pixels (rows bottom to top; (h, w, 3), or (h, w, 1) for a scalar) of
        the socket `socket_identifier` of node `node_name` in `material` (the value reaching
        that input; 'out:' + identifier: an Emission node's own output) evaluated on the
        original object `obj` over its UV map `uv_name`. Raises BakeError with the reason."""
        r = self.bake_many(obj, material, [(node_name, socket_identifier, scalar)], mesh_key,
                           uv_name)[0]
        if isinstance(r, BakeError):
            raise r
        return r

    def bake_many(self, obj, material, sockets, mesh_key, uv_name):
        """bake() for a list of (node name, socket identifier, scalar): one result per entry,
        the pixels or a BakeError. Scalars missing from CACHE are baked three at a time, one
        per channel (a Combine Color node), colours one per bake."""
        mkey = self.material_key(material)
        out = [None] * len(sockets)
        todo = []
        for i, (node_name, ident, scalar) in enumerate(sockets):
            key = (mkey, mesh_key, node_name, ident, self.resolution)
            px = CACHE.get(key)
            if px is not None:
                self.reused += 1
                out[i] = px
            elif not self.available():
                self.off_thread += 1
                out[i] = BakeError(OFF_THREAD)
            else:
                todo.append((i, key))
        scalars = [t for t in todo if sockets[t[0]][2] and ":" not in sockets[t[0]][1]]
        groups = [scalars[k:k + 3] for k in range(0, len(scalars), 3)]
        groups += [[t] for t in todo if t not in scalars]
        for group in groups:
            t0 = time.perf_counter()
            try:
                px = self._bake(obj, material, [sockets[i][:2] for i, _k in group], uv_name,
                                packed=group[0] in scalars)
            except BakeError as e:
                for i, _k in group:
                    out[i] = e
                continue
            self.seconds += time.perf_counter() - t0
            self.baked += 1
            for c, (i, key) in enumerate(group):
                r = np.ascontiguousarray(px[:, :, c:c + 1]) if sockets[i][2] else px
                _cache_put(key, r)
                out[i] = r
        return out

    # ---- the temporary scene -------------------------------------------------------------
    def _temp_scene(self):
        import bpy

        if self._scene is None:
            sc = bpy.data.scenes.new("principled_bake")
            sc.render.engine = "CYCLES"
            c = sc.cycles
            c.device = "CPU"
            c.samples = SAMPLES
            c.use_denoising = False
            c.use_adaptive_sampling = False
            sc.render.bake.margin = MARGIN
            self._scene = sc
        return self._scene

    def _temp_object(self, obj):
        import bpy

        t = self._objects.get(obj.name_full)
        if t is None:
            t = obj.copy()  # shares the mesh; the copy's own slots are overridden below
            t.name = "principled_bake_" + obj.name
            self._temp_scene().collection.objects.link(t)
            t.hide_render = False
            t.hide_viewport = False
            for k in ("visible_camera", "visible_diffuse", "visible_glossy",
                      "visible_transmission", "visible_volume_scatter", "visible_shadow"):
                if hasattr(t, k):
                    setattr(t, k, True)
            self._objects[obj.name_full] = t
        return t

    def _other_material(self):
        """A black emitter with its own 1x1 image for the slots of other materials (the bake
        wants an active image in every slot)."""
        import bpy

        if self._other is None:
            m = bpy.data.materials.new("principled_bake_other")
            m.use_nodes = True
            nt = m.node_tree
            img = bpy.data.images.new("principled_bake_other", 1, 1)
            tex = nt.nodes.new("ShaderNodeTexImage")
            tex.image = img
            nt.nodes.active = tex
            self._other = (m, img)
        return self._other[0]

    def _source(self, nt, node_name, socket_identifier):
        """(source socket in the material copy's tree, True for an Emission node's own
        output). node_name is export.GNode.key: a node inside (nested) groups has its group
        nodes' names in front; the groups on the way are copies (_copy_groups), and the source
        is exposed as an extra output of each enclosing group copy up to the top level."""
        from .export import PATH_SEP, _group_output, resolve_input

        names = node_name.split(PATH_SEP)
        tree, path = nt, []
        for g in names[:-1]:
            gn = tree.nodes.get(g)
            if gn is None or gn.type != "GROUP" or gn.node_tree is None:
                raise BakeError(f"group node {g} not found")
            path.append(gn)
            tree = gn.node_tree
        node = tree.nodes.get(names[-1])
        output = socket_identifier.startswith("out:")
        ident = socket_identifier.split(":", 1)[1] if ":" in socket_identifier else \
            socket_identifier
        sock = None if node is None else next(
            (s for s in (node.outputs if output else node.inputs) if s.identifier == ident), None)
        if sock is None:
            raise BakeError(f"socket {node_name}.{socket_identifier} not found")
        if output:  # an Emission shader's own output (its Color x Strength)
            if node.type not in ("EMISSION", "BACKGROUND"):  # a Background on a surface emits
                raise BakeError(f"output of a {node.type} node")
            src = sock
        else:
            src, path, _v = resolve_input(sock, path)
            if src is None:
                raise BakeError(f"socket {node_name}.{socket_identifier} not linked")
            if src.type == "SHADER":
                raise BakeError("fed by a shader output")
        for g in reversed(path):  # innermost first: one more output on each group copy
            t = g.node_tree
            iface = t.outputs.new(_INTERFACE.get(src.type, "NodeSocketColor"), "principled_bake")
            go = _group_output(t) or t.nodes.new("NodeGroupOutput")
            target = next((x for x in go.inputs if x.identifier == iface.identifier), None)
            outer = next((x for x in g.outputs if x.identifier == iface.identifier), None)
            if target is None or outer is None:
                raise BakeError(f"could not expose {node_name} through group {g.name}")
            t.links.new(src, target)
            src = outer
        return src, output

    def _bake(self, obj, material, sources, uv_name, packed=False):
        """One Cycles bake: sources [(node name, socket identifier)] is one socket, or with
        packed up to three scalar sockets written to R, G, B. (h, w, 3) pixels."""
        import bpy

        if obj.type != "MESH":
            raise BakeError(f"object type {obj.type} (meshes only)")
        sc = self._temp_scene()
        tobj = self._temp_object(obj)
        mcopy = material.copy()
        mcopy.name = "principled_bake_" + material.name
        img = None
        copies = []
        try:
            nt = mcopy.node_tree
            if any(n.type == "GROUP" for n in nt.nodes):
                _copy_groups(nt, copies)
            found = [self._source(nt, n, i) for n, i in sources]
            for n in [n for n in nt.nodes if n.type == "OUTPUT_MATERIAL"]:
                nt.nodes.remove(n)
            out = nt.nodes.new("ShaderNodeOutputMaterial")
            out.target = "ALL"
            normal = sources[0][1].startswith("normal:")
            if normal:
                # A normal source (Bump, ...): Cycles' NORMAL bake of a Diffuse BSDF with that
                # Normal writes the perturbed normal in the UV map's tangent space, 0.5 + 0.5 n.
                dif = nt.nodes.new("ShaderNodeBsdfDiffuse")
                nt.links.new(found[0][0], dif.inputs["Normal"])
                nt.links.new(dif.outputs[0], out.inputs["Surface"])
            elif found[0][1]:
                nt.links.new(found[0][0], out.inputs["Surface"])
            else:
                em = nt.nodes.new("ShaderNodeEmission")
                em.inputs["Strength"].default_value = 1.0
                nt.links.new(em.outputs["Emission"], out.inputs["Surface"])
                if packed:
                    # Each scalar converted to a float as its own input would convert it.
                    comb = nt.nodes.new("ShaderNodeCombineColor")
                    comb.mode = "RGB"
                    for c in range(3):
                        comb.inputs[c].default_value = 0.0
                    for c, (src, _o) in enumerate(found):
                        nt.links.new(src, comb.inputs[c])
                    nt.links.new(comb.outputs[0], em.inputs["Color"])
                else:
                    nt.links.new(found[0][0], em.inputs["Color"])
            res = self.resolution
            img = bpy.data.images.new("principled_bake", res, res, alpha=False,
                                      float_buffer=True, is_data=True)
            img.colorspace_settings.is_data = True
            tex = nt.nodes.new("ShaderNodeTexImage")
            tex.image = img
            for n in nt.nodes:
                n.select = False
            tex.select = True
            nt.nodes.active = tex
            used = False
            for i, slot in enumerate(obj.material_slots):
                ts = tobj.material_slots[i]
                ts.link = "OBJECT"
                if slot.material is not None and slot.material.original == material:
                    ts.material = mcopy
                    used = True
                else:
                    ts.material = self._other_material()
            if not used:
                raise BakeError("the material is in none of the object's slots")
            vl = sc.view_layers[0]
            for o in sc.objects:
                o.select_set(o == tobj, view_layer=vl)
            vl.objects.active = tobj
            with bpy.context.temp_override(scene=sc, view_layer=vl, active_object=tobj,
                                           object=tobj, selected_objects=[tobj],
                                           selected_editable_objects=[tobj]):
                extra = dict(normal_space="TANGENT", normal_r="POS_X", normal_g="POS_Y",
                             normal_b="POS_Z") if normal else {}
                r = bpy.ops.object.bake(type="NORMAL" if normal else "EMIT", margin=MARGIN,
                                        use_clear=True, **extra,
                                        uv_layer=uv_name or "", target="IMAGE_TEXTURES",
                                        save_mode="INTERNAL", use_selected_to_active=False)
            if "FINISHED" not in r:
                raise BakeError(f"bake returned {r}")
            w, h = img.size
            px = np.empty(w * h * 4, np.float32)
            img.pixels.foreach_get(px)
            return np.ascontiguousarray(px.reshape(h, w, 4)[:, :, :3])
        except BakeError:
            raise
        except Exception as e:  # the bake operator reports through RuntimeError
            raise BakeError(str(e).strip().replace("\n", " ")) from e
        finally:
            for slot in tobj.material_slots:
                if slot.link == "OBJECT":
                    slot.material = None
            bpy.data.materials.remove(mcopy)
            for c in reversed(copies):
                bpy.data.node_groups.remove(c)
            if img is not None:
                bpy.data.images.remove(img)

    def close(self):
        """Removes the temporary scene, objects, material and image."""
        import bpy

        for t in self._objects.values():
            try:
                bpy.data.objects.remove(t)
            except Exception:
                pass
        self._objects.clear()
        if self._other is not None:
            m, img = self._other
            try:
                bpy.data.materials.remove(m)
                bpy.data.images.remove(img)
            except Exception:
                pass
            self._other = None
        if self._scene is not None:
            try:
                bpy.data.scenes.remove(self._scene)
            except Exception:
                pass
            self._scene = None
