// SPDX-License-Identifier: Apache-2.0
#include "plugins/renderSession.h"

#include <algorithm>

#include "delegate/hd/renderIndex.h"
#include "delegate/aovs.h"
#include "delegate/hd/tokens.h"
#include "delegate/renderBuffer.h"
#include "delegate/renderDelegate.h"
#include "delegate/renderPass.h"
#include "scene_adapter/usda/stage.h"
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
    _sceneDelegate.reset();
    _delegate.reset();
}

void RenderSession::setup() {
    if (_options.width <= 0 || _options.height <= 0 || _options.width > 32768 ||
        _options.height > 32768)
        throw UserError("resolution must be between 1x1 and 32768x32768");
    if (_options.samplesPerPixel <= 0) throw UserError("samples per pixel must be at least 1");
    if (_options.shadingModel != "disney" && _options.shadingModel != "ue4")
        throw UserError("shading model must be 'disney' or 'ue4', not '" + _options.shadingModel + "'");
    _delegate = std::make_unique<embree::EmbreeRenderDelegate>();
    _delegate->setRenderSetting(Token("convergedSamplesPerPixel"), Value(_options.samplesPerPixel));
    _delegate->setRenderSetting(Token("seed"), Value(_options.seed));
    _delegate->setRenderSetting(Token("maxDepth"), Value(std::max(0, _options.maxDepth)));
    _delegate->setRenderSetting(Token("shadingModel"), Value(Token(_options.shadingModel)));
    if (_options.sampler != "sobol" && _options.sampler != "independent")
        throw UserError("sampler must be 'sobol' or 'independent', not '" + _options.sampler + "'");
    _delegate->setRenderSetting(Token("sampler"), Value(Token(_options.sampler)));
    _index = std::make_unique<RenderIndex>(_delegate.get());
    adapter::AdapterOptions ao;
    ao.time = _options.time;
    _sceneDelegate = std::make_unique<adapter::UsdSceneDelegate>(*_stage, ao);
    _sceneDelegate->populate(_index.get());

    const auto& cams = _sceneDelegate->cameras();
    if (!_options.camera.empty()) {
        if (std::find(cams.begin(), cams.end(), Path(_options.camera)) == cams.end()) {
            std::string list;
            for (const auto& c : cams) list += (list.empty() ? "" : ", ") + c.str();
            throw UserError("camera '" + _options.camera + "' not found in the stage" +
                            (list.empty() ? " (it has no cameras)" : "; cameras: " + list));
        }
        _cameraPath = _options.camera;
    } else if (!cams.empty()) {
        _cameraPath = cams.front().str();
    } else {
        _cameraPath = _sceneDelegate
                          ->addDefaultCamera(_index.get(),
                                             double(_options.width) / double(_options.height))
                          .str();
    }
    std::vector<std::string> names{"color"};
    for (const auto& a : _options.aovs) {
        if (a == "all") {
            for (const auto& info : embree::allAovs()) names.push_back(info.name);
        } else if (!embree::findAov(a)) {
            std::string known;
            for (const auto& info : embree::allAovs()) known += std::string(known.empty() ? "" : ", ") + info.name;
            throw UserError("unknown AOV '" + a + "'; known AOVs: " + known + ", all");
        } else {
            names.push_back(a);
        }
    }
    for (const auto& name : names) {
        if (std::any_of(_buffers.begin(), _buffers.end(), [&](auto& b) { return b.first == name; }))
            continue;
        Path bufferId("/__principled/aov/" + name);
        _index->insertBprim(tokens::renderBuffer(), _sceneDelegate.get(), bufferId);
        auto* buf = static_cast<embree::EmbreeRenderBuffer*>(_index->bprim(tokens::renderBuffer(), bufferId));
        AovDescriptor d = _delegate->defaultAovDescriptor(Token(name));
        buf->allocate(_options.width, _options.height, d.format, d.multiSampled);
        _buffers.emplace_back(name, buf);
    }
    _color = _buffers.front().second;
    _index->sync();
    _pass = _delegate->createRenderPass(_index.get());
}

bool RenderSession::step() {
    _index->sync();  // no-op unless something was edited
    RenderPassState state;
    state.cameraId = Path(_cameraPath);
    state.width = _options.width;
    state.height = _options.height;
    for (const auto& [name, buf] : _buffers) state.aovBindings.push_back({Token(name), buf});
    _pass->execute(state);
    return _pass->isConverged();
}

bool RenderSession::converged() const { return _pass->isConverged(); }

int RenderSession::completedSamples() const {
    return static_cast<const embree::EmbreeRenderPass*>(_pass.get())->completedSamples();
}

int RenderSession::targetSamples() const {
    return std::max(1, _options.samplesPerPixel);
}

const float* RenderSession::color() const { return static_cast<const float*>(_color->map()); }

std::vector<RenderSession::AovImage> RenderSession::aovs() const {
    std::vector<AovImage> out;
    for (const auto& [name, buf] : _buffers)
        out.push_back({name, componentCount(buf->format()), buf->format() == Format::Int32, buf->map()});
    return out;
}

std::vector<std::string> RenderSession::takeWarnings() {
    std::vector<std::string> out;
    const auto& adapterWarnings = _sceneDelegate->warnings();
    for (; _adapterWarningsTaken < adapterWarnings.size(); ++_adapterWarningsTaken)
        out.push_back(adapterWarnings[_adapterWarningsTaken]);
    for (auto& w : _delegate->takeWarnings()) out.push_back(std::move(w));
    const auto& stageWarnings = _stage->warnings();
    for (; _stageWarningsTaken < stageWarnings.size(); ++_stageWarningsTaken)
        out.push_back(stageWarnings[_stageWarningsTaken].where.str() + ": " +
                      stageWarnings[_stageWarningsTaken].message);
    return out;
}

std::map<std::string, double> RenderSession::stats() const { return _delegate->renderStats(); }

}  // namespace principled::host
