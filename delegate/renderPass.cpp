// SPDX-License-Identifier: Apache-2.0
#include "delegate/renderPass.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include "delegate/aovs.h"
#include "delegate/cameraConnection.h"
#include "delegate/causticBudget.h"
#include "delegate/causticScene.h"
#include "delegate/photonGrid.h"
#include "delegate/hd/camera.h"
#include "delegate/hd/renderIndex.h"
#include "delegate/hd/tokens.h"
#include "delegate/integrator.h"
#include "delegate/renderBuffer.h"
#include "delegate/renderDelegate.h"
#include "delegate/sampler.h"

#include "bsdf/warp.h"

namespace principled::embree {

using namespace hd;

namespace {

constexpr int kTileSize = 16;
constexpr int kMaxSamplesPerPass = 16;

// The samples a pixel takes before adaptive sampling may stop it: the minSamples setting, or
// with 0 (the default) more the lower the threshold, as Cycles' automatic rule does
// (16 / threshold^0.3: 32 at 0.1, 40 at 0.05, 64 at 0.01).
int adaptiveMinSamples(int setting, float threshold) {
    if (setting > 0) return std::max(2, setting);
    return std::max(2, int(std::ceil(16.0 / std::pow(double(threshold), 0.3))));
}

// A camera ray through image position (px, py) in pixels, top-left origin. With a lens
// (lensRadius > 0, perspective only) the ray starts at lens point lens * lensRadius on the
// z = 0 plane and passes through the pinhole ray's point on the focus plane z = -focusDistance.
// Thin lens: Pharr, Jakob & Humphreys 2023, "Physically Based Rendering" 4th ed., §5.2.3.
Ray cameraRay(const Camera& cam, const glm::vec4& window, int width, int height, float px,
              float py, float lensRadius = 0.0f, glm::vec2 lens = glm::vec2(0.0f)) {
    float sx = window.x + (px / width) * (window.y - window.x);
    float sy = window.w - (py / height) * (window.w - window.z);
    const glm::dmat4& m = cam.transform();
    glm::dvec3 o, d;
    glm::dvec4 oCam(0.0, 0.0, 0.0, 1.0), dCam(sx, sy, -1.0, 0.0);
    if (cam.projection() == Camera::Projection::Orthographic) {
        oCam = glm::dvec4(sx, sy, 0.0, 1.0);
        dCam = glm::dvec4(0.0, 0.0, -1.0, 0.0);
    } else if (lensRadius > 0.0f) {
        const double f = cam.focusDistance();
        oCam = glm::dvec4(double(lens.x) * lensRadius, double(lens.y) * lensRadius, 0.0, 1.0);
        dCam = glm::dvec4(sx * f - oCam.x, sy * f - oCam.y, -f, 0.0) / f;  // z stays -1
    }
    o = glm::dvec3(m * oCam);
    d = glm::dvec3(m * dCam);
    double len = glm::length(d);
    Ray r;
    r.origin = glm::vec3(o);
    r.direction = glm::vec3(d / len);
    // The clipping range is along -z in camera space; d has z = -1, so t scales with |d|.
    glm::vec2 clip = cam.clippingRange();
    r.tnear = float(clip.x * len);  // orthographic too (len 1): its near plane clips as Storm's
    r.tfar = float(clip.y * len);
    if (!(r.tnear >= 0.0f) || !std::isfinite(r.tnear)) r.tnear = 0.0f;
    if (!(r.tfar > r.tnear) || !std::isfinite(r.tfar)) r.tfar = 1e30f;
    return r;
}

struct BoundAov {
    AovInfo info;
    EmbreeRenderBuffer* buffer;
    int primvarSlot = -1;  ///< index into FirstHit::primvars for "primvars:NAME"
};

// Camera quantities the geometric AOVs need.
struct CameraFrame {
    glm::vec3 origin;    // world-space camera position
    glm::vec3 forward;   // world-space viewing direction (-Z of the camera), unit
    glm::mat3 toEye;     // world -> camera rotation for normals
    float nearZ, farZ;
    bool ortho;
    float clipDepth(float viewZ) const {
        // OpenGL-style depth remapped to [0,1]: (z_ndc + 1) / 2 = f (1 - n/z) / (f - n);
        // orthographic: (z - n) / (f - n).
        float d = ortho ? (viewZ - nearZ) / (farZ - nearZ)
                        : farZ * (1.0f - nearZ / viewZ) / (farZ - nearZ);
        return std::isfinite(d) ? std::clamp(d, 0.0f, 1.0f) : 1.0f;
    }
};

CameraFrame cameraFrame(const Camera& cam) {
    CameraFrame cf;
    const glm::dmat4& m = cam.transform();
    cf.origin = glm::vec3(m[3]);
    cf.forward = glm::normalize(glm::vec3(m * glm::dvec4(0, 0, -1, 0)));
    // Normals go to eye space with the inverse transpose of the view matrix, i.e. the
    // transpose of camera-to-world's rotation (renormalised after).
    cf.toEye = glm::transpose(glm::mat3(m));
    cf.nearZ = cam.clippingRange().x;
    cf.farZ = cam.clippingRange().y;
    cf.ortho = cam.projection() == Camera::Projection::Orthographic;
    return cf;
}

void writeSample(const BoundAov& a, int x, int y, const PathSample& ps, const CameraFrame& cf) {
    const FirstHit& f = ps.first;
    auto put3 = [&](const glm::vec3& v) {
        float c[3] = {v.x, v.y, v.z};
        a.buffer->addSample(x, y, c);
    };
    switch (a.info.kind) {
        case AovKind::Color: {
            float c[4] = {ps.radiance.x, ps.radiance.y, ps.radiance.z, ps.alpha};
            a.buffer->addSample(x, y, c);
            return;
        }
        case AovKind::Alpha: a.buffer->addSample(x, y, &ps.alpha); return;
        case AovKind::Albedo: put3(f.hit ? f.albedo : glm::vec3(0.0f)); return;
        case AovKind::Diffuse: put3(ps.lobes[int(bsdf::Lobe::Diffuse)]); return;
        case AovKind::Sheen: put3(ps.lobes[int(bsdf::Lobe::Sheen)]); return;
        case AovKind::Specular: put3(ps.lobes[int(bsdf::Lobe::Specular)]); return;
        case AovKind::Clearcoat: put3(ps.lobes[int(bsdf::Lobe::Clearcoat)]); return;
        case AovKind::Transmission: put3(ps.lobes[int(bsdf::Lobe::Transmission)]); return;
        case AovKind::Emission: put3(ps.emission); return;
        case AovKind::SampleCount:
        case AovKind::Variance: return;  // filled from the pixel statistics at resolve
        default: break;
    }
    // First-hit AOVs: only hits write; pixels never hit resolve to the clear value.
    if (!f.hit) return;
    switch (a.info.kind) {
        case AovKind::Depth: {
            float d = cf.clipDepth(glm::dot(f.position - cf.origin, cf.forward));
            a.buffer->addSample(x, y, &d);
            return;
        }
        case AovKind::CameraDepth: a.buffer->addSample(x, y, &f.t); return;
        case AovKind::Position: put3(f.position); return;
        case AovKind::Normal: put3(f.normal); return;
        case AovKind::Neye: put3(glm::normalize(cf.toEye * f.normal)); return;
        case AovKind::PrimId: a.buffer->addSample(x, y, int32_t(f.primId)); return;
        case AovKind::InstanceId: a.buffer->addSample(x, y, int32_t(f.instanceId)); return;
        case AovKind::ElementId: a.buffer->addSample(x, y, int32_t(f.elementId)); return;
        case AovKind::MaterialId: a.buffer->addSample(x, y, int32_t(f.materialId)); return;
        case AovKind::Primvar:
            if (a.primvarSlot >= 0) put3(f.primvars[a.primvarSlot]);
            return;
        default: return;
    }
}

// The light a sample carries times the camera's exposure scale (Camera::exposureScale): the
// colour, emission and per-lobe values; first-hit data is not light and is left alone.
void exposeSample(PathSample* ps, float exposure) {
    ps->radiance *= exposure;
    ps->emission *= exposure;
    for (glm::vec3& l : ps->lobes) l *= exposure;
}

float luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

}  // namespace

EmbreeRenderPass::EmbreeRenderPass(hd::RenderIndex* index, EmbreeRenderDelegate* delegate)
    : RenderPass(index), _delegate(delegate) {}

EmbreeRenderPass::~EmbreeRenderPass() = default;

bool EmbreeRenderPass::needsRestart(const RenderPassState& state) {
    // The delegate's content version moves only when a commit changed what is rendered, so an
    // edit that leaves the image as it is does not throw the samples away.
    unsigned sv = _delegate->contentVersion();
    unsigned setv = _delegate->renderSettingsVersion();
    std::ostringstream key;
    key << std::setprecision(17);  // any change of a value restarts (6 digits missed small ones)
    key << state.cameraId.str() << '|' << state.width << 'x' << state.height;
    for (const auto& b : state.aovBindings) key << '|' << b.aovName.str() << '@' << b.renderBuffer;
    const hd::Framing& fr = state.framing;
    // (Exact digits: the window's pixel rectangle follows from these values.)
    key << '|' << int(fr.conform) << ',' << fr.pixelAspectRatio << ',' << fr.dataWindowNDC.x << ','
        << fr.dataWindowNDC.y << ',' << fr.dataWindowNDC.z << ',' << fr.dataWindowNDC.w;
    if (auto* cam = static_cast<Camera*>(renderIndex()->sprim(tokens::camera(), state.cameraId))) {
        const double* m = &cam->transform()[0][0];
        for (int i = 0; i < 16; ++i) key << ',' << m[i];
        key << ',' << cam->focalLength() << ',' << cam->horizontalAperture() << ','
            << cam->verticalAperture() << ',' << cam->horizontalApertureOffset() << ','
            << cam->verticalApertureOffset() << ',' << cam->clippingRange().x << ','
            << cam->clippingRange().y << ',' << int(cam->projection()) << ',' << cam->fStop() << ','
            << cam->focusDistance() << ',' << cam->apertureBlades() << ',' << cam->exposureScale();
    }
    bool restart = sv != _sceneVersion || setv != _settingsVersion || key.str() != _stateKey;
    _sceneVersion = sv;
    _settingsVersion = setv;
    _stateKey = key.str();
    return restart;
}

void EmbreeRenderPass::execute(const RenderPassState& state) {
    size_t pixels = size_t(std::max(0, state.width)) * size_t(std::max(0, state.height));
    if (needsRestart(state) || _lumSum.size() != pixels) {
        _samples = 0;
        _passes = 0;
        _converged = false;
        _causticPaths = 0;
        _causticBudget.reset();
        // Pixels outside the data window (UsdRender dataWindowNDC) are never sampled: they start
        // done and resolve to their AOV's clear value.
        const glm::ivec4 rect = state.framing.pixelRect(state.width, state.height);
        _pixelDone.assign(pixels, 1);
        for (int y = rect.y; y < rect.w; ++y)
            std::fill_n(_pixelDone.begin() + ptrdiff_t(size_t(y) * size_t(state.width) + size_t(rect.x)), rect.z - rect.x, 0);
        _active = size_t(rect.z - rect.x) * size_t(rect.w - rect.y);
        _lumSum.assign(pixels, 0.0);
        _lumSqSum.assign(pixels, 0.0);
        _pixelSamples.assign(pixels, 0);
        _frozenVariance.clear();  // (pixels outside a data window start done: no stale variance)
        _ltSum.clear();  // allocated by the first pass with light paths
        _ltN1.clear();
        _ltN2.clear();
        _ltPaths = _ltSpread = 0.0;
        _ltPasses = 0;
        for (const auto& b : state.aovBindings)
            if (auto* buf = dynamic_cast<EmbreeRenderBuffer*>(b.renderBuffer)) {
                if (auto info = findAov(b.aovName.str())) buf->setClearValue(info->clear);
                buf->clear();
            }
    }
    int rangeFirst = 0;
    _target = std::max(1, _delegate->samplesPerPixel());
    if (_rangeEnd > _rangeFirst) {
        rangeFirst = _rangeFirst;
        _target = _rangeEnd - _rangeFirst;
    }
    if (_converged) return;
    auto* cam = static_cast<Camera*>(renderIndex()->sprim(tokens::camera(), state.cameraId));
    if (!cam || pixels == 0) {
        _converged = true;  // nothing can be rendered: do not spin
        return;
    }
    // The bound buffers this pass can fill; others are reported once and left alone.
    std::vector<BoundAov> aovs;
    for (const auto& b : state.aovBindings) {
        auto* buf = dynamic_cast<EmbreeRenderBuffer*>(b.renderBuffer);
        auto info = findAov(b.aovName.str());
        std::string problem;
        if (!buf)
            problem = "is not bound to a buffer of this delegate";
        else if (!info)
            problem = "is not an AOV this delegate renders";
        else if (buf->width() != state.width || buf->height() != state.height)
            problem = "buffer size differs from the pass size";
        else if (buf->format() != info->format)
            problem = "buffer format does not match the AOV's format";
        if (!problem.empty()) {
            if (_reported.insert(b.aovName.str()).second)
                _delegate->warn(hd::Path("/__principled/aov/" + b.aovName.str()), "AOV '" + b.aovName.str() + "' " + problem + "; skipped");
            continue;
        }
        aovs.push_back({*info, buf});
    }

    const SceneSnapshot& scene = _delegate->snapshot();
    IntegratorSettings settings = _delegate->integratorSettings();
    settings.recorder = _recorder;
    settings.splitLobes = std::any_of(aovs.begin(), aovs.end(), [](const BoundAov& a) {
        switch (a.info.kind) {
            case AovKind::Diffuse: case AovKind::Sheen: case AovKind::Specular:
            case AovKind::Clearcoat: case AovKind::Transmission: return true;
            default: return false;
        }
    });
    for (auto& a : aovs) {
        if (a.info.kind != AovKind::Primvar) continue;
        std::string name;
        for (const auto& b : state.aovBindings)
            if (b.renderBuffer == a.buffer) name = b.aovName.str().substr(9);
        if (settings.aovPrimvars.size() < 4) {
            a.primvarSlot = int(settings.aovPrimvars.size());
            settings.aovPrimvars.emplace_back(name);
        }
    }
    // Caustic light tracing: casters and lights found again only when the content or settings change.
    const bool causticsWanted = settings.causticRoughness > 0.0f && settings.causticPaths > 0.0f;
    if (causticsWanted) {
        const unsigned content = _delegate->contentVersion(), set = _delegate->renderSettingsVersion();
        if (!_caustics || content != _causticContent || set != _causticSettings) {
            _caustics = std::make_unique<CausticScene>(scene, settings.bsdf, settings.causticRoughness);
            _causticContent = content;
            _causticSettings = set;
        }
        settings.caustics = _caustics.get();
    }
    Integrator integrator(scene, settings);
    long causticPathsThisPass = 0;
    uint32_t seed = static_cast<uint32_t>(_delegate->seed());
    glm::vec4 window = cam->screenWindow(state.width, state.height, state.framing);
    const float exposure = cam->exposureScale();  // the camera's exposure model, on all light AOVs
    const float lensRadius = cam->lensRadius();  // once per pass, not per ray
    const bool thinLens = lensRadius > 0.0f;
    CameraFrame cf = cameraFrame(*cam);
    // The first pass is a single sample so a viewport shows an image at once; later passes
    // double up to kMaxSamplesPerPass.
    int batch = std::min({_target - _samples, 1 << std::min(_passes, 4), kMaxSamplesPerPass});
    if (_passSampleLimit > 0) batch = std::min(batch, _passSampleLimit);
    int first = rangeFirst + _samples;
    std::atomic<long> rays{0}, invalid{0}, taken{0}, lightRays{0}, cameraRays{0};
    auto start = std::chrono::steady_clock::now();
    // Caustic light paths first: their photons serve this pass's camera paths.
    std::vector<float>& splat = _causticStorage.splat;
    std::vector<float>& lobeSplat = _causticStorage.lobeSplat;
    std::vector<Photon>& photons = _causticStorage.photons;
    photons.clear();
    const bool lobes = settings.splitLobes;
    if (integrator.causticsActive()) {
        // Caustic light paths: each is an estimate of every pixel's caustic share at once
        // (CameraConnection::importance), so a pixel's estimate is its splat sum over the paths
        // traced. It joins the pixel's mean as this pass's `batch` samples' share.
        const CameraConnector connector(*cam, state.width, state.height, window);
        // At most 2^20 paths a pass (photon memory); big frames get fewer per camera sample.
        // The first pass after a restart (the viewport's first image) traces an eighth: its
        // latency stays that of path tracing, and caustics path tracing cannot find at all (a
        // delta light through a mirror) are still in it.
        const double share = _passes == 0 ? 0.125 : 1.0;
        // Paths per camera sample: as many as make variance x cost least (delegate/causticBudget.h).
        const double perSample = settings.causticAdaptive
                                     ? _causticBudget.pathsPerSample(settings.causticPaths, pixels)
                                     : double(settings.causticPaths);
        const long paths = std::clamp(std::lround(share * perSample * batch * double(pixels)), 1L, 1L << 20);
        splat.assign(pixels * 3, 0.0f);
        lobeSplat.assign(lobes ? pixels * 3 * bsdf::kLobeCount : 0, 0.0f);
        // Sample ranges rendered apart (distributed frames) take their own scrambling of the
        // sequence, independent of the others'; a whole render (range 0) keeps the plain one.
        const uint64_t base = _causticPaths;
        const uint32_t causticSeed = seed ^ 0xa511e9b3u ^ (uint32_t(rangeFirst) * 0x9e3779b9u);
        // Splats are collected per chunk of paths and added in path order: the same image for
        // any thread count (float sums depend on their order). Batches bound the memory.
        constexpr long kChunk = 256, kBatch = 128 * kChunk;
        double splatSquares = 0.0;  // for the budget, summed in path order
        std::vector<std::vector<Integrator::Splat>>& chunkSplats = _causticStorage.chunkSplats;
        std::vector<std::vector<Photon>>& chunkPhotons = _causticStorage.chunkPhotons;
        chunkSplats.resize(size_t(kBatch / kChunk));
        chunkPhotons.resize(size_t(kBatch / kChunk));
        for (long b0 = 0; b0 < paths; b0 += kBatch) {
            const long b1 = std::min(paths, b0 + kBatch);
            const long chunks = (b1 - b0 + kChunk - 1) / kChunk;
            tbb::parallel_for(tbb::blocked_range<long>(0, chunks), [&](const tbb::blocked_range<long>& range) {
                long localRays = 0;
                for (long c = range.begin(); c < range.end(); ++c) {
                    std::vector<Integrator::Splat>& out = chunkSplats[size_t(c)];
                    std::vector<Photon>& outPhotons = chunkPhotons[size_t(c)];
                    out.clear();
                    outPhotons.clear();
                    for (long i = b0 + c * kChunk; i < std::min(b1, b0 + (c + 1) * kChunk); ++i) {
                        // One Owen-scrambled Sobol sequence over all light paths of the frame.
                        Sampler sampler(settings.sampler, causticSeed, 0u, uint32_t(base + uint64_t(i)));
                        const glm::vec2 uPos = sampler.next2D();
                        const float uLight = sampler.next1D(), uTarget = sampler.next1D();
                        const glm::vec2 uDir = sampler.next2D();
                        EmittedRay emitted;
                        if (!_caustics->sampleEmission(scene, uLight, uTarget, uPos, uDir, &emitted)) continue;
                        localRays += integrator.traceCaustic(emitted, sampler, connector,
                                                             [&](const Integrator::Splat& sp) { out.push_back(sp); },
                                                             [&](const Photon& ph) { outPhotons.push_back(ph); });
                    }
                }
                lightRays += localRays;
            });
            for (long c = 0; c < chunks; ++c) {
                photons.insert(photons.end(), chunkPhotons[size_t(c)].begin(), chunkPhotons[size_t(c)].end());
                for (const Integrator::Splat& sp : chunkSplats[size_t(c)]) {
                    const size_t p = size_t(sp.y) * size_t(state.width) + size_t(sp.x);
                    const double ls = luminance(sp.value) * exposure;  // in the pixel statistics' (exposed) units
                    // (Pixels adaptive sampling stopped keep no splats: not counted either.)
                    if (_pixelSamples[p] > 0 && !_pixelDone[p])
                        splatSquares += ls * ls * CausticBudget::displayWeight(_lumSum[p] / _pixelSamples[p]);
                    for (int k = 0; k < 3; ++k) splat[3 * p + k] += sp.value[k];
                    if (lobes)
                        for (int l = 0; l < bsdf::kLobeCount; ++l)
                            for (int k = 0; k < 3; ++k) lobeSplat[(p * bsdf::kLobeCount + l) * 3 + k] += sp.lobes[l][k];
                }
            }
        }
        _causticPaths += uint64_t(paths);
        causticPathsThisPass = paths;
        rays += lightRays;
        // The first pass after a restart has no pixel means to weight its splats with.
        if (_samples > 0) _causticBudget.addLightPaths(uint64_t(paths), uint64_t(lightRays.load()), splatSquares);
    }
    // The camera paths merge the photons within a radius that shrinks with the paths traced.
    if (!photons.empty()) {
        PhotonGrid& photonGrid = _causticStorage.grid;
        const double perSample = std::max(1.0, double(settings.causticPaths) * double(pixels));
        const float r0 = settings.causticMergeRadius > 0.0f ? settings.causticMergeRadius
                                                            : 0.05f * _caustics->meanTargetRadius();
        // Kept within the scene's scale: a huge radius would make every query visit every photon.
        const float rMax = 0.1f * _caustics->sceneRadius();
        const float r = std::clamp(r0 * float(std::pow(std::max(1.0, double(_causticPaths) / perSample), -1.0 / 6.0)),
                                   1e-6f * rMax, rMax);
        photonGrid.rebuild(photons, r);
        if (!photonGrid.empty())
            integrator.usePhotons(&photonGrid, float(1.0 / (double(causticPathsThisPass) * 3.14159265358979 * double(r) * r)));
    }
    // The caustic budget's per-pixel variance of this pass's samples (-1: none), summed after the
    // pass in pixel order so the budget, and the image, do not depend on the thread count.
    const bool budgetStats = causticPathsThisPass > 0 && settings.causticAdaptive && batch >= 2;
    if (budgetStats) _passVariance.assign(pixels, -1.0f);
    tbb::parallel_for(
        tbb::blocked_range2d<int>(0, state.height, kTileSize, 0, state.width, kTileSize),
        [&](const tbb::blocked_range2d<int>& tile) {
            long tileRays = 0, tileInvalid = 0, tileSamples = 0;
            for (int y = tile.rows().begin(); y < tile.rows().end(); ++y)
                for (int x = tile.cols().begin(); x < tile.cols().end(); ++x) {
                    uint32_t pixel = uint32_t(y) * uint32_t(state.width) + uint32_t(x);
                    if (_pixelDone[pixel]) continue;  // adaptive sampling: converged
                    double passSum = 0.0, passSquares = 0.0;  // this pass's samples (caustic budget)
                    const double weight = budgetStats && _pixelSamples[pixel] > 0
                                              ? CausticBudget::displayWeight(_lumSum[pixel] / _pixelSamples[pixel])
                                              : 1.0;
                    for (int s = first; s < first + batch; ++s) {
                        Sampler sampler(settings.sampler, seed, pixel, uint32_t(s));
                        glm::vec2 j = sampler.next2D();  // box filter: uniform in the pixel
                        // The lens point takes a Sobol group of its own, only when there is a lens
                        // (pinhole images keep their sample dimensions).
                        glm::vec2 lens = thinLens ? cam->apertureSample(sampler.next2D()) : glm::vec2(0.0f);
                        Ray r = cameraRay(*cam, window, state.width, state.height, x + j.x, y + j.y, lensRadius, lens);
                        PathSample ps = integrator.trace(r, sampler);
                        if (exposure != 1.0f) exposeSample(&ps, exposure);
                        tileRays += ps.rays;
                        ++tileSamples;
                        tileInvalid += ps.invalid;
                        for (const auto& a : aovs) writeSample(a, x, y, ps, cf);
                        double lum = luminance(ps.radiance);
                        _lumSum[pixel] += lum;
                        _lumSqSum[pixel] += lum * lum;
                        ++_pixelSamples[pixel];
                        passSum += lum;
                        passSquares += lum * lum;
                    }
                    if (budgetStats)
                        _passVariance[pixel] = float(CausticBudget::displayVariance(
                            weight * std::max(0.0, (passSquares - passSum * passSum / batch) / (batch - 1))));
                }
            cameraRays += tileRays;
            invalid += tileInvalid;
            taken += tileSamples;
        });
    rays += cameraRays;
    if (causticPathsThisPass > 0) {
        double varianceSum = 0.0;
        uint64_t varianceCount = 0;
        if (budgetStats)
            for (float v : _passVariance)
                if (v >= 0.0f) {
                    varianceSum += v;
                    ++varianceCount;
                }
        _causticBudget.addCameraSamples(uint64_t(taken.load()), uint64_t(cameraRays.load()), varianceSum, varianceCount);
        const long paths = causticPathsThisPass;
        if (_ltSum.size() != pixels) {
            _ltSum.assign(pixels, 0.0);
            _ltN1.assign(pixels, 0.0);
            _ltN2.assign(pixels, 0.0);
        }
        _ltPaths += double(paths);
        _ltSpread += double(batch) * batch / double(paths);
        ++_ltPasses;
        const float scale = float(batch) / float(paths) * exposure;
        for (int y = 0; y < state.height; ++y)
            for (int x = 0; x < state.width; ++x) {
                const size_t p = size_t(y) * size_t(state.width) + size_t(x);
                if (_pixelDone[p]) continue;  // took no samples this pass
                const glm::vec3 e = scale * glm::vec3(splat[3 * p], splat[3 * p + 1], splat[3 * p + 2]);
                if (e == glm::vec3(0.0f)) continue;
                for (const auto& a : aovs) {
                    if (a.info.kind == AovKind::Color) {
                        const float v[4] = {e.x, e.y, e.z, 0.0f};
                        a.buffer->addToSum(x, y, v);
                    } else if (lobes && a.info.kind >= AovKind::Diffuse && a.info.kind <= AovKind::Transmission) {
                        const int l = int(a.info.kind) - int(AovKind::Diffuse);
                        const float* q = &lobeSplat[(p * bsdf::kLobeCount + size_t(l)) * 3];
                        const float v[3] = {scale * q[0], scale * q[1], scale * q[2]};
                        a.buffer->addToSum(x, y, v);
                    }
                }
                // The pixel's luminance statistics get the mean's share; the light paths' own
                // variance is not in them.
                const double le = luminance(e), m = le / batch;
                _lumSum[p] += le;
                _ltSum[p] += le;
                _ltN1[p] += double(paths) * m;
                _ltN2[p] += double(paths) * m * m;
            }
    }
    double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // The photons served this pass only; their storage serves the next pass's light paths.
    _causticStorage.grid.release(_causticStorage.photons);
    _delegate->addPassStats(rays.load(), taken.load(), invalid.load(), seconds);
    if (!causticsWanted || (settings.caustics && !integrator.causticsActive() && _caustics->active()))
        _delegate->setCausticStats(-1, 0, 0);  // turned off by the settings
    else if (settings.caustics)
        _delegate->setCausticStats(long(_caustics->casterCount()), long(_caustics->lightCount()), causticPathsThisPass);
    _samples += batch;
    ++_passes;
    // Adaptive sampling: a pixel stops once the relative standard error of the mean luminance
    // over its 3x3 neighbourhood is below the threshold (after a minimum number of samples).
    // The neighbourhood matters: a pixel's own estimate decides little of it. Judged on its own
    // samples alone, a pixel that had not yet drawn its rare bright paths had a low variance and
    // stopped early, low: the Cornell box at 0.05 came out 1.2 % dark.
    float threshold = _delegate->noiseThreshold();
    if (threshold > 0.0f) {
        const int minSamples = adaptiveMinSamples(_delegate->minSamples(), threshold);
        std::vector<float> mean(pixels), variance(pixels);
        for (size_t p = 0; p < pixels; ++p) {
            mean[p] = _pixelSamples[p] > 0 ? float(_lumSum[p] / _pixelSamples[p]) : 0.0f;
            variance[p] = float(meanVariance(p));
        }
        size_t active = 0;
        for (size_t p = 0; p < pixels; ++p) {
            if (!_pixelDone[p] && _pixelSamples[p] >= minSamples) {
                const int x = int(p % size_t(state.width)), y = int(p / size_t(state.width));
                double m = 0.0, v = 0.0;
                int k = 0;
                for (int yy = std::max(0, y - 1); yy <= std::min(state.height - 1, y + 1); ++yy)
                    for (int xx = std::max(0, x - 1); xx <= std::min(state.width - 1, x + 1); ++xx) {
                        const size_t q = size_t(yy) * size_t(state.width) + size_t(xx);
                        m += mean[q], v += variance[q], ++k;
                    }
                // 1e-3: an absolute floor so black pixels converge instead of dividing by ~0.
                double rel = std::sqrt(v / k) / std::max(m / k, 1e-3);
                if (rel < threshold) {
                    // Its estimate stops changing, and so does its variance (the light-traced
                    // share's frame sums go on growing without it).
                    if (_frozenVariance.size() != pixels) _frozenVariance.assign(pixels, 0.0f);
                    _frozenVariance[p] = float(meanVariance(p));
                    _pixelDone[p] = 1;
                }
            }
            active += !_pixelDone[p];
        }
        _active = active;
    }
    _converged = _samples >= _target || _active == 0;
    for (const auto& a : aovs) {
        if (a.info.kind == AovKind::SampleCount || a.info.kind == AovKind::Variance) {
            for (int y = 0; y < state.height; ++y)
                for (int x = 0; x < state.width; ++x) {
                    size_t p = size_t(y) * state.width + x;
                    float v = float(_pixelSamples[p]);
                    if (a.info.kind == AovKind::Variance) v = float(meanVariance(p));
                    a.buffer->setPixel(x, y, &v);
                }
        }
        a.buffer->resolve();
        a.buffer->setConverged(_converged);
    }
}

double EmbreeRenderPass::meanVariance(size_t p) const {
    // Unbiased sample variance of the luminance divided by n: the variance of the pixel mean.
    // The light-traced share is not in the samples. Its passes' estimates m_k have variances
    // t^2 / N_k; t^2 comes from their spread about the N-weighted mean over the K passes, and
    // the image's sum over k of (b_k / n) m_k has variance t^2 (sum b_k^2 / N_k) / n^2. A pixel
    // that adaptive sampling stopped keeps the variance it had then (_frozenVariance).
    if (_pixelDone[p] && p < _frozenVariance.size()) return _frozenVariance[p];
    const long n = _pixelSamples[p];
    if (n < 2) return 0.0;
    const double lt = p < _ltSum.size() ? _ltSum[p] : 0.0, pt = _lumSum[p] - lt;
    const double mean = pt / n;
    double var = std::max(0.0, (_lumSqSum[p] - n * mean * mean) / (n - 1)) / n;
    if (lt != 0.0 && _ltPasses >= 2 && _ltPaths > 0.0) {
        const double t2 = std::max(0.0, (_ltN2[p] - _ltN1[p] * _ltN1[p] / _ltPaths) / (_ltPasses - 1));
        var += t2 * _ltSpread / (double(n) * n);
    }
    return var;
}

}  // namespace principled::embree

namespace principled::embree {

bool EmbreeRenderPass::setPixelStats(const PixelStats& stats, int completedSamples) {
    if (stats.lumSum.size() != _lumSum.size() || stats.lumSqSum.size() != _lumSqSum.size() ||
        stats.samples.size() != _pixelSamples.size())
        return false;
    _lumSum = stats.lumSum;
    _lumSqSum = stats.lumSqSum;
    _pixelSamples = stats.samples;
    _ltSum = stats.ltSum;
    _ltN1 = stats.ltN1;
    _ltN2 = stats.ltN2;
    _ltPaths = stats.ltPaths;
    _ltSpread = stats.ltSpread;
    _ltPasses = stats.ltPasses;
    if (_ltSum.size() != _lumSum.size() || _ltN1.size() != _lumSum.size() || _ltN2.size() != _lumSum.size()) {
        _ltSum.clear();  // none saved (no light paths, or an older checkpoint)
        _ltN1.clear();
        _ltN2.clear();
        _ltPaths = _ltSpread = 0.0;
        _ltPasses = 0;
    }
    _samples = std::max(0, completedSamples);
    // Resumed: the saved pass count keeps the batch sizes (and so the light paths' passes) of
    // an uninterrupted render; without one, full-size batches.
    _passes = stats.passes > 0 ? stats.passes : 5;
    // The light paths continue their sequence and their budget where the saved render stopped.
    _causticPaths = stats.causticPaths;
    _causticBudget.restore(stats.budget);
    _converged = _samples >= _target;
    return true;
}

void EmbreeRenderPass::setSampleRange(int first, int end) {
    _rangeFirst = std::max(0, first);
    _rangeEnd = std::max(0, end);
    _stateKey.clear();  // restart accumulation
}

}  // namespace principled::embree
