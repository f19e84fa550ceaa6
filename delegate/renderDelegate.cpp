// SPDX-License-Identifier: Apache-2.0
#include "delegate/renderDelegate.h"
#include "delegate/surfacePoint.h"

#include "delegate/sceneFeatures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <set>

#include <tbb/parallel_for.h>

#include "delegate/aovs.h"
#include "delegate/hd/camera.h"
#include "delegate/hd/tokens.h"
#include "delegate/light.h"
#include "delegate/material.h"
#include "delegate/mesh.h"
#include "delegate/renderBuffer.h"
#include "delegate/renderPass.h"
#include "delegate/sphere.h"
#include "delegate/points.h"
#include "delegate/curves.h"

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
    // Diagnostics and before/after benchmarks (bench/latency_bench): every commit rebuilds every
    // table, as before incremental commits.
    const char* full = std::getenv("PRINCIPLED_FULL_COMMIT");
    _fullCommit = full && *full && std::string(full) != "0";
}

EmbreeRenderDelegate::~EmbreeRenderDelegate() { rtcReleaseScene(_scene); }

const std::vector<Token>& EmbreeRenderDelegate::supportedRprimTypes() const {
    static const std::vector<Token> t{tokens::mesh(), tokens::sphere(), tokens::pointsPrim(), tokens::basisCurves()};
    return t;
}
const std::vector<Token>& EmbreeRenderDelegate::supportedSprimTypes() const {
    static const std::vector<Token> t{tokens::camera(),      tokens::material(),
                                      tokens::distantLight(), tokens::domeLight(),
                                      tokens::sphereLight(),  tokens::rectLight(),
                                      tokens::diskLight(),    tokens::cylinderLight(),
                                      tokens::portalLight()};
    return t;
}
const std::vector<Token>& EmbreeRenderDelegate::supportedBprimTypes() const {
    static const std::vector<Token> t{tokens::renderBuffer()};
    return t;
}

std::unique_ptr<Rprim> EmbreeRenderDelegate::createRprim(const Token& typeId, const Path& id) {
    if (typeId == tokens::mesh()) return std::make_unique<Mesh>(id);
    if (typeId == tokens::sphere()) return std::make_unique<Sphere>(id);
    if (typeId == tokens::pointsPrim()) return std::make_unique<Points>(id);
    if (typeId == tokens::basisCurves()) return std::make_unique<BasisCurves>(id);
    return nullptr;
}

std::unique_ptr<Sprim> EmbreeRenderDelegate::createSprim(const Token& typeId, const Path& id) {
    if (typeId == tokens::camera()) return std::make_unique<Camera>(id);
    if (typeId == tokens::material()) return std::make_unique<Material>(id);
    for (const Token& light : {tokens::distantLight(), tokens::domeLight(), tokens::sphereLight(),
                               tokens::rectLight(), tokens::diskLight(), tokens::cylinderLight(),
                               tokens::portalLight()})
        if (typeId == light) return std::make_unique<Light>(typeId, id);
    return nullptr;
}

std::unique_ptr<Bprim> EmbreeRenderDelegate::createBprim(const Token& typeId, const Path& id) {
    if (typeId == tokens::renderBuffer()) return std::make_unique<EmbreeRenderBuffer>(id);
    return nullptr;
}

std::unique_ptr<RenderPass> EmbreeRenderDelegate::createRenderPass(RenderIndex* index) {
    return std::make_unique<EmbreeRenderPass>(index, this);
}

EmbreeRenderDelegate::TextureReload EmbreeRenderDelegate::reloadTextures(bool onlyChanged) {
    TextureReload r;
    if (onlyChanged) {
        r.paths = _textures.reloadChanged();
        r.any = !r.paths.empty();
    } else {
        r.any = r.all = _textures.reloadAll();
    }
    if (r.any) ++_contentVersion;  // the next pass starts over
    return r;
}

void EmbreeRenderDelegate::commitResources(ChangeTracker*) {
    if (!_budgetWarning.empty()) _param->warn(hd::Path::absoluteRoot(), std::exchange(_budgetWarning, {}));
    // Incremental (issue 7, edit latency): each table is rebuilt only when what it depends on
    // changed. The result is what a full rebuild of the same scene gives, bit for bit (tables
    // keep the same order and indices; the light distribution uses the same arithmetic).
    // A quiescent point for texture lookups (render passes run between commits, not during
    // one): free the texture versions that TextureCache::invalidate() retired.
    _textures.collectRetired();
    EmbreeRenderParam::Changes c = _param->takeChanges();
    if (!c.any()) return;
    if (_fullCommit) c.all = true;
    ++_contentVersion;
    if (c.scene) {
        rtcCommitScene(_scene);
        ++_topCommits;
    }
    bool meshLights = c.all || c.materialSet || c.geometrySet;
    if (c.all || c.materialSet) {
        // Materials sorted by path, so indices do not depend on pointer order.
        std::vector<MaterialSource*> mats(_param->materials().begin(), _param->materials().end());
        std::sort(mats.begin(), mats.end(), [](auto* a, auto* b) { return a->materialId() < b->materialId(); });
        _snapshot.materials.clear();
        _materialIndex.clear();
        for (MaterialSource* m : mats) {
            _materialIndex[m->materialId()] = static_cast<int>(_snapshot.materials.size());
            _snapshot.materials.push_back(m->record());
        }
        for (GeometrySource* g : _param->geometry()) g->bindMaterials(_materialIndex);
        ++_materialTableBuilds;
        _bindings += long(_param->geometry().size());
    } else {
        for (MaterialSource* m : c.materials) {
            auto it = _materialIndex.find(m->materialId());
            if (it == _materialIndex.end()) {  // not in the table (cannot happen): rebuild all
                _param->markTablesDirty();
                continue;
            }
            MaterialRecord& slot = _snapshot.materials[size_t(it->second)];
            // Mesh lights come from emission (constant or textured): redo them only if it is or
            // was there.
            if (slot.mayEmit || m->record().mayEmit) meshLights = true;
            slot = m->record();
            ++_materialUpdates;
        }
        for (GeometrySource* g : c.bindings) {
            bool before = mayEmit(g->record());
            g->bindMaterials(_materialIndex);
            meshLights = meshLights || before || mayEmit(g->record());
            ++_bindings;
        }
    }
    if (c.all || c.materialSet || !c.materials.empty()) {
        _snapshot.anyPartlyPresent = false;
        for (const MaterialRecord& m : _snapshot.materials) _snapshot.anyPartlyPresent |= m.mayBePartlyPresent;
    }
    // A moved or rebuilt prim changes the mesh lights only if it is (or may become) one.
    for (GeometrySource* g : c.geometry)
        if (!meshLights && mayEmit(g->record())) meshLights = true;
    bool lightTable = c.all || c.lights;
    if (lightTable) {
        std::vector<LightSource*> lights;
        _anyAuthoredLight = false;
        for (LightSource* l : _param->lights()) {
            // A light switched off (invisible) is still the scene's lighting: no default dome.
            _anyAuthoredLight = _anyAuthoredLight || !l->record().portal;
            if (l->enabled()) lights.push_back(l);
        }
        std::sort(lights.begin(), lights.end(), [](auto* a, auto* b) { return a->lightId() < b->lightId(); });
        _sceneLights.clear();
        std::vector<Portal> portals;
        for (LightSource* l : lights) {
            const LightRecord& r = l->record();
            if (r.portal)
                portals.push_back(Portal{r.center, r.axisU, r.axisV, r.normal, r.area});
            else
                _sceneLights.push_back(r);
        }
        _portals = portals.empty() ? nullptr : std::make_shared<const PortalSet>(std::move(portals));
        ++_lightTableBuilds;
    }
    if (meshLights) {
        buildMeshLights();
        ++_meshLightBuilds;
    }
    if (lightTable || meshLights) {
        _snapshot.lights = _sceneLights;
        const int firstMeshLight = int(_snapshot.lights.size());
        _snapshot.lights.insert(_snapshot.lights.end(), _meshLights.begin(), _meshLights.end());
        // Where each prim's (or placed copy's) lights are: the integrator weights a BSDF ray that
        // hits emitting geometry against the light holding that triangle.
        _snapshot.instanceLights.clear();
        for (const MeshLightGroup& g : _meshLightGroups) {
            const int first = firstMeshLight + g.first;
            if (g.instance == RTC_INVALID_GEOMETRY_ID) {
                g.record->emissiveLight = first;
                g.record->emissiveLightCount = g.count;
                continue;
            }
            if (g.instance >= _snapshot.instanceLights.size())
                _snapshot.instanceLights.resize(size_t(g.instance) + 1, {-1, 0});
            _snapshot.instanceLights[g.instance] = {first, g.count};
        }
        _snapshot.usingDefaultLight = false;
        // Emissive geometry lights the scene (even when none of it could be made a light); a
        // textured emitter black wherever it was probed does not.
        if (!_anyAuthoredLight && !_anyEmitter && intSetting("defaultLighting", 1) != 0) {
            // A scene without lights would render black; light it like an overcast sky
            // (a white dome of radiance 1) and say so in the stats.
            LightRecord dome;
            dome.kind = LightRecord::Kind::Dome;
            dome.radiance = glm::vec3(1.0f);
            _snapshot.lights.push_back(dome);
            _snapshot.usingDefaultLight = true;
        }
        // Portals guide every dome light's sampling (delegate/portalSampling.h).
        for (LightRecord& l : _snapshot.lights)
            if (l.kind == LightRecord::Kind::Dome) l.portals = _portals;
        computeLightPower();
    }
    if (lightTable || meshLights || c.scene) {
        // The distribution depends on the scene's bounding sphere: redo it when that moved.
        float R = sceneRadius();
        if (lightTable || meshLights || R != _lightRadius) {
            _lightRadius = R;
            buildLightDistribution();
            ++_lightDistributionBuilds;
        }
    }
    if (lightTable || meshLights || c.all || c.materialSet || c.geometrySet || !c.bindings.empty()) assignLightLinks();
    if (c.scene || c.all || c.geometrySet) {
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
        ++_instanceTableBuilds;
    }
    // A material missing from the table asked for a full rebuild: do it now, not next frame.
    if (_param->takeTablesDirty()) {
        _param->markTablesDirty();
        commitResources(nullptr);
    }
}

void EmbreeRenderDelegate::assignLightLinks() {
    // One bit per linked light (UsdLux collection:lightLink) and one per shadow-linked light
    // (collection:shadowLink), in the light table's order; a prim's bits say which linked lights
    // reach it and whose shadows it casts. Lights without a category light every prim and are
    // shadowed by every prim.
    std::unordered_map<std::string, int> linkBits, shadowBits;
    auto assign = [&](std::unordered_map<std::string, int>& bits, const std::string& category, const char* what) {
        if (category.empty()) return -1;
        auto [it, added] = bits.emplace(category, int(bits.size()));
        if (it->second < 64) return it->second;
        if (added) _param->warn(hd::Path(category), std::string("more than 64 ") + what + ": this one is ignored");
        return -1;
    };
    for (LightRecord& l : _snapshot.lights) {
        l.linkBit = assign(linkBits, l.linkCategory, "light-linked lights");
        l.shadowBit = assign(shadowBits, l.shadowCategory, "shadow-linked lights");
    }
    // Without links, now or at the last assignment, every prim's bits are already 0.
    const bool anyLinks = !linkBits.empty() || !shadowBits.empty();
    if (!anyLinks && !_lightLinksAssigned) return;
    _lightLinksAssigned = anyLinks;
    for (GeometrySource* g : _param->geometry()) {
        uint64_t links = 0, shadows = 0;
        if (anyLinks)
            for (const hd::Token& c : g->categories()) {
                if (auto it = linkBits.find(c.str()); it != linkBits.end() && it->second < 64) links |= uint64_t(1) << it->second;
                if (auto it = shadowBits.find(c.str()); it != shadowBits.end() && it->second < 64) shadows |= uint64_t(1) << it->second;
            }
        g->record()->lightLinks = links;
        g->record()->shadowLinks = shadows;
    }
}

bool EmbreeRenderDelegate::mayEmit(const GeometryRecord* r) const {
    // Whether this prim has mesh lights (its own, or its placed copies') or any material it
    // uses may emit.
    if (r->emissiveLight >= 0) return true;
    for (const MeshLightGroup& g : _meshLightGroups)
        if (g.record == r) return true;
    if (r->kind != GeometryRecord::Kind::Triangles) return false;
    if (materialMayEmit(r->materialIndex)) return true;
    for (int mi : r->triangleMaterial)
        if (mi != r->materialIndex && materialMayEmit(mi)) return true;
    return false;
}

bool EmbreeRenderDelegate::materialMayEmit(int materialIndex) const {
    return materialIndex >= 0 && materialIndex < int(_snapshot.materials.size()) &&
           _snapshot.materials[size_t(materialIndex)].mayEmit;
}

void EmbreeRenderDelegate::buildMeshLights() {
    _meshLights.clear();
    _meshLightGroups.clear();
    _anyEmitter = false;
    // Triangle meshes whose material emits become lights NEE can sample, one light per emitting
    // material of the prim (so a BSDF ray that hits an emitting triangle always finds the light
    // that could have sampled it, and weights it against that light's pdf), and per placed copy
    // of an instanced prototype (PointInstancers, instanceable prims) up to a triangle budget.
    // A textured emission is evaluated at each sampled point; its radiance here is an estimate
    // for picking lights. Ordered by prim id, then instance, then material, so the light list
    // does not depend on pointer order.
    std::vector<GeometrySource*> sources(_param->geometry().begin(), _param->geometry().end());
    std::sort(sources.begin(), sources.end(),
              [](GeometrySource* a, GeometrySource* b) { return a->record()->primId < b->record()->primId; });
    // Instanced emitters copy their emitting triangles per placement (≈ 60 bytes each).
    constexpr size_t kInstancedTriangleBudget = size_t(1) << 20;
    size_t instancedTriangles = 0;
    for (GeometrySource* g : sources) {
        GeometryRecord* r = g->record();
        r->emissiveLight = -1;
        r->emissiveLightCount = 0;
        if (r->kind != GeometryRecord::Kind::Triangles) {
            // Emissive spheres, points and curves light the scene through the paths that hit
            // them (they are not sampled as lights), so the scene is not dark: no default dome.
            if (materialMayEmit(r->materialIndex)) _anyEmitter = true;
            continue;
        }
        const std::vector<unsigned>* ids = g->instanceGeomIds();
        if (!ids && g->instanceId() == RTC_INVALID_GEOMETRY_ID) continue;
        std::vector<int> materials;  // the emitting materials this prim uses, sorted
        if (materialMayEmit(r->materialIndex)) materials.push_back(r->materialIndex);
        for (int mi : r->triangleMaterial)
            if (materialMayEmit(mi)) materials.push_back(mi);
        if (materials.empty()) continue;
        std::sort(materials.begin(), materials.end());
        materials.erase(std::unique(materials.begin(), materials.end()), materials.end());
        if (!ids) {
            addMeshLights(r, materials, r->objectToWorld, RTC_INVALID_GEOMETRY_ID);
            continue;
        }
        const std::vector<InstanceRecord>& placed = *g->instanceRecords();
        size_t perCopy = 0;
        for (uint32_t t = 0; t < r->triangles.size(); ++t)
            perCopy += std::binary_search(materials.begin(), materials.end(), r->materialFor(t));
        size_t skipped = 0;
        for (size_t k = 0; k < ids->size() && k < placed.size(); ++k) {
            if (instancedTriangles + perCopy > kInstancedTriangleBudget) {
                ++skipped;
                continue;
            }
            instancedTriangles += perCopy;
            addMeshLights(r, materials, placed[k].objectToWorld, (*ids)[k]);
        }
        if (skipped)
            warn(g->instancerId(), std::to_string(skipped) + " emissive instances beyond the budget of " +
                                       std::to_string(kInstancedTriangleBudget) +
                                       " light triangles are found by BSDF sampling only (noisier)");
    }
}

void EmbreeRenderDelegate::addMeshLights(GeometryRecord* r, const std::vector<int>& materials,
                                         const glm::mat4& objectToWorld, unsigned instance) {
    MeshLightGroup group{r, instance, int(_meshLights.size()), 0};
    for (int mi : materials) {
        const MaterialRecord& m = _snapshot.materials[size_t(mi)];
        auto tris = std::make_shared<std::vector<uint32_t>>();
        auto cdf = std::make_shared<std::vector<float>>(1, 0.0f);
        double area = 0.0;
        glm::dvec3 sum(0.0);
        auto world = [&](uint32_t point) { return glm::vec3(objectToWorld * glm::vec4(r->points[point], 1.0f)); };
        for (uint32_t t = 0; t < r->triangles.size(); ++t) {
            if (r->materialFor(t) != mi) continue;
            const glm::uvec3& tri = r->triangles[t];
            glm::vec3 a = world(tri.x), b = world(tri.y), c = world(tri.z);
            double ta = 0.5 * glm::length(glm::cross(b - a, c - a));
            if (!(ta > 0.0) || !std::isfinite(ta)) continue;
            area += ta;
            sum += glm::dvec3(a) + glm::dvec3(b) + glm::dvec3(c);
            tris->push_back(t);
            cdf->push_back(float(area));
        }
        if (tris->empty() || !(area > 0.0)) continue;
        for (auto& v : *cdf) v = float(v / area);
        cdf->back() = 1.0f;
        LightRecord l;
        l.kind = LightRecord::Kind::Mesh;
        l.solidAngleSampling = intSetting("lightSolidAngle", 1) != 0;
        l.meshMaterial = mi;
        l.texturedEmission = m.program != nullptr && m.mayEmit;
        // What reaches a point is emission x presence (a partly present emitter is hit, and
        // emits, only that often); textured lights apply their presence per sample.
        bool emitsSomewhere = true;
        l.radiance = l.texturedEmission ? meanEmission(*r, m, *tris, &emitsSomewhere)
                                        : m.constant.emission * m.constant.presence();
        if (!l.texturedEmission && l.radiance == glm::vec3(0.0f)) continue;
        _anyEmitter |= emitsSomewhere;
        l.area = float(area);
        l.mesh = r;
        // Bounding sphere of the emitting triangles (vertex mean, farthest vertex): solid-angle
        // sampling is used only near the light (lightSampling.cpp).
        l.center = glm::vec3(sum / double(3 * tris->size()));
        float rad = 0.0f;
        for (uint32_t t : *tris)
            for (int k = 0; k < 3; ++k) rad = std::max(rad, glm::length(world(r->triangles[t][k]) - l.center));
        l.radius = rad;
        l.meshTriangles = std::move(tris);
        l.meshAreaCdf = std::move(cdf);
        prepareMeshLight(&l, objectToWorld);
        l.visibleToCamera = false;  // the geometry itself is seen; the light is not drawn twice
        _meshLights.push_back(std::move(l));
        ++group.count;
    }
    if (group.count) _meshLightGroups.push_back(group);
}

glm::vec3 EmbreeRenderDelegate::meanEmission(const GeometryRecord& r, const MaterialRecord& m,
                                             const std::vector<uint32_t>& triangles, bool* emits) const {
    // The textured emission x presence at 256 points spread over the light's triangles (several
    // per triangle when there are few: a textured quad is probed across its texture), averaged.
    // Only the light-picking probabilities depend on it, never the estimate's mean.
    constexpr size_t kProbes = 256;
    const size_t n = triangles.size(), step = std::max<size_t>(1, n / kProbes);
    const size_t perTriangle = std::max<size_t>(1, kProbes / n);
    glm::dvec3 sum(0.0);
    size_t count = 0;
    for (size_t i = 0; i < n; i += step) {
        for (size_t k = 0; k < perTriangle; ++k, ++count) {
            // A stratified point of the triangle: Hammersley (k / N, radical inverse of k) mapped
            // by u = 1 - sqrt(a), v = b sqrt(a) (Pharr et al. 2023, §6.5.4: uniform on a triangle).
            float a = (float(k) + 0.5f) / float(perTriangle);
            uint32_t bits = uint32_t(k);
            bits = (bits << 16) | (bits >> 16);
            bits = ((bits & 0x55555555u) << 1) | ((bits & 0xAAAAAAAAu) >> 1);
            bits = ((bits & 0x33333333u) << 2) | ((bits & 0xCCCCCCCCu) >> 2);
            bits = ((bits & 0x0F0F0F0Fu) << 4) | ((bits & 0xF0F0F0F0u) >> 4);
            bits = ((bits & 0x00FF00FFu) << 8) | ((bits & 0xFF00FF00u) >> 8);
            float b = perTriangle > 1 ? float(bits) * 0x1p-32f : 0.5f;
            float sa = std::sqrt(perTriangle > 1 ? a : 1.0f / 3.0f);
            float u = perTriangle > 1 ? b * sa : 1.0f / 3.0f, v = perTriangle > 1 ? (1.0f - b) * sa : 1.0f / 3.0f;
            SurfacePoint point(r, triangles[i], u, v);
            glm::vec3 e = m.program->evaluate(point).emission * m.program->presence(point);
            if (std::isfinite(e.x) && std::isfinite(e.y) && std::isfinite(e.z)) sum += glm::dvec3(e);
        }
    }
    glm::vec3 mean = count ? glm::vec3(sum / double(count)) : glm::vec3(0.0f);
    *emits = std::max({mean.x, mean.y, mean.z}) > 0.0f;
    // Never zero: a texture black at every probe may still emit elsewhere.
    return glm::max(mean, glm::vec3(1e-3f));
}

float EmbreeRenderDelegate::sceneRadius() const {
    RTCBounds b;
    rtcGetSceneBounds(_scene, &b);
    float R = 1.0f;
    if (b.lower_x <= b.upper_x) {
        glm::vec3 ext(b.upper_x - b.lower_x, b.upper_y - b.lower_y, b.upper_z - b.lower_z);
        R = std::max(1e-3f, 0.5f * glm::length(ext));
        if (!std::isfinite(R)) R = 1.0f;
    }
    return R;
}

void EmbreeRenderDelegate::computeLightPower() {
    // The power of each light without the scene radius: distant and dome lights deliver in
    // proportion to R^2 (multiplied in buildLightDistribution, same arithmetic order as before),
    // the others do not depend on it. Textured lights use their image's mean texel (from load).
    constexpr float kPi = 3.14159265358979323846f;
    auto lum = [](const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; };
    const auto& lights = _snapshot.lights;
    _lightPower.assign(lights.size(), 0.0f);
    _lightPowerScales.assign(lights.size(), 0);
    for (size_t i = 0; i < lights.size(); ++i) {
        const LightRecord& l = lights[i];
        switch (l.kind) {
            case LightRecord::Kind::Distant:
                _lightPower[i] = lum(l.irradiance) * kPi;
                _lightPowerScales[i] = 1;
                break;
            case LightRecord::Kind::Dome: {
                glm::vec3 L = l.radiance;
                if (l.environment) L = l.environment->mean * l.radiance;
                _lightPower[i] = lum(L) * kPi * kPi;
                _lightPowerScales[i] = 1;
                break;
            }
            case LightRecord::Kind::Sphere:
                if (l.point) {  // radiance holds the radiant intensity: flux 4 pi I
                    _lightPower[i] = lum(l.radiance) * 4.0f * kPi;
                    break;
                }
                [[fallthrough]];
            default: {
                glm::vec3 L = l.radiance;  // one-sided Lambertian emitter
                if (l.rectTexture) L *= l.rectTexture->mean;
                _lightPower[i] = lum(L) * kPi * l.area;
            }
        }
    }
}

void EmbreeRenderDelegate::buildLightDistribution() {
    // Next-event estimation picks lights in proportion to the power they can deliver to the
    // scene (its bounding sphere of radius R), mixed with 10% uniform so no light starves.
    const float R = _lightRadius;
    _snapshot.lightSceneRadius = R;
    auto& lights = _snapshot.lights;
    std::vector<float> power(lights.size());
    double total = 0.0;
    for (size_t i = 0; i < lights.size(); ++i) {
        float p = _lightPowerScales[i] ? _lightPower[i] * R * R : _lightPower[i];
        power[i] = std::isfinite(p) && p > 0.0f ? p : 0.0f;
        total += power[i];
    }
    _snapshot.lightCdf.assign(lights.size() + 1, 0.0f);
    const float mix = std::clamp(floatSetting("lightPickUniform", 0.1f), 0.0f, 1.0f);
    for (size_t i = 0; i < lights.size(); ++i) {
        float uniform = 1.0f / float(lights.size());
        float prob = total > 0.0 ? (1.0f - mix) * float(power[i] / total) + mix * uniform : uniform;
        lights[i].pickProbability = prob;
        _snapshot.lightCdf[i + 1] = _snapshot.lightCdf[i] + prob;
    }
    if (!lights.empty()) _snapshot.lightCdf.back() = 1.0f;
    // Few lights: sample each at every vertex instead of picking one. No pick variance (on the
    // sun + sky figure scenes the pick was most of the direct-light noise, docs/performance.md
    // 5b) for one extra shadow ray per light. Veach 1997, thesis section 9.2.4 (MIS with a
    // sampling technique per light); pdfs are per light, so each pick probability is 1.
    const int allUpTo = intSetting("neeAllLights", 4);
    _snapshot.neeAllLights = !lights.empty() && int(lights.size()) <= allUpTo;
    if (_snapshot.neeAllLights)
        for (auto& l : lights) l.pickProbability = 1.0f;
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

EmbreeRenderDelegate::Summary EmbreeRenderDelegate::summary() const {
    Summary out;
    std::set<Path> instancers;  // several prototype rprims share one instancer
    for (GeometrySource* g : _param->geometry()) {
        const GeometryRecord* r = g->record();
        const auto* ids = g->instanceGeomIds();
        size_t copies = ids && !ids->empty() ? ids->size() : 1;
        if (ids && !ids->empty()) instancers.insert(g->instancerId());
        if (g->instanceId() == RTC_INVALID_GEOMETRY_ID && (!ids || ids->empty())) continue;
        if (r->kind == GeometryRecord::Kind::Sphere) {
            ++out.spheres;
        } else if (r->kind == GeometryRecord::Kind::Points) {
            out.points += r->points.size();
        } else if (r->kind == GeometryRecord::Kind::Curves) {
            ++out.curvePrims;
            out.curveSegments += r->triangleFace.size();
        } else {
            ++out.meshes;
            out.triangles += r->triangles.size();
        }
        out.instances += copies;
    }
    out.instancers = instancers.size();
    static const char* kinds[] = {"distant", "dome", "sphere", "rect", "disk", "cylinder", "mesh"};
    for (const auto& l : _snapshot.lights)
        if (!_snapshot.usingDefaultLight) ++out.lightsByKind[kinds[int(l.kind)]];
    static const char* lobeNames[] = {"diffuse", "sheen", "specular", "clearcoat", "transmission"};
    IntegratorSettings settings = integratorSettings();
    for (MaterialSource* m : _param->materials()) {
        const MaterialRecord& rec = m->record();
        if (rec.program) {
            out.materialLobes[m->materialId().str()] = "textured";
            continue;
        }
        bsdf::Bsdf b(rec.constant.params, settings.bsdf);
        std::string lobes;
        for (int i = 0; i < bsdf::kLobeCount; ++i)
            if (b.lobes() & (1u << i)) lobes += (lobes.empty() ? "" : "+") + std::string(lobeNames[i]);
        out.materialLobes[m->materialId().str()] = lobes.empty() ? "none" : lobes;
    }
    return out;
}

AovDescriptor EmbreeRenderDelegate::defaultAovDescriptor(const Token& aovName) const {
    auto info = findAov(aovName.str());
    if (!info) return {};
    Value clear = info->format == Format::Int32 ? Value(int(info->clear)) : Value(info->clear);
    return {info->format, info->multiSampled, clear};
}

std::vector<RenderSettingDescriptor> EmbreeRenderDelegate::renderSettingDescriptors() const {
    // Words list their choices and numbers their range (renderSettingProblem): hosts and
    // `principled render --set` refuse anything else instead of rendering with the default.
    return {
        {"Samples per pixel", Token("convergedSamplesPerPixel"), Value(64), "samples per pixel at convergence", {}, 1, 1 << 20},
        {"Random seed", Token("seed"), Value(0), "same seed, same image; another seed, another image"},
        {"Max depth", Token("maxDepth"), Value(8), "bounces after the camera hit (0 = direct light only)", {}, 0, 1024},
        {"Clamp indirect", Token("clampIndirect"), Value(0.0f), "max channel value of an indirect contribution; 0 = off", {}, 0},
        {"Shading model", Token("shadingModel"), Value(Token("disney")), "disney | ue4", {"disney", "ue4"}},
        {"Sampler", Token("sampler"), Value(Token("sobol")), "sobol (Owen-scrambled) | independent", {"sobol", "independent"}},
        {"MIS", Token("mis"), Value(1), "multiple importance sampling of lights and BSDF (0: next-event estimation only)", {}, 0, 1},
        {"MIS compensation", Token("misCompensation"), Value(1), "with MIS, a textured dome light samples only what lies above its mean radiance; BSDF sampling takes the rest (0: the whole map)", {}, 0, 1},
        {"Spatial light pick", Token("spatialLightPick"), Value(1), "with more lights than neeAllLights, next-event estimation weighs each light's power by 1 / distance^2 from the point (beyond 64 lights through a light tree; 0: by power alone)", {}, 0, 1},
        {"NEE all lights", Token("neeAllLights"), Value(4), "next-event estimation samples every light when the scene has at most this many (0: always pick one)", {}, 0},
        {"Light pick uniform", Token("lightPickUniform"), Value(0.1f), "next-event estimation light pick: this fraction uniform, the rest by power", {}, 0, 1},
        {"Light solid angle", Token("lightSolidAngle"), Value(1), "small mesh lights (<= 8 triangles) sampled by solid angle (Arvo 1995); 0: by area", {}, 0, 1},
        {"NEE", Token("nee"), Value(1), "next-event estimation (shadow rays to lights); 0: lights found by BSDF sampling only", {}, 0, 1},
        {"Lobe pruning", Token("lobePruning"), Value(1), "skip BSDF lobes whose weight is below the cutoff", {}, 0, 1},
        {"VNDF sampling", Token("vndf"), Value(1), "GGX visible-normal sampling (0: classic distribution sampling)", {}, 0, 1},
        {"Delta roughness", Token("deltaRoughness"), Value(1e-3f), "below this roughness specular is a perfect mirror", {}, 0, 1},
        {"Legacy specular G", Token("legacySpecularG"), Value(0), "Burley 2012 course-notes G remap (0.5 + 0.5 r)^2", {}, 0, 1},
        {"Specular Fresnel", Token("specularFresnel"), Value(Token("schlick")),
         "schlick (Burley 2012) | dielectric (Cycles 3.4 Principled v1: F0 blended to white along the exact "
         "dielectric Fresnel of the index from specular)", {"schlick", "dielectric"}},
        {"Lobe mask", Token("lobeMask"), Value(31), "diagnostics: BSDF lobes allowed (bits: 1 diffuse, 2 sheen, 4 specular, 8 clearcoat, 16 transmission)", {}, 0, 31},
        {"Noise threshold", Token("noiseThreshold"), Value(0.0f), "stop sampling a pixel when the relative standard error of its mean is below this; 0 = off", {}, 0, 10},
        {"Min samples", Token("minSamples"), Value(0),
         "adaptive sampling: samples before a pixel may stop; 0 = from the threshold, 16 / threshold^0.3 (40 at 0.05)", {}, 0, 1 << 20},
        {"Default lighting", Token("defaultLighting"), Value(1), "light a scene without lights with a white dome", {}, 0, 1},
        {"Refine level", Token("refineLevel"), Value(-1), "subdivision level for every mesh; -1 = adaptive from the projected size", {}, -1, 8},
        {"Dicing rate", Token("dicingRate"), Value(1.5f), "adaptive subdivision: target refined edge length in pixels", {}, 0.05},
        {"Max refine level", Token("maxRefineLevel"), Value(6), "adaptive subdivision: highest level", {}, 0, 8},
        {"Dicing tolerance", Token("dicingTolerance"), Value(0.1f),
         "adaptive subdivision: refine no further once the surface lies within this many pixels of its limit "
         "(flat cages stay unrefined); 0 = edge length (dicingRate) only", {}, 0},
        {"Subdivision budget", Token("subdivisionBudget"), Value(16e6f),
         "triangles all subdivision meshes may refine to together; over it every level is lowered in half steps "
         "(the dicing rate times sqrt 2 each) until the scene fits; 0 = no limit", {}, 0},
        {"Dome visible to camera", Token("domeLightCameraVisibility"), Value(1), "camera rays see the dome light", {}, 0, 1},
        {"Lights visible to camera", Token("lightCameraVisibility"), Value(0),
         "camera rays see the shapes of sphere, rect, disk and cylinder lights (0, as Cycles, Karma and hdEmbree: "
         "lights light the scene and show in reflections only)", {}, 0, 1},
        {"Back-face culling", Token("backfaceCulling"), Value(0),
         "camera rays skip the back faces of meshes and spheres whose doubleSided is 0 (1, as Storm and usdrecord; "
         "0, as Cycles and Karma by default: both sides are seen; UsdGeomGprim leaves culling to the renderer)", {}, 0, 1},
        {"Caustics", Token("caustics"), Value(1),
         "light tracing for caustics: light from sphere, rect, disk, cylinder, distant and untextured mesh lights through sharp "
         "specular, clearcoat or glass lobes onto the surfaces the camera sees (0: path tracing only)", {}, 0, 1},
        {"Caustic roughness", Token("causticRoughness"), Value(0.1f),
         "lobes at most this rough carry caustics to light tracing", {}, 0, 1},
        {"Caustic paths", Token("causticPaths"), Value(0.125f),
         "light paths per camera sample when the scene has caustic casters and lights (with causticAdaptive: "
         "the first passes' count; later passes pick within 1/16x to 4x of it)", {}, 0, 64},
        {"Caustic adaptive", Token("causticAdaptive"), Value(1),
         "later passes trace as many caustic light paths as make the image's variance times its rays least, "
         "from the passes before (0: causticPaths throughout)", {}, 0, 1},
        {"Caustic merging", Token("causticMerging"), Value(1),
         "caustics seen after the first bounce (in mirrors, lighting other surfaces) from light-traced photons "
         "(progressive photon mapping); 0: path tracing finds those", {}, 0, 1},
        {"Caustic merge radius", Token("causticMergeRadius"), Value(0.0f),
         "photon search radius at 1 sample per pixel, scene units (0: 5 % of the caustic casters' size); "
         "shrinks as samples accumulate", {}, 0},
        {"Bump shadowing", Token("bumpShadowing"), Value(1),
         "diffuse and sheen lobes shadowed where a normal map or bent normal leans away from the surface "
         "(Chiang et al. 2019, as Cycles); 0: off", {}, 0, 1},
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
    if (key == Token("refineLevel") || key == Token("dicingRate") || key == Token("maxRefineLevel") ||
        key == Token("dicingTolerance")) {
        updateDicing();
        _subdivisionSettingsChanged = true;  // the next sync re-plans every subdivision mesh
    }
    // The plans do not depend on the budget: the next sync fits them again and rebuilds only
    // the meshes whose level moves.
    if (key == Token("subdivisionBudget")) _param->requestSubdivisionRefit();
}

void EmbreeRenderDelegate::prepareRprimSync(const std::vector<hd::Rprim*>& prims,
                                            const std::vector<hd::SceneDelegate*>& delegates,
                                            const std::vector<hd::DirtyBits>& bits,
                                            std::vector<std::pair<hd::Rprim*, hd::DirtyBits>>* alsoSync) {
    // The meshes this sync rebuilds, planned afresh; every other mesh keeps the plan it was
    // built from. The fit covers the whole scene, so a scene's levels do not depend on the
    // order of its edits.
    std::vector<size_t> rebuilt;
    std::set<const Mesh*> rebuilding;
    for (size_t i = 0; i < prims.size(); ++i)
        if (auto* m = dynamic_cast<Mesh*>(prims[i]); m && m->rebuildsOn(bits[i])) {
            rebuilt.push_back(i);
            rebuilding.insert(m);
        }
    // Dicing settings changed since the last sync: every subdivision mesh is planned afresh
    // (this call hands them back to be rebuilt; the next one plans them).
    if (_subdivisionSettingsChanged.exchange(false)) {
        for (GeometrySource* g : _param->geometry())
            if (auto* m = dynamic_cast<Mesh*>(g); m && m->plan() && !rebuilding.count(m))
                alsoSync->emplace_back(m, hd::RprimDirty::Topology);
        if (!alsoSync->empty()) return;
    }
    std::vector<std::optional<subdiv::LevelPlan>> fresh(rebuilt.size());
    tbb::parallel_for(size_t(0), rebuilt.size(), [&](size_t j) {
        const size_t i = rebuilt[j];
        fresh[j] = static_cast<Mesh*>(prims[i])->levelPlan(delegates[i], _param.get());
    });
    std::vector<subdiv::LevelPlan> plans;
    std::vector<Mesh*> owners;
    std::vector<char> isRebuilt;
    for (size_t j = 0; j < rebuilt.size(); ++j) {
        auto* m = static_cast<Mesh*>(prims[rebuilt[j]]);
        m->grantLevel(-1, fresh[j]);
        if (!fresh[j]) continue;
        plans.push_back(*fresh[j]);
        owners.push_back(m);
        isRebuilt.push_back(1);
    }
    // Nothing to refine in this sync and no mesh removed: the last fit stands.
    if (!_param->takeSubdivisionRefit() && plans.empty()) return;
    for (GeometrySource* g : _param->geometry())
        if (auto* m = dynamic_cast<Mesh*>(g); m && !rebuilding.count(m) && m->plan()) {
            plans.push_back(*m->plan());
            owners.push_back(m);
            isRebuilt.push_back(0);
        }
    if (plans.empty()) return;
    const double budget = std::max(0.0f, floatSetting("subdivisionBudget", 16e6f));
    const subdiv::LevelBudgetFit fit = subdiv::fitLevelBudget(plans, budget);
    for (size_t j = 0; j < plans.size(); ++j) {
        if (isRebuilt[j]) {
            owners[j]->grantLevel(fit.levels[j], plans[j]);
        } else if (std::min(fit.levels[j], plans[j].faceCapLevel) != owners[j]->refineLevel()) {
            // A clean mesh the new fit moves: rebuilt at its new level in this sync.
            owners[j]->grantLevel(fit.levels[j], plans[j]);
            alsoSync->emplace_back(owners[j], hd::RprimDirty::Topology);
        }
    }
    if (fit.steps > 0) {
        int before = 0, after = 0;
        for (size_t j = 0; j < plans.size(); ++j) {
            before = std::max(before, std::min(plans[j].levelAt(0), plans[j].faceCapLevel));
            after = std::max(after, std::min(fit.levels[j], plans[j].faceCapLevel));
        }
        char text[400];
        std::snprintf(text, sizeof text,
                      "subdivision: %zu mesh(es) would refine to %.3g triangles, over the scene budget of %.3g "
                      "(render setting subdivisionBudget): levels lowered in %d half step(s), the highest from %d "
                      "to %d, to %.3g triangles%s",
                      plans.size(), fit.requested, budget, fit.steps, before, after, fit.triangles,
                      fit.fits ? "" : "; still over the budget with every mesh at its lowest level");
        _budgetWarning = text;  // said once, at commit: this may run more than once per sync
    }
}

void EmbreeRenderDelegate::updateDicing() {
    EmbreeRenderParam::Dicing d = _param->dicing();
    d.level = intSetting("refineLevel", -1);
    d.targetEdgePixels = std::max(0.05f, floatSetting("dicingRate", 1.5f));
    d.maxLevel = std::clamp(intSetting("maxRefineLevel", 6), 0, 8);
    const float tolerance = floatSetting("dicingTolerance", 0.1f);
    d.tolerancePixels = std::isnan(tolerance) ? 0.0f : std::max(0.0f, tolerance);  // inf: never refine for shape
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
    s.lightsVisible = intSetting("lightCameraVisibility", 0) != 0;
    s.backfaceCulling = intSetting("backfaceCulling", 0) != 0;
    s.bumpShadowing = intSetting("bumpShadowing", 1) != 0;
    s.causticRoughness = intSetting("caustics", 1) != 0 ? std::clamp(floatSetting("causticRoughness", 0.1f), 0.0f, 1.0f) : 0.0f;
    s.causticPaths = std::clamp(floatSetting("causticPaths", 0.125f), 0.0f, 64.0f);
    if (!std::isfinite(s.causticRoughness)) s.causticRoughness = 0.0f;
    if (!std::isfinite(s.causticPaths)) s.causticPaths = 0.0f;
    s.causticMerging = intSetting("causticMerging", 1) != 0;
    s.causticAdaptive = intSetting("causticAdaptive", 1) != 0;
    s.causticMergeRadius = floatSetting("causticMergeRadius", 0.0f);
    if (!(s.causticMergeRadius > 0.0f) || !std::isfinite(s.causticMergeRadius)) s.causticMergeRadius = 0.0f;
    auto model = getString(renderSetting(Token("shadingModel")));
    s.bsdf.model = (model && *model == "ue4") ? bsdf::Model::UE4 : bsdf::Model::Disney;
    s.mis = intSetting("mis", 1) != 0;
    s.nee = intSetting("nee", 1) != 0;
    s.misCompensation = intSetting("misCompensation", 1) != 0;
    s.spatialLightPick = intSetting("spatialLightPick", 1) != 0;
    s.bsdf.pruneLobes = intSetting("lobePruning", 1) != 0;
    s.bsdf.vndfSampling = intSetting("vndf", 1) != 0;
    s.bsdf.deltaRoughness = std::clamp(floatSetting("deltaRoughness", 1e-3f), 0.0f, 1.0f);
    s.bsdf.legacySpecularG = intSetting("legacySpecularG", 0) != 0;
    auto fresnel = getString(renderSetting(Token("specularFresnel")));
    s.bsdf.dielectricFresnel = fresnel && *fresnel == "dielectric";
    s.bsdf.lobeMask = bsdf::LobeMask(intSetting("lobeMask", 31)) & ((1u << bsdf::kLobeCount) - 1u);
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
    std::map<std::string, double> stats = sceneFeatureStats(describeScene(_snapshot, integratorSettings().bsdf));
    stats.merge(std::map<std::string, double>{
        {"rays", double(_rays.load())},
        {"samples", double(_samples.load())},
        {"invalidSamples", double(_invalidSamples.load())},
        {"causticCasters", double(std::max(0L, _causticCasters.load()))},
        {"causticLights", double(_causticLights.load())},
        {"causticPaths", double(_causticPaths.load())},
        {"renderSeconds", secs},
        {"mraysPerSecond", secs > 0 ? double(_rays.load()) / secs * 1e-6 : 0.0},
        {"blasBuilds", double(_param->blasBuilds.load())},
        {"meshesRebuilt", double(_param->meshesRebuilt.load())},
        {"transformUpdates", double(_param->transformUpdates.load())},
        {"topLevelCommits", double(_topCommits.load())},
        // Commit work (tests of incremental edits): whole tables against in-place updates.
        {"commits", double(_contentVersion.load() - 1)},
        {"materialTableBuilds", double(_materialTableBuilds.load())},
        {"materialUpdates", double(_materialUpdates.load())},
        {"materialBindings", double(_bindings.load())},
        {"lightTableBuilds", double(_lightTableBuilds.load())},
        {"meshLightBuilds", double(_meshLightBuilds.load())},
        {"lightDistributionBuilds", double(_lightDistributionBuilds.load())},
        {"instanceTableBuilds", double(_instanceTableBuilds.load())},
        {"defaultLight", _snapshot.usingDefaultLight ? 1.0 : 0.0},
        {"lights", double(_snapshot.lights.size())},
        {"materials", double(_snapshot.materials.size())},
        {"instances", double(_instances.load())},  // PointInstancer / instanceable instances
    });
    return stats;
}

void EmbreeRenderDelegate::setCausticStats(long casters, long lights, long paths) {
    _causticCasters = casters;
    _causticLights = lights;
    _causticPaths += paths;
}

std::string EmbreeRenderDelegate::sceneSummary() const {
    std::string s = describeFeatures(describeScene(_snapshot, integratorSettings().bsdf));
    const long casters = _causticCasters.load(), lights = _causticLights.load();
    if (casters == -2) return s;  // no pass yet
    if (casters == -1) return s + "; caustics: path tracing only (turned off: caustics, clampIndirect or nee)";
    if (casters > 0 && lights > 0)
        s += "; caustics: light tracing from " + std::to_string(lights) + " light(s) through " +
             std::to_string(casters) + " caster(s) with sharp lobes";
    else
        s += lights == 0 ? "; caustics: none (no sphere, rect, disk, cylinder or distant light)"
                         : "; caustics: none (no prim has a sharp lobe)";
    return s;
}

}  // namespace principled::embree
