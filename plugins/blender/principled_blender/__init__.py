# SPDX-License-Identifier: Apache-2.0
"""principled render engine for Blender 3.4 (bl_idname "PRINCIPLED").

Final renders (F12, `blender -b file.blend -E PRINCIPLED -f 1`) translate the evaluated
depsgraph into a principled.SceneBuilder, render progressive passes through the C ABI and
write Combined plus Depth, Normal, IndexOB, Diffuse, Glossy, Emit and the other principled
AOVs into the render result. The viewport renders progressively and applies material, light,
world, transform, mesh geometry and added/deleted object edits through the delegate's edit
calls (session.Session.apply_updates lists what still needs a full sync).
"""

bl_info = {
    "name": "principled",
    "author": "principled",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Render Properties > Render Engine > principled",
    "description": "The principled Disney-BSDF path tracer as a render engine",
    "category": "Render",
}

import math
import time

import bpy

from . import session as _session

_ENGINE_PANELS = []


class PrincipledSettings(bpy.types.PropertyGroup):
    samples: bpy.props.IntProperty(name="Samples", default=64, min=1, max=1 << 16,
                                   description="Samples per pixel of a final render")
    preview_samples: bpy.props.IntProperty(name="Viewport Samples", default=32, min=1,
                                           max=1 << 16,
                                           description="Samples per pixel in the viewport")
    max_depth: bpy.props.IntProperty(name="Max Bounces", default=8, min=0, max=1024)
    time_limit: bpy.props.FloatProperty(name="Time Limit", default=0.0, min=0.0,
                                        description="Stop a final render after this many "
                                                    "seconds (0: no limit)")
    seed: bpy.props.IntProperty(name="Seed", default=0, min=0)
    fresnel: bpy.props.EnumProperty(
        name="Specular Fresnel", default="DIELECTRIC",
        items=[("DIELECTRIC", "Principled v1 (Cycles)",
                "The specular Fresnel shaped like Blender's Principled BSDF in Cycles 3.4: exact "
                "dielectric Fresnel of the IOR the Specular input implies"),
               ("SCHLICK", "Disney (Schlick)",
                "Schlick's approximation, as in Burley's Disney BRDF and UsdPreviewSurface")],
        description="Fresnel curve of the specular lobe (the delegate's specularFresnel)")
    bake_procedural: bpy.props.BoolProperty(
        name="Bake Procedural Textures", default=True,
        description="Final renders: bake material inputs fed by procedural nodes (noise, color "
                    "ramps, math...) into textures with Cycles over the object's UV map; the "
                    "viewport and objects without UVs keep the sockets' values")
    bake_resolution: bpy.props.IntProperty(
        name="Bake Resolution", default=512, min=16, max=8192,
        description="Width and height in pixels of each baked procedural texture")
    viewport_scale: bpy.props.FloatProperty(
        name="Viewport Resolution", default=0.5, min=0.1, max=1.0, subtype="FACTOR",
        description="Viewport render size relative to the 3D view (the image is stretched to "
                    "fit); smaller shows the first image after an edit sooner")


def _settings(scene, viewport):
    s = scene.principled
    out = {"convergedSamplesPerPixel": int(s.preview_samples if viewport else s.samples)}
    out["maxDepth"] = int(s.max_depth)
    out["seed"] = int(s.seed)
    out["defaultLighting"] = 0  # Blender adds no light to a scene without lights
    # Blender's Principled BSDF is Cycles' Principled v1, whose Fresnel is not Schlick's: 13 of the
    # parity bench's 19 scenes read 0.1-1.2 % darker with Schlick (docs/hosts.md).
    out["specularFresnel"] = "dielectric" if s.fresnel == "DIELECTRIC" else "schlick"
    # Film > Transparent: camera rays do not see the world (Cycles: background RGBA = 0).
    out["domeLightCameraVisibility"] = 0 if scene.render.film_transparent else 1
    return out


def _apply_settings(delegate, settings, report=None):
    known = {d["key"] for d in delegate.settings()}
    for k, v in settings.items():
        if k in known:
            delegate.set_setting(k, v)
        elif report:
            report(f"principled: render setting '{k}' not offered by the delegate; ignored")


def border_rect(render, w, h):
    """Blender's render border (Output > Format > Render Region) as pixel bounds (x0, y0, x1, y1),
    rows counted from the bottom, as Blender computes them (the float product truncated: its
    render result has exactly that size); None when it is off or covers the whole image."""
    if not render.use_border:
        return None
    import numpy as np

    def px(v, n):
        return min(max(int(np.float32(v) * np.float32(n)), 0), n)

    x0, x1 = px(render.border_min_x, w), px(render.border_max_x, w)
    y0, y1 = px(render.border_min_y, h), px(render.border_max_y, h)
    if x1 <= x0 or y1 <= y0 or (x0, y0, x1, y1) == (0, 0, w, h):
        return None
    return x0, y0, x1, y1


def _set_rect(render_pass, pixels):
    """pixels: (w*h, channels) float32, rows bottom to top."""
    try:
        render_pass.rect.foreach_set(pixels)
    except (TypeError, RuntimeError):
        render_pass.rect = pixels.tolist()


def _get_rect(render_pass, count):
    import numpy as np

    buf = np.empty((count, render_pass.channels), np.float32)
    try:
        render_pass.rect.foreach_get(buf)
    except (TypeError, RuntimeError):
        buf[:] = np.array(render_pass.rect, np.float32)
    return buf.ravel()


class PrincipledRenderEngine(bpy.types.RenderEngine):
    bl_idname = "PRINCIPLED"
    bl_label = "principled"
    bl_use_preview = False
    bl_use_shading_nodes_custom = False
    bl_use_postprocess = True

    def __init__(self):
        self.session = None
        self.view_session = None
        self.view_key = None
        self._warned = set()

    def __del__(self):
        for s in (getattr(self, "session", None), getattr(self, "view_session", None)):
            if s is not None:
                try:
                    s.close()
                except Exception:
                    pass

    # ---- passes ------------------------------------------------------------------------
    def update_render_passes(self, scene=None, renderlayer=None):
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", "COLOR")
        for name, _aov, ch, chan_id, kind in _session.PASSES:
            self.register_pass(scene, renderlayer, name, ch, chan_id, kind)

    # ---- final render ------------------------------------------------------------------
    def render(self, depsgraph):
        try:
            self._render(depsgraph)
        except Exception as e:  # never take Blender down: report and leave
            self.report({"ERROR"}, f"principled: {e}")
            self.error_set(f"principled: {e}")

    def _render(self, depsgraph):
        scene = depsgraph.scene
        # Blender's own integer arithmetic (its render result has this size).
        pct = scene.render.resolution_percentage
        w = max(1, scene.render.resolution_x * pct // 100)
        h = max(1, scene.render.resolution_y * pct // 100)
        t0 = time.perf_counter()
        s = _session.Session()
        try:
            _apply_settings(s.delegate, _settings(scene, False),
                            lambda m: self.report({"WARNING"}, m))
            s.bind(s.required_aovs([p[0] for p in _session.PASSES]))
            self.update_stats("principled", "Exporting scene")
            bake_res = scene.principled.bake_resolution if scene.principled.bake_procedural \
                else None
            if bake_res:
                self.update_stats("principled", "Baking procedural textures")
            warnings = s.full_sync(depsgraph, w, h, bake_resolution=bake_res)
            # A render region: only its pixels are path traced (the delegate's data window, whose
            # edges fall on pixel edges here, so it takes exactly Blender's rectangle); Blender
            # takes a result of the region's size and places it (or crops to it).
            rect = border_rect(scene.render, w, h)
            if rect:
                x0, y0, x1, y1 = rect
                try:
                    s.delegate.set_framing("expandAperture", 1.0, (x0 / w, y0 / h, x1 / w, y1 / h))
                except Exception as e:  # an older renderer plugin: the full frame, cropped below
                    self.report({"WARNING"}, f"principled: render region traced in full ({e})")
            for wmsg in warnings + s.delegate.take_warnings():
                self.report({"WARNING"}, f"principled: {wmsg}")
            for msg in s.export.info:
                self.report({"INFO"}, f"principled: {msg}")
            t_sync = time.perf_counter() - t0
            limit = scene.principled.time_limit
            start = time.perf_counter()
            while True:
                if self.test_break():
                    break
                converged = s.delegate.render_pass()
                done, target = s.delegate.progress()[1:]
                self.update_progress(min(1.0, done / max(1, target)))
                self.update_stats("principled", f"Sample {done}/{target}")
                if converged:
                    break
                if limit > 0 and time.perf_counter() - start >= limit:
                    break
            self._write_result(s, w, h, rect)
            stats = s.delegate.stats()
            self.last_timing = {"sync": t_sync, "render": time.perf_counter() - start,
                                "stats": stats}
            for wmsg in s.delegate.take_warnings():
                self.report({"WARNING"}, f"principled: {wmsg}")
        finally:
            s.close()

    def _write_result(self, s, w, h, rect=None):
        x0, y0, x1, y1 = rect or (0, 0, w, h)
        rw, rh = x1 - x0, y1 - y0

        def region(pixels):  # (w*h, ch) rows bottom to top -> the region's (rw*rh, ch)
            import numpy as np

            if rect is None:
                return pixels
            ch = pixels.shape[-1]
            return np.ascontiguousarray(pixels.reshape(h, w, ch)[y0:y1, x0:x1]).reshape(rw * rh, ch)

        result = self.begin_result(0, 0, rw, rh)
        try:
            layer = result.layers[0]
            for rp in layer.passes:
                name = rp.name
                if name == "Combined":
                    _set_rect(rp, region(s.blender_pass("Combined", "color", 4)))
                    continue
                entry = next((p for p in _session.PASSES if p[0] == name), None)
                if entry is None:
                    continue
                _n, aov, ch, _cid, _k = entry
                _set_rect(rp, region(s.blender_pass(name, aov, rp.channels)))
            if _session.CAPTURE is not None:
                for rp in layer.passes:
                    _session.CAPTURE[rp.name] = _get_rect(rp, rw * rh)
        finally:
            self.end_result(result)

    # ---- viewport ----------------------------------------------------------------------
    def view_update(self, context, depsgraph):
        try:
            self._view_update(context, depsgraph)
        except Exception as e:
            self.report({"ERROR"}, f"principled: {e}")
            self.view_session = None

    def _view_camera(self, context, w, h):
        from mathutils import Matrix

        rv3d = context.region_data
        space = context.space_data
        mw = rv3d.view_matrix.inverted()
        if rv3d.view_perspective == "CAMERA" and context.scene.camera is not None:
            from . import export

            cam = context.scene.camera
            return cam.matrix_world.copy(), export.camera_params(cam.data, w, h, cam.matrix_world)
        # Free view: Blender's viewport uses a 72 mm sensor along the larger side.
        sensor = 72.0
        if w >= h:
            hap, vap = sensor, sensor * h / w
        else:
            vap, hap = sensor, sensor * w / h
        # Tenths of a metre, as export.camera_params writes lengths (only their ratio matters
        # here: no lens).
        params = {"focalLength": float(space.lens) * 0.01, "horizontalAperture": hap * 0.01,
                  "verticalAperture": vap * 0.01, "clippingRange": (space.clip_start, space.clip_end),
                  "projection": "perspective", "fStop": 0.0, "focusDistance": 1.0}  # no lens
        if rv3d.view_perspective == "ORTHO":
            params["projection"] = "orthographic"
            extent = rv3d.view_distance * sensor / space.lens
            params["horizontalAperture"] = extent * 10.0 * (1 if w >= h else w / h)
            params["verticalAperture"] = extent * 10.0 * (h / w if w >= h else 1)
        return Matrix(mw), params

    @staticmethod
    def _view_size(context):
        region = context.region
        f = context.scene.principled.viewport_scale
        return region.width, region.height, max(1, round(region.width * f)), \
            max(1, round(region.height * f))

    def _view_update(self, context, depsgraph):
        w, h, rw, rh = self._view_size(context)
        cam = self._view_camera(context, w, h)
        s = self.view_session
        if s is None:
            s = _session.Session(aovs=("color",))
            _apply_settings(s.delegate, _settings(depsgraph.scene, True))
            self.view_session = s
            s.full_sync(depsgraph, rw, rh, view_camera=cam)
            self.view_key = (rw, rh, cam[1].get("projection"))
            return
        done = s.apply_updates(depsgraph, depsgraph.updates)
        if done["rebuild"]:
            s.full_sync(depsgraph, rw, rh, view_camera=cam)
        for msg in s.delegate.take_warnings():
            if msg not in self._warned:
                self._warned.add(msg)
                self.report({"WARNING"}, f"principled: {msg}")

    def view_draw(self, context, depsgraph):
        s = self.view_session
        if s is None:
            return
        try:
            w, h, rw, rh = self._view_size(context)
            mw, params = self._view_camera(context, w, h)
            key = (rw, rh, params.get("projection"))
            if key != self.view_key:
                s.resize(rw, rh)
                if params.get("projection") != (self.view_key or (0, 0, None))[2]:
                    s.full_sync(depsgraph, rw, rh, view_camera=(mw, params))
                self.view_key = key
            if s.camera_matrix is None or mw != s.camera_matrix or \
                    params != getattr(s, "view_params", None):
                s.set_view_camera(mw, params)
                s.view_params = params
            t_pass = time.perf_counter()
            converged = s.delegate.render_pass()
            t_pass = time.perf_counter() - t_pass
            rgba = s.delegate.aov("color")
            self._draw_pixels(context, depsgraph, rgba[::-1], w, h)  # stretched to the view
            if _session.CAPTURE is not None:
                _session.CAPTURE.setdefault("view_draw", []).append({
                    "time": time.perf_counter(), "color": rgba.copy(), "converged": converged,
                    "rebuilds": s.rebuilds, "stats": s.delegate.stats(),
                    "update": dict(s.last_update),
                    "pass_seconds": t_pass, "size": (rw, rh)})
            if not converged:
                self.tag_redraw()
        except Exception as e:
            self.report({"ERROR"}, f"principled: {e}")
            self.view_session = None

    def _draw_pixels(self, context, depsgraph, rgba, w, h):
        import gpu
        import numpy as np
        from gpu_extras.presets import draw_texture_2d

        flat = np.ascontiguousarray(rgba, dtype=np.float32).ravel()
        buf = gpu.types.Buffer("FLOAT", flat.size, flat)
        tex = gpu.types.GPUTexture((rgba.shape[1], rgba.shape[0]), format="RGBA16F", data=buf)
        gpu.state.blend_set("ALPHA_PREMULT")
        self.bind_display_space_shader(depsgraph.scene)
        draw_texture_2d(tex, (0, 0), w, h)
        self.unbind_display_space_shader()
        gpu.state.blend_set("NONE")


class PRINCIPLED_OT_bake_procedural(bpy.types.Operator):
    """Bake the scene's procedural material inputs with Cycles now (main thread), into the
    session cache an interactive render (F12, which runs off the main thread and cannot bake)
    then uses"""
    bl_idname = "principled.bake_procedural"
    bl_label = "Bake Procedural Textures"
    bl_options = {"REGISTER"}

    def execute(self, context):
        import shutil
        import tempfile

        from . import bake, export

        scene = context.scene
        tmp = tempfile.mkdtemp(prefix="principled-bake-")
        try:
            ex = export.SceneExport(None, context.evaluated_depsgraph_get(), tmp, 1, 1,
                                    baker=bake.Baker(scene.principled.bake_resolution))
            ex.prepare_bakes()
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
        for msg in ex.warnings:
            self.report({"WARNING"}, f"principled: {msg}")
        for msg in ex.info or ["no procedural inputs to bake"]:
            self.report({"INFO"}, f"principled: {msg}")
        return {"FINISHED"}


class PRINCIPLED_PT_sampling(bpy.types.Panel):
    bl_label = "principled"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {"PRINCIPLED"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def draw(self, context):
        s = context.scene.principled
        col = self.layout.column()
        col.prop(s, "samples")
        col.prop(s, "preview_samples")
        col.prop(s, "max_depth")
        col.prop(s, "time_limit")
        col.prop(s, "seed")
        col.prop(s, "fresnel")
        col.prop(s, "viewport_scale")
        col.prop(s, "bake_procedural")
        sub = col.column()
        sub.active = s.bake_procedural
        sub.prop(s, "bake_resolution")
        sub.operator(PRINCIPLED_OT_bake_procedural.bl_idname, icon="RENDER_STILL")


def _compat_panels():
    # Let the usual material/light/world/camera panels show for this engine.
    names = ("DATA_PT_lens", "DATA_PT_camera", "DATA_PT_camera_dof", "DATA_PT_camera_dof_aperture",
             "DATA_PT_light", "DATA_PT_EEVEE_light",
             "EEVEE_MATERIAL_PT_surface", "EEVEE_WORLD_PT_surface", "MATERIAL_PT_preview",
             "RENDER_PT_format", "RENDER_PT_dimensions", "VIEWLAYER_PT_layer_passes",
             "CYCLES_LIGHT_PT_light", "CYCLES_WORLD_PT_surface", "CYCLES_MATERIAL_PT_surface")
    out = []
    for n in names:
        p = getattr(bpy.types, n, None)
        if p is not None and hasattr(p, "COMPAT_ENGINES"):
            out.append(p)
    return out


def register():
    bpy.utils.register_class(PrincipledSettings)
    bpy.types.Scene.principled = bpy.props.PointerProperty(type=PrincipledSettings)
    bpy.utils.register_class(PrincipledRenderEngine)
    bpy.utils.register_class(PRINCIPLED_OT_bake_procedural)
    bpy.utils.register_class(PRINCIPLED_PT_sampling)
    for p in _compat_panels():
        p.COMPAT_ENGINES.add("PRINCIPLED")
        _ENGINE_PANELS.append(p)


def unregister():
    for p in _ENGINE_PANELS:
        p.COMPAT_ENGINES.discard("PRINCIPLED")
    _ENGINE_PANELS.clear()
    bpy.utils.unregister_class(PRINCIPLED_PT_sampling)
    bpy.utils.unregister_class(PRINCIPLED_OT_bake_procedural)
    bpy.utils.unregister_class(PrincipledRenderEngine)
    del bpy.types.Scene.principled
    bpy.utils.unregister_class(PrincipledSettings)
