// SPDX-License-Identifier: Apache-2.0
#include "delegate/renderDelegate.h"

#include <algorithm>
#include <cmath>

#include "delegate/aovs.h"
#include "delegate/hd/camera.h"
#include "delegate/hd/tokens.h"
#include "delegate/light.h"
#include "delegate/material.h"
#include "delegate/mesh.h"
#include "delegate/renderBuffer.h"
#include "delegate/renderPass.h"
#include "delegate/sphere.h"

namespace principled::embree {

using namespace hd;

EmbreeRenderDelegate::EmbreeRenderDelegate() {
    _scene = rtcNewScene(_device.get());
    // Two-level BVH: a dynamic, fast-to-rebuild top level over per-prim instances.
    rtcSetSceneFlags(_scene, RTC_SCENE_FLAG_DYNAMIC | RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(_scene, RTC_BUILD_QUALITY_LOW);
    _param = std::make_unique<EmbreeRenderParam>(_device.get(), _scene);
    _param->setTextureCache(&_textures);
    for (const auto& d : renderSettingDescriptors()) _settings[d.key] = d.defaultValue;
    updateDicing();
    _snapshot.scene = _scene;
}

EmbreeRenderDelegate::~EmbreeRenderDelegate() { rtcReleaseScene(_scene); }

const std::vector<Token>& EmbreeRenderDelegate::supportedRprimTypes() const {
    static const std::vector<Token> t{tokens::mesh(), tokens::sphere()};
    return t;
}
const std::vector<Token>& EmbreeRenderDelegate::supportedSprimTypes() const {
    static const std::vector<Token> t{tokens::camera(), tokens::material(), tokens::distantLight(),
                                      tokens::domeLight()};
    return t;
}
const std::vector<Token>& EmbreeRenderDelegate::supportedBprimTypes() const {
    static const std::vector<Token> t{tokens::renderBuffer()};
    return t;
}

std::unique_ptr<Rprim> EmbreeRenderDelegate::createRprim(const Token& typeId, const Path& id) {
    if (typeId == tokens::mesh()) return std::make_unique<Mesh>(id);
    if (typeId == tokens::sphere()) return std::make_unique<Sphere>(id);
    return nullptr;
}

std::unique_ptr<Sprim> EmbreeRenderDelegate::createSprim(const Token& typeId, const Path& id) {
    if (typeId == tokens::camera()) return std::make_unique<Camera>(id);
    if (typeId == tokens::material()) return std::make_unique<Material>(id);
    if (typeId == tokens::distantLight() || typeId == tokens::domeLight())
        return std::make_unique<Light>(typeId, id);
    return nullptr;
}

std::unique_ptr<Bprim> EmbreeRenderDelegate::createBprim(const Token& typeId, const Path& id) {
    if (typeId == tokens::renderBuffer()) return std::make_unique<EmbreeRenderBuffer>(id);
    return nullptr;
}

std::unique_ptr<RenderPass> EmbreeRenderDelegate::createRenderPass(RenderIndex* index) {
    return std::make_unique<EmbreeRenderPass>(index, this);
}

void EmbreeRenderDelegate::commitResources(ChangeTracker*) {
    bool sceneDirty = _param->takeSceneDirty();
    bool tablesDirty = _param->takeTablesDirty();
    if (sceneDirty) {
        rtcCommitScene(_scene);
        ++_topCommits;
    }
    if (tablesDirty) {
        // Materials sorted by path, so indices do not depend on pointer order.
        std::vector<MaterialSource*> mats(_param->materials().begin(), _param->materials().end());
        std::sort(mats.begin(), mats.end(), [](auto* a, auto* b) { return a->materialId() < b->materialId(); });
        _snapshot.materials.clear();
        std::unordered_map<Path, int> index;
        for (MaterialSource* m : mats) {
            index[m->materialId()] = static_cast<int>(_snapshot.materials.size());
            _snapshot.materials.push_back(m->record());
        }
        for (GeometrySource* g : _param->geometry()) g->bindMaterials(index);
        std::vector<LightSource*> lights;
        for (LightSource* l : _param->lights())
            if (l->enabled()) lights.push_back(l);
        std::sort(lights.begin(), lights.end(), [](auto* a, auto* b) { return a->lightId() < b->lightId(); });
        _snapshot.lights.clear();
        for (LightSource* l : lights) _snapshot.lights.push_back(l->record());
        _snapshot.usingDefaultLight = false;
        if (_snapshot.lights.empty() && intSetting("defaultLighting", 1) != 0) {
            // A scene without lights would render black; light it like an overcast sky
            // (a white dome of radiance 1) and say so in the stats.
            LightRecord dome;
            dome.kind = LightRecord::Kind::Dome;
            dome.radiance = glm::vec3(1.0f);
            _snapshot.lights.push_back(dome);
            _snapshot.usingDefaultLight = true;
        }
    }
    if (sceneDirty || tablesDirty) {
        _snapshot.geometryByInstance.clear();
        _snapshot.instanceByInstance.clear();
        for (GeometrySource* g : _param->geometry()) {
            unsigned id = g->instanceId();
            if (id == RTC_INVALID_GEOMETRY_ID) continue;
            if (id >= _snapshot.geometryByInstance.size())
                _snapshot.geometryByInstance.resize(id + 1, nullptr);
            _snapshot.geometryByInstance[id] = g->record();
        }
        addInstancerInstances();
    }
}

void EmbreeRenderDelegate::addInstancerInstances() {
    // PointInstancer instances: their geomIDs map to the prototype's record plus a placement.
    long count = 0;
    for (GeometrySource* g : _param->geometry()) {
        const std::vector<unsigned>* ids = g->instanceGeomIds();
        if (!ids || ids->empty()) continue;
        count += long(ids->size());
        const std::vector<InstanceRecord>& recs = *g->instanceRecords();
        unsigned top = *std::max_element(ids->begin(), ids->end());
        if (top >= _snapshot.geometryByInstance.size())
            _snapshot.geometryByInstance.resize(top + 1, nullptr);
        if (_snapshot.instanceByInstance.size() < _snapshot.geometryByInstance.size())
            _snapshot.instanceByInstance.resize(_snapshot.geometryByInstance.size(), nullptr);
        for (size_t i = 0; i < ids->size(); ++i) {
            _snapshot.geometryByInstance[(*ids)[i]] = g->record();
            _snapshot.instanceByInstance[(*ids)[i]] = &recs[i];
        }
    }
    if (!_snapshot.instanceByInstance.empty())
        _snapshot.instanceByInstance.resize(_snapshot.geometryByInstance.size(), nullptr);
    _instances = count;
}

AovDescriptor EmbreeRenderDelegate::defaultAovDescriptor(const Token& aovName) const {
    auto info = findAov(aovName.str());
    if (!info) return {};
    Value clear = info->format == Format::Int32 ? Value(int(info->clear)) : Value(info->clear);
    return {info->format, info->multiSampled, clear};
}

std::vector<RenderSettingDescriptor> EmbreeRenderDelegate::renderSettingDescriptors() const {
    return {
        {"Samples per pixel", Token("convergedSamplesPerPixel"), Value(64), "samples per pixel at convergence"},
        {"Random seed", Token("seed"), Value(0), "same seed, same image; another seed, another image"},
        {"Max depth", Token("maxDepth"), Value(8), "bounces after the camera hit (0 = direct light only)"},
        {"Clamp indirect", Token("clampIndirect"), Value(0.0f), "max channel value of an indirect contribution; 0 = off"},
        {"Shading model", Token("shadingModel"), Value(Token("disney")), "disney | ue4"},
        {"Sampler", Token("sampler"), Value(Token("sobol")), "sobol (Owen-scrambled) | independent"},
        {"Default lighting", Token("defaultLighting"), Value(1), "light a scene without lights with a white dome"},
        {"Refine level", Token("refineLevel"), Value(-1), "subdivision level for every mesh; -1 = adaptive from the projected size"},
        {"Dicing rate", Token("dicingRate"), Value(1.5f), "adaptive subdivision: target refined edge length in pixels"},
        {"Max refine level", Token("maxRefineLevel"), Value(6), "adaptive subdivision: highest level"},
        {"Dome visible to camera", Token("domeLightCameraVisibility"), Value(1), "camera rays see the dome light"},
    };
}

void EmbreeRenderDelegate::setRenderSetting(const Token& key, const Value& value) {
    {
        std::lock_guard<std::mutex> lock(_settingsMutex);
        auto it = _settings.find(key);
        if (it != _settings.end() && it->second == value) return;
        _settings[key] = value;
        ++_settingsVersion;
    }
    if (key == Token("defaultLighting")) _param->markTablesDirty();
    // Subdivision settings apply to meshes (re)built afterwards.
    if (key == Token("refineLevel") || key == Token("dicingRate") || key == Token("maxRefineLevel"))
        updateDicing();
}

void EmbreeRenderDelegate::updateDicing() {
    EmbreeRenderParam::Dicing d = _param->dicing();
    d.level = intSetting("refineLevel", -1);
    d.targetEdgePixels = std::max(0.05f, floatSetting("dicingRate", 1.5f));
    d.maxLevel = std::clamp(intSetting("maxRefineLevel", 6), 0, 8);
    _param->setDicing(d);
}

void EmbreeRenderDelegate::setDicingView(const glm::vec3& cameraPosition, float verticalFov,
                                         int imageHeight) {
    EmbreeRenderParam::Dicing d = _param->dicing();
    d.haveView = std::isfinite(verticalFov) && verticalFov > 0.0f && imageHeight > 0;
    d.cameraPosition = cameraPosition;
    d.verticalFov = verticalFov;
    d.imageHeight = imageHeight;
    _param->setDicing(d);
}

Value EmbreeRenderDelegate::renderSetting(const Token& key) const {
    std::lock_guard<std::mutex> lock(_settingsMutex);
    auto it = _settings.find(key);
    return it == _settings.end() ? Value() : it->second;
}

int EmbreeRenderDelegate::intSetting(const char* key, int fallback) const {
    auto v = getFloat(renderSetting(Token(key)));
    return v ? static_cast<int>(*v) : fallback;
}

float EmbreeRenderDelegate::floatSetting(const char* key, float fallback) const {
    return getFloat(renderSetting(Token(key))).value_or(fallback);
}

int EmbreeRenderDelegate::samplesPerPixel() const { return intSetting("convergedSamplesPerPixel", 64); }
int EmbreeRenderDelegate::seed() const { return intSetting("seed", 0); }

IntegratorSettings EmbreeRenderDelegate::integratorSettings() const {
    IntegratorSettings s;
    s.maxDepth = std::max(0, intSetting("maxDepth", 8));
    s.clampIndirect = std::max(0.0f, floatSetting("clampIndirect", 0.0f));
    s.domeVisible = intSetting("domeLightCameraVisibility", 1) != 0;
    auto model = getString(renderSetting(Token("shadingModel")));
    s.bsdf.model = (model && *model == "ue4") ? bsdf::Model::UE4 : bsdf::Model::Disney;
    auto sampler = getString(renderSetting(Token("sampler")));
    s.sampler = (sampler && *sampler == "independent") ? SamplerKind::Independent : SamplerKind::Sobol;
    return s;
}

void EmbreeRenderDelegate::addPassStats(long rays, long samples, long invalidSamples,
                                        double seconds) {
    _rays += rays;
    _samples += samples;
    _invalidSamples += invalidSamples;
    double cur = _renderSeconds.load();
    while (!_renderSeconds.compare_exchange_weak(cur, cur + seconds)) {
    }
}

std::map<std::string, double> EmbreeRenderDelegate::renderStats() const {
    double secs = _renderSeconds.load();
    return {
        {"rays", double(_rays.load())},
        {"samples", double(_samples.load())},
        {"invalidSamples", double(_invalidSamples.load())},
        {"renderSeconds", secs},
        {"mraysPerSecond", secs > 0 ? double(_rays.load()) / secs * 1e-6 : 0.0},
        {"blasBuilds", double(_param->blasBuilds.load())},
        {"meshesRebuilt", double(_param->meshesRebuilt.load())},
        {"transformUpdates", double(_param->transformUpdates.load())},
        {"topLevelCommits", double(_topCommits.load())},
        {"defaultLight", _snapshot.usingDefaultLight ? 1.0 : 0.0},
        {"lights", double(_snapshot.lights.size())},
        {"materials", double(_snapshot.materials.size())},
        {"instances", double(_instances.load())},  // PointInstancer / instanceable instances
    };
}

}  // namespace principled::embree
