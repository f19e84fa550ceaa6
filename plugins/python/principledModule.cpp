// SPDX-License-Identifier: Apache-2.0
// principled: a pybind11 module over the C ABI (principled_c.h). It exercises exactly the
// boundary a DCC uses: the registry finds the Embree plugin next to libprincipled_c.so, every
// call goes through prd*, failures become principled.Error with prdLastError's message.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <cstring>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "plugins/abi/principled_c.h"

namespace py = pybind11;

namespace {

py::object gErrorType;  // principled.Error

[[noreturn]] void raise(PrdStatus s, const std::string& message) {
    py::object err = gErrorType(message.empty() ? std::string(prdStatusName(s)) : message);
    err.attr("status") = py::str(prdStatusName(s));
    PyErr_SetObject(gErrorType.ptr(), err.ptr());
    throw py::error_already_set();
}

void check(PrdStatus s, const PrdDelegate* d) {
    if (s != PRD_OK) raise(s, prdLastError(d));
}
void checkNull(PrdStatus s) {
    if (s != PRD_OK) raise(s, prdLastError(nullptr));
}

/// Any Python number, sequence of numbers or numpy array -> flat doubles.
std::vector<double> numbers(const py::handle& v) {
    if (py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v) ||
        py::isinstance<py::bool_>(v))
        return {v.cast<double>()};
    auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(v);
    if (!a) throw py::type_error("expected a number, a sequence of numbers or a numpy array");
    return std::vector<double>(a.data(), a.data() + a.size());
}

std::vector<double> matrix16(const py::handle& m) {
    std::vector<double> v = numbers(m);
    if (v.size() != 16) throw py::value_error("a transform needs 16 numbers (4x4, USD row-vector order, translation in 12..14)");
    return v;
}

/// Keeps the delegate alive while a zero-copy numpy view of one of its buffers exists.
struct Delegate {
    PrdDelegate* d = nullptr;
    uint64_t generation = 0;  ///< bumped by every call that invalidates mapped buffers
    int width = 640, height = 360;

    explicit Delegate(const std::optional<std::string>& renderer) {
        checkNull(prdCreateDelegate(renderer ? renderer->c_str() : nullptr, &d));
    }
    ~Delegate() { close(); }
    void close() {
        if (d) prdDestroyDelegate(d);
        d = nullptr;
        ++generation;
    }
    PrdDelegate* h() const {
        if (!d) raise(PRD_ERROR_NULL_HANDLE, "the delegate is closed");
        return d;
    }
};

struct SceneBuilder {
    PrdSceneBuilder* b = nullptr;
    SceneBuilder() { checkNull(prdSceneBuilderCreate(&b)); }
    ~SceneBuilder() { prdSceneBuilderDestroy(b); }
};

py::dict aovInfo(const PrdAovInfo& i) {
    static const char* formats[] = {"invalid", "float32", "float32x2", "float32x3", "float32x4",
                                    "int32"};
    py::dict out;
    out["name"] = i.name;
    out["format"] = formats[(i.format >= 0 && i.format <= 5) ? i.format : 0];
    out["channels"] = i.channels;
    out["multi_sampled"] = bool(i.multiSampled);
    return out;
}

/// The numpy array of a mapped view; `owner` (the Delegate) keeps the memory's owner alive.
py::array viewToArray(const PrdBufferView& v, py::object owner, bool copy) {
    std::vector<py::ssize_t> shape{v.height, v.width, v.channels};
    py::array a;
    if (v.format == PRD_FORMAT_INT32) {
        std::vector<py::ssize_t> strides{py::ssize_t(v.width) * v.channels * 4,
                                         py::ssize_t(v.channels) * 4, 4};
        a = copy ? py::array_t<int32_t>(shape, strides, static_cast<const int32_t*>(v.data))
                 : py::array_t<int32_t>(shape, strides, static_cast<const int32_t*>(v.data), owner);
    } else {
        std::vector<py::ssize_t> strides{py::ssize_t(v.width) * v.channels * 4,
                                         py::ssize_t(v.channels) * 4, 4};
        a = copy ? py::array_t<float>(shape, strides, static_cast<const float*>(v.data))
                 : py::array_t<float>(shape, strides, static_cast<const float*>(v.data), owner);
    }
    if (!copy) {
        // A view of library memory: never writable from Python.
        py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    }
    return a;
}

}  // namespace

PYBIND11_MODULE(principled, m) {
    m.doc() = R"doc(principled: drive the principled render delegate from Python.

The module wraps the C ABI (principled_c.h) a DCC uses: the plugin registry finds the Embree
render delegate (PRINCIPLED_PLUGIN_PATH, then <dir of libprincipled_c.so>/principled/plugins),
a Delegate opens a stage (a .usda file, USDA text, or a SceneBuilder filled with host data),
renders progressive passes and hands out AOVs as numpy arrays.

    import principled
    d = principled.Delegate()                      # highest-priority renderer (Embree)
    d.resolution = (320, 180)
    d.set_setting("convergedSamplesPerPixel", 16)
    d.bind_aov("color"); d.bind_aov("cameraDepth")
    d.open_file("scenes/default.usda")
    d.render()                                     # passes until converged
    rgba = d.aov("color", copy=True)               # (H, W, 4) float32, top row first
    d.set_attribute("/World/Mat/Surface", "inputs:diffuseColor", (1, 0, 0))
    d.render_pass()                                # restarts; no BVH build
    print(d.stats()["blasBuilds"])

Every failing call raises principled.Error (a RuntimeError) whose message is the library's
("prdOpenStageFile: ...") and whose .status is the PrdStatus name.
Coordinates: matrices are 16 numbers in USD row-vector order (translation in 12..14); a
numpy (4, 4) array in that layout is the transpose of a column-vector matrix such as Blender's
matrix_world.)doc";

    gErrorType = py::reinterpret_borrow<py::object>(
        PyErr_NewExceptionWithDoc("principled.Error",
                                  "A principled C ABI call failed; .status is the PrdStatus name.",
                                  PyExc_RuntimeError, nullptr));
    m.attr("Error") = gErrorType;
    m.attr("ABI_VERSION") = PRD_ABI_VERSION;

    m.def("abi_version", &prdAbiVersion, "PRD_ABI_VERSION of the loaded libprincipled_c.");
    m.def(
        "renderers",
        [] {
            py::list out;
            int n = prdRendererCount();
            for (int i = 0; i < n; ++i) {
                PrdRendererInfo info{};
                checkNull(prdRendererInfo(i, &info));
                py::dict r;
                r["type_name"] = info.typeName;
                r["display_name"] = info.displayName;
                r["plugin_name"] = info.pluginName;
                r["library_path"] = info.libraryPath;
                r["priority"] = info.priority;
                r["loaded"] = bool(info.loaded);
                out.append(r);
            }
            return out;
        },
        "Renderers the plugin registry found, highest priority first (list of dicts).");
    m.def("registry_diagnostics", &prdRegistryDiagnostics,
          "Problems the registry found in plugInfo.json files, one per line ('' if none).");

    // ---- SceneBuilder -------------------------------------------------------------------
    py::class_<SceneBuilder>(m, "SceneBuilder", R"doc(A scene from host data (no files).

Paths are absolute ("/World/Mesh"); missing ancestors become Xforms. Delegate.open_builder()
opens it like any stage (to_usda() shows the text), so edits, AOVs and warnings behave as for
a .usda file.)doc")
        .def(py::init<>())
        .def(
            "set_stage_metadata",
            [](SceneBuilder& s, const std::string& upAxis, double metersPerUnit) {
                checkNull(prdSceneSetStageMetadata(s.b, upAxis.c_str(), metersPerUnit));
            },
            py::arg("up_axis") = "Y", py::arg("meters_per_unit") = 0.01,
            "Stage upAxis ('Y' or 'Z') and metersPerUnit.")
        .def(
            "add_prim",
            [](SceneBuilder& s, const std::string& path, const std::string& type) {
                checkNull(prdSceneAddPrim(s.b, path.c_str(), type.c_str()));
            },
            py::arg("path"), py::arg("type_name"),
            "Defines a prim of a USD type: Xform, Camera, DistantLight, DomeLight, Sphere, ...")
        .def(
            "add_mesh",
            [](SceneBuilder& s, const std::string& path, py::handle points, py::handle counts,
               py::handle indices, py::handle normals, py::handle st,
               const std::string& normalsInterp, const std::string& stInterp, bool doubleSided) {
                auto p = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(points);
                auto c = py::array_t<int, py::array::c_style | py::array::forcecast>::ensure(counts);
                auto ix = py::array_t<int, py::array::c_style | py::array::forcecast>::ensure(indices);
                if (!p || !c || !ix) throw py::type_error("points, counts and indices must be array-like");
                if (p.size() % 3) throw py::value_error("points must hold 3 numbers per point");
                checkNull(prdSceneAddMesh(s.b, path.c_str(), p.data(), size_t(p.size() / 3),
                                          c.data(), size_t(c.size()), ix.data(), size_t(ix.size())));
                if (!normals.is_none()) {
                    auto n = numbers(normals);
                    checkNull(prdSceneSetAttribute(s.b, path.c_str(), "normal3f[]", "normals",
                                                   n.data(), n.size(), normalsInterp.c_str()));
                }
                if (!st.is_none()) {
                    auto t = numbers(st);
                    checkNull(prdSceneSetAttribute(s.b, path.c_str(), "texCoord2f[]", "primvars:st",
                                                   t.data(), t.size(), stInterp.c_str()));
                }
                if (doubleSided) {
                    double one = 1;
                    checkNull(prdSceneSetAttribute(s.b, path.c_str(), "bool", "doubleSided", &one, 1,
                                                   nullptr));
                }
            },
            py::arg("path"), py::arg("points"), py::arg("face_vertex_counts"),
            py::arg("face_vertex_indices"), py::arg("normals") = py::none(),
            py::arg("st") = py::none(), py::arg("normals_interpolation") = "faceVarying",
            py::arg("st_interpolation") = "faceVarying", py::arg("double_sided") = false,
            R"doc(A polygon mesh (subdivision off). points: N*3 floats; counts/indices: ints;
normals (normal3f[]) and st (primvars:st, texCoord2f[]) are optional flat or (K, 3)/(K, 2)
arrays with the given interpolation ('faceVarying': one per face-vertex, 'vertex': one per
point).)doc")
        .def(
            "set_attribute",
            [](SceneBuilder& s, const std::string& path, const std::string& type,
               const std::string& name, py::handle values, std::optional<std::string> interp) {
                auto v = numbers(values);
                checkNull(prdSceneSetAttribute(s.b, path.c_str(), type.c_str(), name.c_str(),
                                               v.data(), v.size(), interp ? interp->c_str() : nullptr));
            },
            py::arg("path"), py::arg("type_name"), py::arg("name"), py::arg("values"),
            py::arg("interpolation") = py::none(),
            "Authors a numeric attribute of USD type type_name ('float', 'color3f', 'float3[]', ...).")
        .def(
            "set_attribute_string",
            [](SceneBuilder& s, const std::string& path, const std::string& type,
               const std::string& name, const std::string& value) {
                checkNull(prdSceneSetAttributeString(s.b, path.c_str(), type.c_str(), name.c_str(),
                                                     value.c_str()));
            },
            py::arg("path"), py::arg("type_name"), py::arg("name"), py::arg("value"),
            "Authors a 'token', 'string' or 'asset' attribute.")
        .def(
            "set_transform",
            [](SceneBuilder& s, const std::string& path, py::handle m16) {
                auto v = matrix16(m16);
                checkNull(prdSceneSetTransform(s.b, path.c_str(), v.data()));
            },
            py::arg("path"), py::arg("matrix"),
            "The prim's local transform: 16 numbers, USD row-vector order (translation in 12..14).")
        .def(
            "add_material",
            [](SceneBuilder& s, const std::string& path, py::kwargs inputs) {
                checkNull(prdSceneAddMaterial(s.b, path.c_str()));
                for (auto [k, v] : inputs) {
                    auto vals = numbers(v);
                    std::string key = py::str(k);
                    checkNull(prdSceneSetMaterialInput(s.b, path.c_str(), key.c_str(), vals.data(),
                                                       vals.size()));
                }
            },
            py::arg("path"),
            R"doc(A UsdPreviewSurface material (shader at path/Surface); keyword arguments are
surface inputs: diffuseColor=(r, g, b), metallic=, roughness=, ior=, emissiveColor=,
clearcoat=, clearcoatRoughness=, opacity=, and the Disney extras specular=, specularTint=,
anisotropic=, sheen=, sheenTint=, clearcoatGloss=, specTrans=, subsurface=.)doc")
        .def(
            "set_material_input",
            [](SceneBuilder& s, const std::string& path, const std::string& input, py::handle v) {
                auto vals = numbers(v);
                checkNull(prdSceneSetMaterialInput(s.b, path.c_str(), input.c_str(), vals.data(),
                                                   vals.size()));
            },
            py::arg("material"), py::arg("input"), py::arg("value"),
            "One surface input: 1 number -> float, 3 -> color3f (normal3f for 'normal').")
        .def(
            "set_material_texture",
            [](SceneBuilder& s, const std::string& path, const std::string& input,
               const std::string& file, const std::string& channel) {
                checkNull(prdSceneSetMaterialTexture(s.b, path.c_str(), input.c_str(), file.c_str(),
                                                     channel.c_str()));
            },
            py::arg("material"), py::arg("input"), py::arg("file"), py::arg("channel") = "rgb",
            R"doc(Connects a surface input to an image file (UsdUVTexture at
material/<input>Texture reading primvar 'st'); channel 'rgb' or 'r'/'g'/'b'/'a'.)doc")
        .def(
            "bind_material",
            [](SceneBuilder& s, const std::string& prim, const std::string& material) {
                checkNull(prdSceneBindMaterial(s.b, prim.c_str(), material.c_str()));
            },
            py::arg("prim"), py::arg("material"), "material:binding of prim to material.")
        .def(
            "to_usda",
            [](SceneBuilder& s) {
                const char* text = nullptr;
                checkNull(prdSceneToUsda(s.b, &text));
                return std::string(text);
            },
            "The USDA text built so far.");

    // ---- Delegate -----------------------------------------------------------------------
    py::class_<Delegate>(m, "Delegate", R"doc(One render delegate: a stage, settings, AOV buffers.

Delegate(renderer=None): renderer is a type or display name ('Embree'); None picks the
highest-priority renderer. Use as a context manager or call close() to free it early.)doc")
        .def(py::init<std::optional<std::string>>(), py::arg("renderer") = py::none())
        .def("close", &Delegate::close, "Destroys the delegate; later calls raise principled.Error.")
        .def("__enter__", [](py::object self) { return self; })
        .def("__exit__", [](Delegate& d, py::args) { d.close(); })
        .def(
            "open_file",
            [](Delegate& d, const std::string& path) {
                ++d.generation;
                check(prdOpenStageFile(d.h(), path.c_str()), d.d);
            },
            py::arg("path"), "Opens a .usda file (replaces the open stage; settings, camera, AOVs persist).")
        .def(
            "open_string",
            [](Delegate& d, const std::string& text, const std::string& name) {
                ++d.generation;
                check(prdOpenStageString(d.h(), text.c_str(), name.c_str()), d.d);
            },
            py::arg("usda"), py::arg("display_name") = "<string>", "Opens a stage from USDA text.")
        .def(
            "open_builder",
            [](Delegate& d, SceneBuilder& b) {
                ++d.generation;
                PrdStatus s = prdOpenStageFromBuilder(d.h(), b.b);
                if (s != PRD_OK) {
                    std::string msg = prdLastError(d.d);
                    raise(s, msg.empty() ? prdLastError(nullptr) : msg);
                }
            },
            py::arg("builder"), "Opens the scene a SceneBuilder holds.")
        .def(
            "set_attribute",
            [](Delegate& d, const std::string& prim, const std::string& attr, py::handle values) {
                if (py::isinstance<py::str>(values)) {
                    check(prdSetAttributeString(d.h(), prim.c_str(), attr.c_str(),
                                                values.cast<std::string>().c_str()),
                          d.d);
                    return;
                }
                auto v = numbers(values);
                check(prdSetAttributeNumbers(d.h(), prim.c_str(), attr.c_str(), v.data(), v.size()),
                      d.d);
            },
            py::arg("prim"), py::arg("attribute"), py::arg("value"),
            R"doc(Incremental edit of an authored attribute: a material input
('/World/Mat/Surface', 'inputs:diffuseColor', (1, 0, 0)) re-renders without a BVH build; a
light input updates light tables; points rebuild that mesh; a string sets a token/asset.)doc")
        .def(
            "set_transform",
            [](Delegate& d, const std::string& prim, py::handle m16) {
                auto v = matrix16(m16);
                check(prdSetLocalTransform(d.h(), prim.c_str(), v.data()), d.d);
            },
            py::arg("prim"), py::arg("matrix"),
            "Replaces a prim's local transform (16 numbers, USD order): instances move, no mesh rebuild.")
        .def(
            "set_attribute_typed",
            [](Delegate& d, const std::string& prim, const std::string& attr,
               const std::string& type, py::handle values) {
                auto v = numbers(values);
                check(prdSetAttributeTyped(d.h(), prim.c_str(), attr.c_str(), type.c_str(),
                                           v.data(), v.size()),
                      d.d);
            },
            py::arg("prim"), py::arg("attribute"), py::arg("type_name"), py::arg("value"),
            "Like set_attribute, creating the attribute with a USD type ('texCoord2f[]') if absent.")
        .def(
            "add_prim",
            [](Delegate& d, const std::string& prim, const std::string& type) {
                check(prdAddPrim(d.h(), prim.c_str(), type.c_str()), d.d);
            },
            py::arg("prim"), py::arg("type_name"),
            "Defines a prim (Mesh, Sphere, Cube, Xform, Material, Shader, Camera, lights, "
            "PointInstancer...) in the open stage; author its attributes next.")
        .def(
            "remove_prim",
            [](Delegate& d, const std::string& prim) { check(prdRemovePrim(d.h(), prim.c_str()), d.d); },
            py::arg("prim"),
            "Removes a prim and its subtree; prims bound to a removed material use the default one.")
        .def(
            "bind_material",
            [](Delegate& d, const std::string& prim, const std::string& material) {
                check(prdBindMaterial(d.h(), prim.c_str(), material.c_str()), d.d);
            },
            py::arg("prim"), py::arg("material"),
            "Binds a Material to a prim or GeomSubset ('' unbinds): only that prim is re-synced.")
        .def(
            "set_relationship",
            [](Delegate& d, const std::string& prim, const std::string& name,
               const std::vector<std::string>& targets) {
                std::vector<const char*> t;
                for (const auto& x : targets) t.push_back(x.c_str());
                check(prdSetRelationship(d.h(), prim.c_str(), name.c_str(), t.data(), t.size()), d.d);
            },
            py::arg("prim"), py::arg("name"), py::arg("targets"),
            "Sets a relationship's targets (e.g. a PointInstancer's 'prototypes').")
        .def(
            "connect",
            [](Delegate& d, const std::string& prim, const std::string& attr, const std::string& source) {
                check(prdConnectAttribute(d.h(), prim.c_str(), attr.c_str(), source.c_str()), d.d);
            },
            py::arg("prim"), py::arg("attribute"), py::arg("source"),
            "Connects a shading input/output to '/Mat/Shader.outputs:name' ('' disconnects).")
        // Settings
        .def(
            "settings",
            [](Delegate& d) {
                int n = 0;
                check(prdSettingCount(d.h(), &n), d.d);
                py::list out;
                static const char* types[] = {"none", "int", "float", "string"};
                for (int i = 0; i < n; ++i) {
                    PrdSettingDescriptor s{};
                    check(prdSettingDescriptor(d.d, i, &s), d.d);
                    py::dict e;
                    e["key"] = s.key;
                    e["display_name"] = s.displayName;
                    e["help"] = s.help;
                    e["type"] = types[(s.type >= 0 && s.type <= 3) ? s.type : 0];
                    e["default"] = s.defaultText;
                    out.append(e);
                }
                return out;
            },
            "Render settings the delegate describes (list of dicts: key, display_name, help, type, default).")
        .def(
            "set_setting",
            [](Delegate& d, const std::string& key, py::handle value) {
                if (py::isinstance<py::str>(value))
                    check(prdSetSettingString(d.h(), key.c_str(), value.cast<std::string>().c_str()), d.d);
                else if (py::isinstance<py::bool_>(value) || py::isinstance<py::int_>(value))
                    check(prdSetSettingInt(d.h(), key.c_str(), value.cast<int64_t>()), d.d);
                else
                    check(prdSetSettingFloat(d.h(), key.c_str(), value.cast<double>()), d.d);
            },
            py::arg("key"), py::arg("value"), "Sets a render setting (int, float or str by the value's type).")
        .def(
            "get_setting",
            [](Delegate& d, const std::string& key) {
                const char* text = nullptr;
                check(prdGetSetting(d.h(), key.c_str(), &text), d.d);
                return std::string(text);
            },
            py::arg("key"), "A setting's current value as text.")
        // Camera, resolution
        .def_property(
            "camera",
            [](Delegate& d) {
                const char* p = nullptr;
                check(prdGetCamera(d.h(), &p), d.d);
                return std::string(p ? p : "");
            },
            [](Delegate& d, std::optional<std::string> path) {
                check(prdSetCamera(d.h(), path ? path->c_str() : nullptr), d.d);
            },
            "The camera prim path rendered through ('' or None: the first camera or a framing one).")
        .def_property(
            "resolution", [](Delegate& d) { return std::make_pair(d.width, d.height); },
            [](Delegate& d, std::pair<int, int> wh) {
                ++d.generation;
                check(prdSetResolution(d.h(), wh.first, wh.second), d.d);
                d.width = wh.first;
                d.height = wh.second;
            },
            "(width, height) in pixels (default 640x360); setting it reallocates bound buffers.")
        .def(
            "reload_textures",
            [](Delegate& d, bool onlyChanged) {
                int reloaded = 0;
                check(prdReloadTextures(d.h(), onlyChanged ? 1 : 0, &reloaded), d.d);
                return reloaded != 0;
            },
            py::arg("only_changed") = true,
            "Reads texture files edited on disk again from the next pass: those whose modification "
            "time or size changed (only_changed), else all. Returns whether anything is re-read.")
        .def(
            "set_framing",
            [](Delegate& d, std::optional<std::string> policy, double pixelAspectRatio,
               std::optional<std::array<double, 4>> dataWindow) {
                // None is "the stage's framing": a pixel aspect or window given with it would be
                // dropped without a word.
                if (!policy && (pixelAspectRatio != 1.0 || dataWindow))
                    throw py::value_error("set_framing: conform_policy None returns to the stage's framing; "
                                          "give a policy (e.g. 'expandAperture') with a pixel aspect ratio or data window");
                check(prdSetFraming(d.h(), policy ? policy->c_str() : nullptr, pixelAspectRatio,
                                    dataWindow ? dataWindow->data() : nullptr),
                      d.d);
            },
            py::arg("conform_policy") = "expandAperture", py::arg("pixel_aspect_ratio") = 1.0,
            py::arg("data_window") = py::none(),
            "How the image frames the camera, as UsdRenderSettingsBase: conform_policy "
            "'expandAperture' | 'cropAperture' | 'adjustApertureWidth' | 'adjustApertureHeight' | "
            "'adjustPixelAspectRatio', pixel_aspect_ratio (pixel width / height), data_window "
            "(xmin, ymin, xmax, ymax) in [0, 1], (0, 0) the bottom left: only pixels whose centres "
            "lie in it are rendered. conform_policy None (with no other argument): back to the stage's "
            "own RenderSettings framing.")
        // AOVs
        .def(
            "aovs",
            [](Delegate& d) {
                int n = 0;
                check(prdAovCount(d.h(), &n), d.d);
                py::list out;
                for (int i = 0; i < n; ++i) {
                    PrdAovInfo info{};
                    check(prdAovInfo(d.d, i, &info), d.d);
                    out.append(aovInfo(info));
                }
                return out;
            },
            "AOVs the renderer can bind (list of dicts: name, format, channels, multi_sampled).")
        .def(
            "describe_aov",
            [](Delegate& d, const std::string& name) {
                PrdAovInfo info{};
                check(prdAovDescribe(d.h(), name.c_str(), &info), d.d);
                return aovInfo(info);
            },
            py::arg("name"))
        .def(
            "bind_aov",
            [](Delegate& d, const std::string& name) {
                check(prdBindAov(d.h(), name.c_str()), d.d);
            },
            py::arg("name"), "Allocates a buffer for an AOV ('color', 'cameraDepth', 'primId', ...).")
        .def(
            "unbind_aov",
            [](Delegate& d, const std::string& name) {
                ++d.generation;
                check(prdUnbindAov(d.h(), name.c_str()), d.d);
            },
            py::arg("name"))
        // Rendering
        .def(
            "render_pass",
            [](Delegate& d) {
                int converged = 0;
                PrdDelegate* h = d.h();
                PrdStatus s;
                ++d.generation;
                {
                    py::gil_scoped_release release;
                    s = prdRenderPass(h, &converged);
                }
                check(s, d.d);
                return bool(converged);
            },
            "Syncs pending edits and runs one progressive pass (GIL released); returns converged.")
        .def(
            "render",
            [](Delegate& d, std::optional<int> maxPasses, std::optional<double> timeLimit) {
                auto start = std::chrono::steady_clock::now();
                int passes = 0;
                PrdDelegate* h = d.h();
                for (;;) {
                    int converged = 0;
                    PrdStatus s;
                    ++d.generation;
                    {
                        py::gil_scoped_release release;
                        s = prdRenderPass(h, &converged);
                    }
                    check(s, d.d);
                    ++passes;
                    if (converged) break;
                    if (maxPasses && passes >= *maxPasses) break;
                    double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
                    if (timeLimit && t >= *timeLimit) break;
                    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
                }
                return passes;
            },
            py::arg("max_passes") = py::none(), py::arg("time_limit") = py::none(),
            "Runs passes until converged (or max_passes / time_limit seconds); returns the pass count.")
        .def(
            "progress",
            [](Delegate& d) {
                int c = 0, done = 0, target = 0;
                check(prdProgress(d.h(), &c, &done, &target), d.d);
                return py::make_tuple(bool(c), done, target);
            },
            "(converged, samples done, samples targeted) since the last restart.")
        .def(
            "aov",
            [](py::object self, const std::string& name, bool copy) {
                Delegate& d = self.cast<Delegate&>();
                PrdBufferView v{};
                check(prdMapAov(d.h(), name.c_str(), &v), d.d);
                return viewToArray(v, self, copy);
            },
            py::arg("name"), py::arg("copy") = false,
            R"doc(A bound AOV as a numpy array of shape (height, width, channels), top row
first; float32, or int32 for IDs (-1 = no hit).

copy=False (default) returns a read-only view of the delegate's mapped buffer without a
copy: it is valid only until the next render_pass/render/resolution change/open/unbind/close
on this delegate (it keeps the Delegate object alive, not the buffer's contents). Take
copy=True (or np.array(view)) to keep pixels across passes.)doc")
        .def(
            "stats",
            [](Delegate& d) {
                int n = 0;
                check(prdStatCount(d.h(), &n), d.d);
                py::dict out;
                for (int i = 0; i < n; ++i) {
                    const char* key = nullptr;
                    double value = 0;
                    check(prdStat(d.d, i, &key, &value), d.d);
                    out[py::str(key)] = value;
                }
                return out;
            },
            "Render statistics (rays, samples, blasBuilds, meshesRebuilt, transformUpdates, renderSeconds, ...).")
        .def(
            "take_warnings",
            [](Delegate& d) {
                const char* text = nullptr;
                check(prdTakeWarnings(d.h(), &text), d.d);
                std::string t = text ? text : "";
                py::list out;
                size_t start = 0;
                while (start < t.size()) {
                    size_t end = t.find('\n', start);
                    if (end == std::string::npos) end = t.size();
                    if (end > start) out.append(t.substr(start, end - start));
                    start = end + 1;
                }
                return out;
            },
            "Scene warnings gathered since the last call (list of str).");
}
