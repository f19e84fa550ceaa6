// SPDX-License-Identifier: Apache-2.0
#include "plugins/renderSession.h"

#include <regex>

#include <algorithm>
#include <set>
#include <cerrno>
#include <limits>
#include <utility>

#include "delegate/hd/renderIndex.h"
#include "scene_adapter/renderSettings.h"
#include "delegate/aovs.h"
#include "delegate/hd/camera.h"

#include <cmath>
#include "delegate/hd/tokens.h"
#include "delegate/renderBuffer.h"
#include "delegate/renderDelegate.h"
#include "delegate/renderPass.h"
#include "scene_adapter/usda/stage.h"
#include "scene_adapter/stageEditor.h"
#include "scene_adapter/usdSceneDelegate.h"

namespace principled::host {

using namespace hd;

std::unique_ptr<RenderSession> RenderSession::openFile(const std::string& path,
                                                       const SessionOptions& options) {
    std::unique_ptr<RenderSession> s(new RenderSession(usd::Stage::open(path), options));
    s->setup();
    return s;
}

std::unique_ptr<RenderSession> RenderSession::openString(const std::string& text,
                                                         const std::string& displayName,
                                                         const SessionOptions& options) {
    std::unique_ptr<RenderSession> s(
        new RenderSession(usd::Stage::openString(text, displayName), options));
    s->setup();
    return s;
}

RenderSession::RenderSession(std::unique_ptr<usd::Stage> stage, const SessionOptions& options)
    : _options(options), _stage(std::move(stage)) {}

RenderSession::~RenderSession() {
    _pass.reset();
    if (_index) _index->clear();
    _index.reset();
    _editor.reset();
    _sceneDelegate.reset();
    _ownedDelegate.reset();
}

void RenderSession::applySettings() {
    if (_options.samplesPerPixel <= 0) throw UserError("samples per pixel must be at least 1");
    if (_options.shadingModel != "disney" && _options.shadingModel != "ue4")
        throw UserError("shading model must be 'disney' or 'ue4', not '" + _options.shadingModel + "'");
    _delegate->setRenderSetting(Token("convergedSamplesPerPixel"), Value(_options.samplesPerPixel));
    _delegate->setRenderSetting(Token("seed"), Value(_options.seed));
    _delegate->setRenderSetting(Token("maxDepth"), Value(std::max(0, _options.maxDepth)));
    _delegate->setRenderSetting(Token("shadingModel"), Value(Token(_options.shadingModel)));
    if (_options.sampler != "sobol" && _options.sampler != "independent")
        throw UserError("sampler must be 'sobol' or 'independent', not '" + _options.sampler + "'");
    _delegate->setRenderSetting(Token("sampler"), Value(Token(_options.sampler)));
    _delegate->setRenderSetting(Token("refineLevel"), Value(std::clamp(_options.refineLevel, -1, 8)));
    _delegate->setRenderSetting(Token("noiseThreshold"), Value(std::max(0.0f, _options.noiseThreshold)));
    for (const auto& [key, text] : _options.settings) {
        auto descriptors = _delegate->renderSettingDescriptors();
        auto d = std::find_if(descriptors.begin(), descriptors.end(),
                              [&](const auto& x) { return x.key.str() == key; });
        if (d == descriptors.end()) {
            std::string known;
            for (const auto& x : descriptors) known += (known.empty() ? "" : ", ") + x.key.str();
            throw UserError("unknown render setting '" + key + "'; settings: " + known);
        }
        Value v;
        char* end = nullptr;
        errno = 0;
        long i = std::strtol(text.c_str(), &end, 10);
        if (!text.empty() && *end == '\0') {
            // An integer past int's range stays a number (a float): a budget of 3e9 must not wrap.
            const bool fits = errno != ERANGE && i >= std::numeric_limits<int>::min() && i <= std::numeric_limits<int>::max();
            if (!fits && std::holds_alternative<int>(d->defaultValue))
                throw UserError("render setting '" + key + "' expects an integer within +-" +
                                std::to_string(std::numeric_limits<int>::max()) + ", not '" + text + "'");
            v = fits ? Value(int(i)) : Value(std::strtof(text.c_str(), nullptr));
        } else {
            float f = std::strtof(text.c_str(), &end);
            v = (!text.empty() && *end == '\0') ? Value(f) : Value(Token(text));
        }
        // Keep the descriptor's type: a float setting given as "1" is still a float.
        if (std::holds_alternative<float>(d->defaultValue) && std::holds_alternative<int>(v))
            v = Value(float(std::get<int>(v)));
        if (std::holds_alternative<Token>(d->defaultValue) != std::holds_alternative<Token>(v))
            throw UserError("render setting '" + key + "' expects " +
                            (std::holds_alternative<Token>(d->defaultValue) ? "a word" : "a number") +
                            ", not '" + text + "'");
        if (std::holds_alternative<int>(d->defaultValue) && !std::holds_alternative<int>(v))
            throw UserError("render setting '" + key + "' expects an integer, not '" + text + "'");
        // Words among their choices, numbers within their range (the descriptor table).
        if (std::string problem = hd::renderSettingProblem(*d, v); !problem.empty())
            throw UserError("render setting '" + key + "' " + problem +
                            (std::holds_alternative<Token>(v) ? "" : ", not '" + text + "'"));
        _delegate->setRenderSetting(Token(key), v);
    }
}

void RenderSession::setup() {
    // UsdRender: what the caller leaves open (no size, no camera) comes from the stage's
    // RenderSettings, else 640x360 and the first camera.
    const adapter::StageRenderSettings stageSettings = adapter::readRenderSettings(*_stage);
    for (const std::string& w : stageSettings.warnings) _notes.push_back(w);
    _stageFraming = stageSettings.framing;
    _framing = _options.framing.value_or(_stageFraming);
    if (_options.width == 0 && _options.height == 0) {
        _options.width = stageSettings.width > 0 ? stageSettings.width : 640;
        _options.height = stageSettings.height > 0 ? stageSettings.height : 360;
    }
    if (_options.width <= 0 || _options.height <= 0 || _options.width > 32768 ||
        _options.height > 32768)
        throw UserError("resolution must be between 1x1 and 32768x32768");
    if (_options.renderDelegate) {
        _delegate = _options.renderDelegate;  // the host's settings stand
        // Its texture cache outlives the previous stage: files rewritten since (a host that
        // re-exports a scene writes the same paths) are read again, not served from the cache.
        _delegate->reloadTextures(true);
    } else {
        _ownedDelegate = std::make_unique<embree::EmbreeRenderDelegate>();
        _delegate = _ownedDelegate.get();
        applySettings();
    }
    _index = std::make_unique<RenderIndex>(_delegate);
    adapter::AdapterOptions ao;
    ao.time = _options.time;
    ao.includedPurposes = stageSettings.includedPurposes;
    ao.materialBindingPurposes = stageSettings.materialBindingPurposes;
    ao.disableDepthOfField = stageSettings.disableDepthOfField;
    _sceneDelegate = std::make_unique<adapter::UsdSceneDelegate>(*_stage, ao);
    _sceneDelegate->populate(_index.get());
    _editor = std::make_unique<adapter::StageEditor>(*_stage, *_sceneDelegate, *_index);
    std::string camera = _options.camera;
    if (camera.empty() && !stageSettings.camera.empty()) {
        const auto& cams = _sceneDelegate->cameras();
        if (std::find(cams.begin(), cams.end(), Path(stageSettings.camera)) != cams.end())
            camera = stageSettings.camera;
        else
            _notes.push_back(stageSettings.prim + ": camera <" + stageSettings.camera +
                             "> is not a camera of the stage; using the default camera");
    }
    chooseCamera(camera);

    std::vector<std::string> names{"color"};
    for (const auto& a : _options.aovs) {
        if (a == "all") {
            for (const auto& info : embree::allAovs()) names.push_back(info.name);
        } else if (!embree::findAov(a)) {
            std::string known;
            for (const auto& info : embree::allAovs()) known += std::string(known.empty() ? "" : ", ") + info.name;
            throw UserError("unknown AOV '" + a + "'; known AOVs: " + known + ", primvars:NAME, all");
        } else {
            names.push_back(a);
        }
    }
    // A primvar AOV no prim can fill is black: most likely a misspelt name (primvars:St).
    for (const auto& name : names) {
        if (name.rfind("primvars:", 0) != 0) continue;
        const auto prims = _stage->traverse();
        if (std::none_of(prims.begin(), prims.end(), [&](const usd::Prim* p) { return p->attribute(name) != nullptr; }))
            _notes.push_back("AOV '" + name + "': no prim has primvar '" + name.substr(9) +
                             "'; the layer is written empty (0)");
    }
    for (const auto& name : names) bindAov(name);
    _color = _buffers.front().second;
    _index->sync();
    _pass = _delegate->createRenderPass(_index.get());
    if (_options.sampleRangeEnd > _options.sampleRangeFirst)
        pass()->setSampleRange(_options.sampleRangeFirst, _options.sampleRangeEnd);
}

const std::vector<Path>& RenderSession::cameras() const { return _sceneDelegate->cameras(); }

void RenderSession::chooseCamera(const std::string& request) {
    const auto& cams = _sceneDelegate->cameras();
    if (!request.empty()) {
        if (std::find(cams.begin(), cams.end(), Path(request)) == cams.end()) {
            std::string list;
            for (const auto& c : cams) list += (list.empty() ? "" : ", ") + c.str();
            throw UserError("camera '" + request + "' not found in the stage" +
                            (list.empty() ? " (it has no cameras)" : "; cameras: " + list));
        }
        _cameraPath = request;
    } else if (!cams.empty()) {
        _cameraPath = cams.front().str();
    } else {
        _cameraPath = _sceneDelegate->addDefaultCamera(_index.get(), _options.width, _options.height, _framing).str();
    }
    updateCameraWindow();
}

void RenderSession::updateCameraWindow() {
    // Adaptive subdivision measures meshes from the render camera, through the image's window.
    Path cam(_cameraPath);
    glm::dmat4 xf = _sceneDelegate->getTransform(cam);
    auto param = [&](const char* n, float fallback) {
        return getFloat(_sceneDelegate->getCameraParamValue(cam, Token(n))).value_or(fallback);
    };
    hd::Camera probe(cam);
    probe.set(xf, param("focalLength", 5.0f), param("horizontalAperture", 2.0955f),
              param("verticalAperture", 1.52908f));
    glm::vec4 w = probe.screenWindow(_options.width, _options.height, _framing);
    const double par = (double(w.y - w.x) / _options.width) / (double(w.w - w.z) / _options.height);
    _pixelAspectRatio = std::isfinite(par) && par > 0.0 ? float(par) : 1.0f;
    float vfov = 2.0f * std::atan(0.5f * (w.w - w.z));
    _delegate->setDicingView(glm::vec3(xf[3]), vfov, _options.height);
}

void RenderSession::setCamera(const std::string& primPath) {
    chooseCamera(primPath);
    _options.camera = primPath;
}

embree::EmbreeRenderBuffer* RenderSession::allocate(const std::string& name) {
    Path bufferId("/__principled/aov/" + name);
    auto* buf = static_cast<embree::EmbreeRenderBuffer*>(_index->bprim(tokens::renderBuffer(), bufferId));
    if (!buf) {
        _index->insertBprim(tokens::renderBuffer(), _sceneDelegate.get(), bufferId);
        buf = static_cast<embree::EmbreeRenderBuffer*>(_index->bprim(tokens::renderBuffer(), bufferId));
    }
    if (!buf) throw std::runtime_error("could not create a render buffer for AOV '" + name + "'");
    AovDescriptor d = _delegate->defaultAovDescriptor(Token(name));
    buf->allocate(_options.width, _options.height, d.format, d.multiSampled);
    return buf;
}

void RenderSession::bindAov(const std::string& name) {
    if (std::any_of(_buffers.begin(), _buffers.end(), [&](auto& b) { return b.first == name; }))
        return;
    if (_delegate->defaultAovDescriptor(Token(name)).format == Format::Invalid)
        throw UserError("unknown AOV '" + name + "'");
    _buffers.emplace_back(name, allocate(name));
}

void RenderSession::unbindAov(const std::string& name) {
    if (name == "color") return;
    auto it = std::find_if(_buffers.begin(), _buffers.end(), [&](auto& b) { return b.first == name; });
    if (it == _buffers.end()) return;
    _buffers.erase(it);
    _index->removeBprim(Path("/__principled/aov/" + name));
}

void RenderSession::setResolution(int width, int height) {
    if (width <= 0 || height <= 0 || width > 32768 || height > 32768)
        throw UserError("resolution must be between 1x1 and 32768x32768");
    _options.width = width;
    _options.height = height;
    for (auto& [name, buf] : _buffers) buf = allocate(name);
    updateCameraWindow();
    _color = _buffers.front().second;
}

bool RenderSession::reloadTextures(bool onlyChanged) {
    const embree::EmbreeRenderDelegate::TextureReload r = _delegate->reloadTextures(onlyChanged);
    if (!r.any) return false;
    hd::ChangeTracker& tracker = _index->changeTracker();
    const hd::DirtyBits bits = hd::SprimDirty::Params | hd::SprimDirty::MaterialParams | hd::SprimDirty::Resource;
    const std::set<std::string> changed(r.paths.begin(), r.paths.end());
    for (const Token& type : _delegate->supportedSprimTypes()) {
        if (type == tokens::camera()) continue;
        const bool material = type == tokens::material();
        for (const Path& id : _index->sprimIds(type)) {
            // Materials compile cheaply (their textures stay cached but the changed ones); a
            // light re-reads its image at sync, so only lights whose image changed do.
            if (!material && !r.all) {
                const auto file = getString(_sceneDelegate->getLightParamValue(id, Token("texture:file")));
                if (!file || !changed.count(*file)) continue;
            }
            tracker.markSprimDirty(id, bits);
        }
    }
    return true;
}

void RenderSession::setFraming(const std::optional<hd::Framing>& framing) {
    _options.framing = framing;
    _framing = framing.value_or(_stageFraming);
    updateCameraWindow();
}

bool RenderSession::step() {
    _index->sync();  // no-op unless something was edited
    RenderPassState state;
    state.cameraId = Path(_cameraPath);
    state.width = _options.width;
    state.height = _options.height;
    state.framing = _framing;
    for (const auto& [name, buf] : _buffers) state.aovBindings.push_back({Token(name), buf});
    _pass->execute(state);
    return _pass->isConverged();
}

bool RenderSession::converged() const { return _pass->isConverged(); }

int RenderSession::completedSamples() const {
    return static_cast<const embree::EmbreeRenderPass*>(_pass.get())->completedSamples();
}

int RenderSession::targetSamples() const { return pass()->targetSamples(); }

embree::EmbreeRenderPass* RenderSession::pass() const {
    return static_cast<embree::EmbreeRenderPass*>(_pass.get());
}

embree::EmbreeRenderBuffer* RenderSession::buffer(const std::string& aov) const {
    for (const auto& [name, buf] : _buffers)
        if (name == aov) return buf;
    return nullptr;
}

const float* RenderSession::color() const { return static_cast<const float*>(_color->map()); }

std::vector<RenderSession::AovImage> RenderSession::aovs() const {
    std::vector<AovImage> out;
    for (const auto& [name, buf] : _buffers)
        out.push_back({name, componentCount(buf->format()), buf->format() == Format::Int32, buf->map()});
    return out;
}

std::vector<std::string> RenderSession::takeWarnings() {
    std::vector<std::string> out = std::exchange(_notes, {});
    const auto& adapterWarnings = _sceneDelegate->warnings();
    for (; _adapterWarningsTaken < adapterWarnings.size(); ++_adapterWarningsTaken)
        out.push_back(adapterWarnings[_adapterWarningsTaken]);
    // The delegate names prims by path ("/World/Lamp: ..."); the stage knows where each was
    // authored, so the warning also says file:line:col.
    for (auto& w : _delegate->takeWarnings()) {
        const size_t colon = w.find(": ");
        // (Messages that already say where, "file:line:col: ...", after the path keep theirs.)
        static const std::regex kLocated(R"(^[^ ]+:[0-9]+:[0-9]+: )");
        const bool located = colon != std::string::npos && std::regex_search(w.substr(colon + 2), kLocated);
        const usd::Prim* p = (colon != std::string::npos && !located && !w.empty() && w[0] == '/')
                                 ? _stage->prim(w.substr(0, colon))
                                 : nullptr;
        const std::string where = p ? p->location().str() : std::string();
        out.push_back(where.empty() ? std::move(w) : where + ": " + w);
    }
    // One line each: a message quoted from a library (an image reader's) may hold newlines.
    for (std::string& w : out) {
        while (!w.empty() && (w.back() == '\n' || w.back() == '\r')) w.pop_back();
        std::replace(w.begin(), w.end(), '\n', ' ');
        std::replace(w.begin(), w.end(), '\r', ' ');
    }
    const auto& stageWarnings = _stage->warnings();
    for (; _stageWarningsTaken < stageWarnings.size(); ++_stageWarningsTaken)
        out.push_back(stageWarnings[_stageWarningsTaken].where.str() + ": " +
                      stageWarnings[_stageWarningsTaken].message);
    return out;
}

std::map<std::string, double> RenderSession::stats() const {
    auto s = _delegate->renderStats();
    s["activePixels"] = double(pass()->activePixels());
    s["converged"] = pass()->isConverged() ? 1.0 : 0.0;
    return s;
}

}  // namespace principled::host
