// SPDX-License-Identifier: Apache-2.0
// Integrator: unidirectional path tracing with next-event estimation and multiple importance
// sampling (power heuristic) over the scene snapshot's lights.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "delegate/hd/token.h"

#include <glm/glm.hpp>

#include "bsdf/bsdf.h"
#include "delegate/rayRecorder.h"
#include "delegate/lightPick.h"
#include "delegate/photonGrid.h"
#include "delegate/sampler.h"
#include "delegate/sceneData.h"

namespace principled::embree {

struct LightSample;  // delegate/lightSampling.h
class CausticScene;         // delegate/causticScene.h
class CameraConnector;      // delegate/cameraConnection.h
struct CameraConnection;
struct EmittedRay;

struct IntegratorSettings {
    SamplerKind sampler = SamplerKind::Sobol;
    bool mis = true;          ///< false: lights are found by next-event estimation only
    bool nee = true;          ///< false: lights are found only by BSDF sampling (no shadow rays)
    /// With MIS, a textured dome's next-event estimation samples the part of it above its mean
    /// radiance only, and BSDF sampling covers the rest (EnvironmentMap::compensated).
    bool misCompensation = true;
    /// Next-event estimation picks a light by its power scaled by 1 / distance^2 from the
    /// shading point (delegate/lightPick.h), when it picks one among at most 64.
    bool spatialLightPick = true;
    RayRecorder* recorder = nullptr;  ///< receives every ray cast (bench/ replay); usually null
    std::vector<hd::Token> aovPrimvars;  ///< primvars the first hit records (at most 4)
    int maxDepth = 8;         ///< path vertices after the camera hit (0 = direct light only)
    int rouletteDepth = 3;    ///< Russian roulette starts at this depth
    float clampIndirect = 0;  ///< max channel of an indirect contribution; 0 = off
    bool domeVisible = true;  ///< camera rays that escape see the dome light
    bool lightsVisible = false;  ///< camera rays see sphere/rect/disk/cylinder light shapes
    /// Camera rays pass the back faces of single-sided (doubleSided = 0) meshes and spheres.
    bool backfaceCulling = false;
    /// Diffuse and sheen lobes are shadowed where the shading normal (normal map, bent normal)
    /// leans away from the surface's own normal (bsdf/bumpShadowing.h; Cycles 3.4 does too).
    bool bumpShadowing = true;
    /// PathSample::lobes holds the per-lobe split (some lobe AOV is bound); when false the
    /// whole first-hit contribution is in lobes[0] and no per-lobe values are computed.
    bool splitLobes = true;
    bsdf::Options bsdf;
    /// Caustic light tracing (delegate/causticScene.h): the scene's casters and caustic lights;
    /// null or inactive: the path tracer does everything. Owned by the render pass.
    const CausticScene* caustics = nullptr;
    /// Roughness at or below which a caster's lobe is sharp (0 turns caustic tracing off).
    float causticRoughness = 0.1f;
    /// Light paths traced per camera sample when the scene has casters and caustic lights: the
    /// count used throughout, or with causticAdaptive the first passes' count and the centre of
    /// the range the budget picks from (delegate/causticBudget.h).
    float causticPaths = 0.125f;
    bool causticAdaptive = true;
    /// Caustic photons of the pass: at path vertices after the first hit the path tracer takes
    /// the caustic light from their density (null: only the first hit's caustics are light
    /// traced, later ones stay with path tracing). photonScale = 1 / (light paths * pi r^2).
    const PhotonGrid* photons = nullptr;
    float photonScale = 0.0f;
    /// Light paths store photons (settings causticMerging).
    bool causticMerging = true;
    /// Photon search radius at the first pass, world units (0: 5 % of the casters' mean
    /// bounding radius); it shrinks as r^2 ~ paths^(-1/3) (Knaus & Zwicker 2011, alpha 2/3).
    float causticMergeRadius = 0.0f;
};

struct Ray {
    glm::vec3 origin;
    glm::vec3 direction;  ///< unit length
    float tnear = 0.0f;
    float tfar = 1e30f;
};

/// What the camera ray hit first (for the geometric and ID AOVs).
struct FirstHit {
    bool hit = false;
    float t = 0.0f;              ///< distance along the unit camera ray
    glm::vec3 position{0.0f};    ///< world space
    glm::vec3 normal{0.0f};      ///< world-space shading normal, facing the camera
    glm::vec3 albedo{0.0f};      ///< base colour of the material
    int primId = -1, instanceId = -1, elementId = -1, materialId = -1;
    std::array<glm::vec3, 4> primvars{};  ///< IntegratorSettings::aovPrimvars at the hit
};

/// What a camera path returns for one sample. radiance = sum(lobes) + emission: the light that
/// left the first hit through each lobe (NEE there split by lobe; light found through the
/// direction sampled at the first hit split by each lobe's share of f there, or all to the
/// sampled lobe after a delta sample), and emission seen directly (emitters and visible lights).
struct PathSample {
    glm::vec3 radiance{0.0f};
    float alpha = 0.0f;     ///< 1 when the camera ray hit geometry
    bsdf::LobeValues lobes{};
    glm::vec3 emission{0.0f};
    FirstHit first;
    uint32_t rays = 0;      ///< rays cast (for stats)
    bool invalid = false;   ///< a NaN/Inf was produced and the sample dropped
};

class Integrator {
public:
    Integrator(const SceneSnapshot& scene, const IntegratorSettings& settings);

    PathSample trace(const Ray& cameraRay, Sampler& sampler) const;

    /// Gives trace() the pass's caustic photons (IntegratorSettings::photons, photonScale), once
    /// the pass's light paths have made them and before any camera path is traced.
    void usePhotons(const PhotonGrid* photons, float scale) {
        _settings.photons = photons;
        _settings.photonScale = scale;
    }

    /// Whether caustic light tracing shares the work (settings.caustics active).
    bool causticsActive() const;
    /// What a caustic light path delivers to one pixel: value = weight * f * importance, and with
    /// splitLobes its split by the lobes of the surface the camera sees.
    struct Splat {
        int x = 0, y = 0;
        glm::vec3 value{0.0f};
        bsdf::LobeValues lobes{};
    };
    /// Traces one light path from the emitted ray through sharp lobes of casters and connects
    /// every later vertex to the camera through its other lobes (the caustic share of the path
    /// space that trace() leaves out). Calls splat for each connection; returns the rays cast.
    /// Stores a photon (photonFn) at the same vertices when settings.causticMerging.
    template <typename SplatFn, typename PhotonFn>
    uint32_t traceCaustic(const EmittedRay& emitted, Sampler& sampler, const CameraConnector& camera,
                          SplatFn&& splat, PhotonFn&& photon) const {
        // Uninitialised storage: entries are written before they are read (a value-initialised
        // pair of arrays cost 2 KB of stores per light path).
        union Buffers {
            Splat splats[kMaxCausticSplats];
            Buffers() {}
        } splatStore;
        union PhotonBuffers {
            Photon photons[kMaxCausticSplats];
            PhotonBuffers() {}
        } photonStore;
        Splat* buffer = splatStore.splats;
        Photon* photons = photonStore.photons;
        int count = 0, photonCount = 0;
        uint32_t rays = traceCausticPath(emitted, sampler, camera, buffer, &count, photons, &photonCount);
        for (int i = 0; i < count; ++i) splat(buffer[i]);
        for (int i = 0; i < photonCount; ++i) photon(photons[i]);
        return rays;
    }
    static constexpr int kMaxCausticSplats = 16;

private:
    uint32_t traceCausticPath(const EmittedRay& emitted, Sampler& sampler, const CameraConnector& camera,
                              Splat* splats, int* count, Photon* photons, int* photonCount) const;
    /// Next-event estimation on a mesh light whose emission is textured: the radiance of the
    /// light's material at the sampled point, into ls->Li. False when it is zero or invalid.
    bool texturedEmission(const LightRecord& light, LightSample* ls) const;

    const SceneSnapshot& _scene;
    IntegratorSettings _settings;
    /// Per material: the BSDF of a material without a program (no textures), built once per
    /// pass instead of once per hit; empty for textured materials.
    std::vector<std::optional<bsdf::Bsdf>> _constantBsdfs;
    /// Indices into the scene's lights: those a ray can hit (sphere, rect, disk, cylinder) and
    /// those an escaping ray sees (dome, distant); mesh lights are hit as geometry.
    std::vector<uint32_t> _areaLights, _environmentLights;
    /// With more than kLinearAreaLights area lights, rays find them through a tree of their
    /// bounding boxes (O(log n) per ray instead of a test per light); _unboundedAreaLights keeps
    /// those without finite bounds, tested one by one.
    static constexpr size_t kLinearAreaLights = 8;
    LightTree _areaLightTree;
    std::vector<uint32_t> _unboundedAreaLights;
    LightPick _lightPick;  ///< which light next-event estimation samples when it samples one
    /// Some light scales the diffuse or specular lobes (LightRecord::scalesLobes): paths then
    /// keep the lobe classes' shares of f at their last vertex.
    bool _lightsScaleLobes = false;
};

}  // namespace principled::embree
