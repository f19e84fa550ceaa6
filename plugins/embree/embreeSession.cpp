// SPDX-License-Identifier: Apache-2.0
#include "plugins/embree/embreeSession.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>

#include "delegate/hd/tokens.h"
#include "delegate/renderBuffer.h"
#include "delegate/renderDelegate.h"
#include "delegate/renderPass.h"
#include "plugins/renderSession.h"
#include "scene_adapter/stageEditor.h"
#include "scene_adapter/usda/error.h"

namespace principled::plugins {

using namespace hd;

namespace {

/// AOV names probed for prdAovCount/prdAovInfo (issue 6's list); the delegate decides which
/// it knows through defaultAovDescriptor(). Any other name may still be bound if it does.
const char* const kKnownAovs[] = {
    "color",  "alpha",      "depth",     "cameraDepth", "position",    "normal",       "Neye",
    "albedo", "diffuse",    "specular",  "sheen",       "clearcoat",   "transmission", "emission",
    "primId", "instanceId", "elementId", "materialId",  "sampleCount", "variance"};

PrdFormat toPrd(Format f) {
    switch (f) {
        case Format::Float32:
            return PRD_FORMAT_FLOAT32;
        case Format::Float32Vec2:
            return PRD_FORMAT_FLOAT32_VEC2;
        case Format::Float32Vec3:
            return PRD_FORMAT_FLOAT32_VEC3;
        case Format::Float32Vec4:
            return PRD_FORMAT_FLOAT32_VEC4;
        case Format::Int32:
            return PRD_FORMAT_INT32;
        default:
            return PRD_FORMAT_INVALID;
    }
}

PrdValueType typeOf(const Value& v) {
    if (std::holds_alternative<int>(v) || std::holds_alternative<bool>(v)) return PRD_TYPE_INT;
    if (std::holds_alternative<float>(v) || std::holds_alternative<double>(v))
        return PRD_TYPE_FLOAT;
    if (std::holds_alternative<Token>(v) || std::holds_alternative<std::string>(v))
        return PRD_TYPE_STRING;
    return PRD_TYPE_NONE;
}

std::string toText(const Value& v) {
    char buf[64];
    if (auto* i = std::get_if<int>(&v)) return std::to_string(*i);
    if (auto* b = std::get_if<bool>(&v)) return *b ? "1" : "0";
    if (auto f = getFloat(v)) {
        std::snprintf(buf, sizeof buf, "%.9g", double(*f));
        return buf;
    }
    if (auto s = getString(v)) return *s;
    return "";
}

const char* typeName(PrdValueType t) {
    switch (t) {
        case PRD_TYPE_INT:
            return "an int";
        case PRD_TYPE_FLOAT:
            return "a float";
        case PRD_TYPE_STRING:
            return "a string";
        default:
            return "untyped";
    }
}

const char* setterFor(PrdValueType t) {
    switch (t) {
        case PRD_TYPE_INT:
            return "prdSetSettingInt";
        case PRD_TYPE_FLOAT:
            return "prdSetSettingFloat";
        default:
            return "prdSetSettingString";
    }
}

}  // namespace

EmbreeSession::EmbreeSession() : _delegate(std::make_unique<embree::EmbreeRenderDelegate>()) {
    for (const char* n : kKnownAovs) {
        AovDescriptor d = _delegate->defaultAovDescriptor(Token(n));
        if (d.format != Format::Invalid)
            _aovs.push_back({keep(n), toPrd(d.format), componentCount(d.format), d.multiSampled});
    }
}

const char* EmbreeSession::keep(const std::string& s) {
    for (const auto& k : _strings)
        if (*k == s) return k->c_str();
    _strings.push_back(std::make_unique<std::string>(s));
    return _strings.back()->c_str();
}

EmbreeSession::~EmbreeSession() {
    _session.reset();  // before the delegate it renders with
}

// ---- Stage ------------------------------------------------------------------------------

template <typename F>
void EmbreeSession::open(F&& makeSession) {
    _session.reset();  // no half-built stage survives a failure
    host::SessionOptions o;
    o.width = _width;
    o.height = _height;
    o.camera = _cameraRequest;
    o.framing = _framing;
    o.renderDelegate = _delegate.get();
    try {
        std::unique_ptr<host::RenderSession> s = makeSession(o);
        for (const std::string& name : _bound) s->bindAov(name);
        _session = std::move(s);
    } catch (const usd::Error& e) {
        throw SessionError(PRD_ERROR_IO, e.what());
    } catch (const host::UserError& e) {
        throw SessionError(PRD_ERROR_NOT_FOUND, e.what());  // the requested camera
    }
}

void EmbreeSession::openFile(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec))
        throw SessionError(PRD_ERROR_IO, "cannot open '" + path + "': no such file");
    if (!std::filesystem::is_regular_file(path, ec))
        throw SessionError(PRD_ERROR_IO, "cannot open '" + path + "': not a regular file");
    open([&](const host::SessionOptions& o) { return host::RenderSession::openFile(path, o); });
}

void EmbreeSession::openString(const std::string& text, const std::string& displayName) {
    open([&](const host::SessionOptions& o) {
        return host::RenderSession::openString(text, displayName.empty() ? "<string>" : displayName,
                                               o);
    });
}

host::RenderSession& EmbreeSession::requireStage(const char* what) const {
    if (!_session)
        throw SessionError(PRD_ERROR_NO_STAGE, std::string(what) +
                                                   " needs an open stage: call prdOpenStageFile "
                                                   "or prdOpenStageString first");
    return *_session;
}

std::string EmbreeSession::cameraList() const {
    if (!_session || _session->cameras().empty()) return " (it has no cameras)";
    std::string list;
    for (const auto& c : _session->cameras()) list += (list.empty() ? "" : ", ") + c.str();
    return "; cameras: " + list;
}

// ---- Edits ------------------------------------------------------------------------------

template <typename F>
void EmbreeSession::edit(const char* what, F&& f) {
    host::RenderSession& s = requireStage(what);
    try {
        f(s.editor());
    } catch (const adapter::EditError& e) {
        switch (e.code) {
            case adapter::EditError::Code::NotFound:
                throw SessionError(PRD_ERROR_NOT_FOUND, e.what());
            case adapter::EditError::Code::Unsupported:
                throw SessionError(PRD_ERROR_UNSUPPORTED, e.what());
            case adapter::EditError::Code::BadValue:
                throw SessionError(PRD_ERROR_INVALID_ARGUMENT, e.what());
        }
    }
}

void EmbreeSession::setAttribute(const std::string& primPath, const std::string& attribute,
                                 const adapter::EditValue& v, const std::string& typeName) {
    edit("editing an attribute",
         [&](adapter::StageEditor& e) { e.setAttribute(primPath, attribute, v, typeName); });
}

void EmbreeSession::setLocalTransform(const std::string& primPath, const double matrix[16]) {
    edit("setting a transform", [&](adapter::StageEditor& e) { e.setTransform(primPath, matrix); });
}

void EmbreeSession::addPrim(const std::string& primPath, const std::string& typeName) {
    edit("adding a prim", [&](adapter::StageEditor& e) { e.addPrim(primPath, typeName); });
}

void EmbreeSession::removePrim(const std::string& primPath) {
    edit("removing a prim", [&](adapter::StageEditor& e) { e.removePrim(primPath); });
}

void EmbreeSession::bindMaterial(const std::string& primPath, const std::string& materialPath) {
    edit("binding a material",
         [&](adapter::StageEditor& e) { e.bindMaterial(primPath, materialPath); });
}

void EmbreeSession::setRelationship(const std::string& primPath, const std::string& name,
                                    const std::vector<std::string>& targets) {
    edit("setting a relationship",
         [&](adapter::StageEditor& e) { e.setRelationship(primPath, name, targets); });
}

void EmbreeSession::connect(const std::string& primPath, const std::string& attribute,
                            const std::string& source) {
    edit("connecting an attribute",
         [&](adapter::StageEditor& e) { e.connect(primPath, attribute, source); });
}

// ---- Settings ---------------------------------------------------------------------------

void EmbreeSession::setSetting(const std::string& key, const SettingInput& in) {
    auto descriptors = _delegate->renderSettingDescriptors();
    auto it = std::find_if(descriptors.begin(), descriptors.end(),
                           [&](const RenderSettingDescriptor& d) { return d.key.str() == key; });
    if (it == descriptors.end()) {
        std::string list;
        for (const auto& d : descriptors) list += (list.empty() ? "" : ", ") + d.key.str();
        throw SessionError(PRD_ERROR_NOT_FOUND,
                           "unknown render setting '" + key + "'; settings: " + list);
    }
    PrdValueType want = typeOf(it->defaultValue);
    bool ok = in.type == want || (want == PRD_TYPE_FLOAT && in.type == PRD_TYPE_INT);
    if (!ok)
        throw SessionError(PRD_ERROR_INVALID_ARGUMENT, "render setting '" + key + "' is " +
                                                           typeName(want) + "; set it with " +
                                                           setterFor(want));
    Value v;
    const Value& def = it->defaultValue;
    if (std::holds_alternative<bool>(def))
        v = Value(in.i != 0);
    else if (std::holds_alternative<int>(def))
        v = Value(int(std::clamp<long long>(in.i, INT32_MIN, INT32_MAX)));
    else if (std::holds_alternative<float>(def))
        v = Value(float(in.type == PRD_TYPE_INT ? double(in.i) : in.f));
    else if (std::holds_alternative<double>(def))
        v = Value(in.type == PRD_TYPE_INT ? double(in.i) : in.f);
    else if (std::holds_alternative<Token>(def))
        v = Value(Token(in.s));
    else
        v = Value(in.s);
    // Range checks the delegate relies on (RenderSession makes the same ones).
    auto bad = [&](const std::string& why) {
        throw SessionError(PRD_ERROR_INVALID_ARGUMENT, "render setting '" + key + "': " + why);
    };
    if (key == "convergedSamplesPerPixel" && in.i < 1) bad("must be at least 1");
    if (key == "maxDepth" && in.i < 0) bad("must be at least 0");
    if (key == "shadingModel" && in.s != "disney" && in.s != "ue4")
        bad("must be 'disney' or 'ue4', not '" + in.s + "'");
    if (in.type == PRD_TYPE_FLOAT && !std::isfinite(in.f)) bad("must be finite");
    _delegate->setRenderSetting(it->key, v);
}

int EmbreeSession::settingCount() {
    return int(_delegate->renderSettingDescriptors().size());
}

PrdSettingDescriptor EmbreeSession::settingDescriptor(int index) {
    auto descriptors = _delegate->renderSettingDescriptors();
    if (index < 0 || index >= int(descriptors.size()))
        throw SessionError(PRD_ERROR_NOT_FOUND,
                           "setting index " + std::to_string(index) + " out of range (" +
                               std::to_string(descriptors.size()) + " settings)");
    const auto& d = descriptors[index];
    PrdSettingDescriptor out{};
    out.key = keep(d.key.str());
    out.displayName = keep(d.name);
    out.help = keep(d.help);
    out.type = typeOf(d.defaultValue);
    out.defaultText = keep(toText(d.defaultValue));
    return out;
}

const char* EmbreeSession::settingText(const std::string& key) {
    bool known = false;
    Value def;
    for (const auto& d : _delegate->renderSettingDescriptors())
        if (d.key.str() == key) known = true, def = d.defaultValue;
    if (!known) throw SessionError(PRD_ERROR_NOT_FOUND, "unknown render setting '" + key + "'");
    Value v = _delegate->renderSetting(Token(key));
    _text = toText(isEmpty(v) ? def : v);
    return _text.c_str();
}

// ---- Camera, resolution, AOVs ------------------------------------------------------------

void EmbreeSession::setCamera(const std::string& primPath) {
    if (_session) {
        try {
            _session->setCamera(primPath);
        } catch (const host::UserError& e) {
            throw SessionError(PRD_ERROR_NOT_FOUND, e.what());
        }
    }
    _cameraRequest = primPath;
}

const std::string& EmbreeSession::camera() const {
    return requireStage("prdGetCamera").cameraPath();
}

void EmbreeSession::setResolution(int width, int height) {
    if (width < 1 || height < 1 || width > 32768 || height > 32768)
        throw SessionError(PRD_ERROR_INVALID_ARGUMENT, "resolution " + std::to_string(width) + "x" +
                                                           std::to_string(height) +
                                                           " must be between 1x1 and 32768x32768");
    _width = width;
    _height = height;
    if (_session) _session->setResolution(width, height);
}

void EmbreeSession::setFraming(const char* conformPolicy, double pixelAspectRatio, const double* dataWindowNDC) {
    if (!conformPolicy) {
        _framing.reset();
    } else {
        hd::Framing f;
        const auto policy = hd::Framing::conformFromToken(conformPolicy);
        if (!policy)
            throw SessionError(PRD_ERROR_INVALID_ARGUMENT, std::string("conform policy '") + conformPolicy +
                                                               "' is not " + hd::Framing::kConformTokens);
        f.conform = *policy;
        if (!hd::Framing::validPixelAspectRatio(pixelAspectRatio))
            throw SessionError(PRD_ERROR_INVALID_ARGUMENT, "pixel aspect ratio " + std::to_string(pixelAspectRatio) +
                                                               " must be a number from 1e-4 to 1e4");
        f.pixelAspectRatio = float(pixelAspectRatio);
        if (dataWindowNDC) {
            const double* w = dataWindowNDC;
            const bool inside = std::all_of(w, w + 4, [](double x) { return x >= 0.0 && x <= 1.0; });
            if (!inside || !(float(w[0]) < float(w[2])) || !(float(w[1]) < float(w[3])))
                throw SessionError(PRD_ERROR_INVALID_ARGUMENT,
                                   "data window (" + std::to_string(w[0]) + ", " + std::to_string(w[1]) + ", " +
                                       std::to_string(w[2]) + ", " + std::to_string(w[3]) +
                                       ") must lie in the unit square with xmin < xmax and ymin < ymax");
            f.dataWindowNDC = glm::vec4(float(w[0]), float(w[1]), float(w[2]), float(w[3]));
        }
        _framing = f;
    }
    if (_session) _session->setFraming(_framing);
}

bool EmbreeSession::reloadTextures(bool onlyChanged) {
    return requireStage("prdReloadTextures").reloadTextures(onlyChanged);
}

PrdAovInfo EmbreeSession::describeAov(const std::string& name) {
    for (const Aov& a : _aovs)
        if (a.name == name) return {a.name, a.format, a.channels, a.multiSampled};
    AovDescriptor d = _delegate->defaultAovDescriptor(Token(name));
    if (d.format == Format::Invalid) {
        std::string list;
        for (const char* n : kKnownAovs)
            if (_delegate->defaultAovDescriptor(Token(n)).format != Format::Invalid)
                list += (list.empty() ? "" : ", ") + std::string(n);
        throw SessionError(PRD_ERROR_NOT_FOUND,
                           "unknown AOV '" + name + "'; this renderer has: " + list);
    }
    _aovs.push_back({keep(name), toPrd(d.format), componentCount(d.format), d.multiSampled});
    const Aov& a = _aovs.back();
    return {a.name, a.format, a.channels, a.multiSampled};
}

PrdAovInfo EmbreeSession::aovInfo(int index) const {
    if (index < 0 || index >= int(_aovs.size()))
        throw SessionError(PRD_ERROR_NOT_FOUND, "AOV index " + std::to_string(index) +
                                                    " out of range (" +
                                                    std::to_string(_aovs.size()) + " AOVs)");
    const Aov& a = _aovs[index];
    return {a.name, a.format, a.channels, a.multiSampled};
}

void EmbreeSession::bindAov(const std::string& name) {
    describeAov(name);  // throws for unknown names
    if (std::find(_bound.begin(), _bound.end(), name) != _bound.end()) return;
    _bound.push_back(name);
    if (_session) _session->bindAov(name);
}

void EmbreeSession::unbindAov(const std::string& name) {
    auto it = std::find(_bound.begin(), _bound.end(), name);
    if (it == _bound.end())
        throw SessionError(PRD_ERROR_NOT_BOUND, "AOV '" + name + "' is not bound");
    _bound.erase(it);
    if (_session) _session->unbindAov(name);
}

// ---- Rendering ---------------------------------------------------------------------------

bool EmbreeSession::renderPass() {
    return requireStage("prdRenderPass").step();
}

void EmbreeSession::progress(int* converged, int* completed, int* target) const {
    if (converged) *converged = _session && _session->converged() ? 1 : 0;
    if (completed) *completed = _session ? _session->completedSamples() : 0;
    if (target) *target = std::max(1, _delegate->samplesPerPixel());
}

PrdBufferView EmbreeSession::mapAov(const std::string& name) {
    if (std::find(_bound.begin(), _bound.end(), name) == _bound.end()) {
        describeAov(name);  // an unknown name says so rather than "not bound"
        throw SessionError(PRD_ERROR_NOT_BOUND,
                           "AOV '" + name + "' is not bound: call prdBindAov first");
    }
    host::RenderSession& s = requireStage("prdMapAov");
    embree::EmbreeRenderBuffer* b = s.buffer(name);
    if (!b) throw SessionError(PRD_ERROR_INTERNAL, "AOV '" + name + "' has no render buffer");
    PrdBufferView view{};
    view.data = b->map();
    view.width = b->width();
    view.height = b->height();
    view.channels = componentCount(b->format());
    view.format = toPrd(b->format());
    view.converged = s.converged() ? 1 : 0;
    return view;
}

const std::vector<std::pair<std::string, double>>& EmbreeSession::snapshotStats() {
    _stats.clear();
    for (const auto& [k, v] : _delegate->renderStats()) _stats.emplace_back(k, v);
    return _stats;
}

const char* EmbreeSession::takeWarnings() {
    _text.clear();
    std::vector<std::string> lines;
    if (_session)
        lines = _session->takeWarnings();
    else
        lines = _delegate->takeWarnings();
    for (const auto& line : lines) _text += line + "\n";
    return _text.c_str();
}

}  // namespace principled::plugins
