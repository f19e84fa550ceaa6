// SPDX-License-Identifier: Apache-2.0
#include "delegate/renderPass.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <sstream>

#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include "delegate/hd/camera.h"
#include "delegate/hd/renderIndex.h"
#include "delegate/hd/tokens.h"
#include "delegate/integrator.h"
#include "delegate/renderBuffer.h"
#include "delegate/renderDelegate.h"
#include "delegate/sampler.h"

namespace principled::embree {

using namespace hd;

namespace {

constexpr int kTileSize = 16;
constexpr int kMaxSamplesPerPass = 16;

// A camera ray through image position (px, py) in pixels, top-left origin.
Ray cameraRay(const Camera& cam, const glm::vec4& window, int width, int height, float px,
              float py) {
    float sx = window.x + (px / width) * (window.y - window.x);
    float sy = window.w - (py / height) * (window.w - window.z);
    const glm::dmat4& m = cam.transform();
    glm::dvec3 o, d;
    if (cam.projection() == Camera::Projection::Orthographic) {
        o = glm::dvec3(m * glm::dvec4(sx, sy, 0.0, 1.0));
        d = glm::dvec3(m * glm::dvec4(0.0, 0.0, -1.0, 0.0));
    } else {
        o = glm::dvec3(m * glm::dvec4(0.0, 0.0, 0.0, 1.0));
        d = glm::dvec3(m * glm::dvec4(sx, sy, -1.0, 0.0));
    }
    double len = glm::length(d);
    Ray r;
    r.origin = glm::vec3(o);
    r.direction = glm::vec3(d / len);
    // The clipping range is along -z in camera space; d has z = -1, so t scales with |d|.
    glm::vec2 clip = cam.clippingRange();
    r.tnear = cam.projection() == Camera::Projection::Orthographic ? 0.0f : float(clip.x * len);
    r.tfar = float(clip.y * len);
    if (!(r.tnear >= 0.0f) || !std::isfinite(r.tnear)) r.tnear = 0.0f;
    if (!(r.tfar > r.tnear) || !std::isfinite(r.tfar)) r.tfar = 1e30f;
    return r;
}

}  // namespace

bool EmbreeRenderPass::needsRestart(const RenderPassState& state) {
    unsigned sv = renderIndex()->changeTracker().sceneVersion();
    unsigned setv = _delegate->renderSettingsVersion();
    std::ostringstream key;
    key << state.cameraId.str() << '|' << state.width << 'x' << state.height;
    for (const auto& b : state.aovBindings) key << '|' << b.aovName.str() << '@' << b.renderBuffer;
    if (auto* cam = static_cast<Camera*>(renderIndex()->sprim(tokens::camera(), state.cameraId))) {
        const double* m = &cam->transform()[0][0];
        for (int i = 0; i < 16; ++i) key << ',' << m[i];
        key << ',' << cam->focalLength() << ',' << cam->horizontalAperture() << ','
            << cam->verticalAperture();
    }
    bool restart = sv != _sceneVersion || setv != _settingsVersion || key.str() != _stateKey;
    _sceneVersion = sv;
    _settingsVersion = setv;
    _stateKey = key.str();
    return restart;
}

void EmbreeRenderPass::execute(const RenderPassState& state) {
    if (needsRestart(state)) {
        _samples = 0;
        _passes = 0;
        _converged = false;
        for (const auto& b : state.aovBindings)
            if (auto* buf = dynamic_cast<EmbreeRenderBuffer*>(b.renderBuffer)) buf->clear();
    }
    _target = std::max(1, _delegate->samplesPerPixel());
    if (_converged) return;
    auto* cam = static_cast<Camera*>(renderIndex()->sprim(tokens::camera(), state.cameraId));
    if (!cam || state.width <= 0 || state.height <= 0) {
        _converged = true;  // nothing can be rendered: do not spin
        return;
    }
    // Bound buffers this pass knows how to fill (others stay at their clear value).
    EmbreeRenderBuffer* color = nullptr;
    for (const auto& b : state.aovBindings) {
        auto* buf = dynamic_cast<EmbreeRenderBuffer*>(b.renderBuffer);
        if (!buf || buf->width() != state.width || buf->height() != state.height) continue;
        if (b.aovName == tokens::color() && componentCount(buf->format()) == 4) color = buf;
    }

    const SceneSnapshot& scene = _delegate->snapshot();
    IntegratorSettings settings = _delegate->integratorSettings();
    Integrator integrator(scene, settings);
    uint32_t seed = static_cast<uint32_t>(_delegate->seed());
    glm::vec4 window = cam->screenWindow(double(state.width) / double(state.height));
    // The first pass is a single sample so a viewport shows an image at once; later passes
    // double up to kMaxSamplesPerPass.
    int batch = std::min({_target - _samples, 1 << std::min(_passes, 4), kMaxSamplesPerPass});
    int first = _samples;
    std::atomic<long> rays{0}, invalid{0};
    auto start = std::chrono::steady_clock::now();
    tbb::parallel_for(
        tbb::blocked_range2d<int>(0, state.height, kTileSize, 0, state.width, kTileSize),
        [&](const tbb::blocked_range2d<int>& tile) {
            long tileRays = 0, tileInvalid = 0;
            for (int y = tile.rows().begin(); y < tile.rows().end(); ++y)
                for (int x = tile.cols().begin(); x < tile.cols().end(); ++x) {
                    uint32_t pixel = uint32_t(y) * uint32_t(state.width) + uint32_t(x);
                    for (int s = first; s < first + batch; ++s) {
                        Sampler sampler(seed, pixel, uint32_t(s));
                        glm::vec2 j = sampler.next2D();  // box filter: uniform in the pixel
                        Ray r = cameraRay(*cam, window, state.width, state.height, x + j.x, y + j.y);
                        PathSample ps = integrator.trace(r, sampler);
                        tileRays += ps.rays;
                        tileInvalid += ps.invalid;
                        float c[4] = {ps.radiance.x, ps.radiance.y, ps.radiance.z, ps.alpha};
                        if (color) color->addSample(x, y, c);
                    }
                }
            rays += tileRays;
            invalid += tileInvalid;
        });
    double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    _delegate->addPassStats(rays.load(), long(batch) * state.width * state.height, invalid.load(),
                            seconds);
    _samples += batch;
    ++_passes;
    _converged = _samples >= _target;
    for (const auto& b : state.aovBindings)
        if (auto* buf = dynamic_cast<EmbreeRenderBuffer*>(b.renderBuffer)) {
            buf->resolve();
            buf->setConverged(_converged);
        }
}

}  // namespace principled::embree
