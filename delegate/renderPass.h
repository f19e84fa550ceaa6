// SPDX-License-Identifier: Apache-2.0
// EmbreeRenderPass: the progressive render pass. Each execute() adds a batch of samples per
// pixel over tiles scheduled on TBB and resolves the bound AOV buffers; accumulation restarts
// when the scene, the settings, the camera, the size or the bindings change.
#pragma once

#include <algorithm>
#include <atomic>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "delegate/causticBudget.h"
#include "delegate/hd/renderPass.h"
#include "delegate/integrator.h"
#include "delegate/photonGrid.h"
#include "delegate/pixelStats.h"
#include "delegate/rayRecorder.h"

namespace principled::embree {

class EmbreeRenderDelegate;
class CausticScene;

class EmbreeRenderPass : public hd::RenderPass {
public:
    EmbreeRenderPass(hd::RenderIndex* index, EmbreeRenderDelegate* delegate);
    ~EmbreeRenderPass() override;

    void execute(const hd::RenderPassState& state) override;
    bool isConverged() const override { return _converged; }

    /// Samples per pixel completed since the last restart.
    int completedSamples() const { return _samples; }
    /// Samples per pixel the pass converges at.
    int targetSamples() const { return _target; }

    /// Variance of pixel p's mean luminance (0 with fewer than 2 samples).
    double meanVariance(size_t p) const;

    /// Renders only sample indices [first, end) of the deterministic sequence (for splitting a
    /// frame across processes); end <= first restores the default [0, samplesPerPixel).
    void setSampleRange(int first, int end);
    /// Receives every ray the integrator casts (null: none).
    void setRayRecorder(RayRecorder* recorder) { _recorder = recorder; }
    /// The per-pixel statistics and pass state (delegate/pixelStats.h), for merging partial
    /// renders; set them to resume.
    using PixelStats = embree::PixelStats;
    PixelStats pixelStats() const {
        return {_lumSum, _lumSqSum, _pixelSamples, _ltSum, _ltN1, _ltN2, _ltPaths, _ltSpread, _ltPasses,
                _causticPaths, _causticBudget.state(), _passes};
    }
    bool setPixelStats(const PixelStats& stats, int completedSamples);

    /// Caps the samples per pixel of each following pass (0: none; passes double from 1 up to
    /// 16): a host with a deadline sizes the next pass to the time left (`--time-limit`). The
    /// samples rendered are the same sample indices either way.
    void setPassSampleLimit(int samples) { _passSampleLimit = std::max(0, samples); }

    /// Pixels still being sampled (adaptive sampling stops converged ones).
    size_t activePixels() const { return _active; }

private:
    bool needsRestart(const hd::RenderPassState& state);

    EmbreeRenderDelegate* _delegate;
    int _samples = 0;
    int _target = 0;
    int _passes = 0;
    int _passSampleLimit = 0;  ///< setPassSampleLimit
    bool _converged = false;
    // What the accumulated samples were rendered with.
    unsigned _sceneVersion = 0, _settingsVersion = 0;
    std::string _stateKey;
    // Per-pixel luminance statistics (variance AOV, convergence, adaptive sampling).
    std::vector<double> _lumSum, _lumSqSum;
    std::vector<int> _pixelSamples;
    /// The light-traced share's own noise for meanVariance (its splats are not samples of the
    /// pixel). Per pixel, over the passes k with N_k light paths, batch b_k and the pass's
    /// estimate m_k of the share: sum b_k m_k (its part of _lumSum), sum N_k m_k and sum
    /// N_k m_k^2; for the frame: sum N_k, sum b_k^2 / N_k and the count of such passes.
    std::vector<double> _ltSum, _ltN1, _ltN2;
    double _ltPaths = 0.0, _ltSpread = 0.0;
    int _ltPasses = 0;
    std::vector<float> _frozenVariance;  ///< meanVariance of pixels adaptive sampling stopped
    std::set<std::string> _reported;
    std::vector<uint8_t> _pixelDone;
    size_t _active = 0;
    int _rangeFirst = 0, _rangeEnd = 0;
    RayRecorder* _recorder = nullptr;
    // Caustic light tracing: the casters and lights of the current scene content and settings,
    // and the light paths traced since the last restart (their Sobol indices continue).
    std::unique_ptr<CausticScene> _caustics;
    unsigned _causticContent = ~0u, _causticSettings = ~0u;
    uint64_t _causticPaths = 0;
    CausticBudget _causticBudget;       ///< light paths per camera sample (causticAdaptive)
    std::vector<float> _passVariance;  ///< per pixel, this pass's sample variance (the budget's)
    /// A pass's light-path results, kept between passes so their memory is reused.
    struct CausticStorage {
        std::vector<float> splat, lobeSplat;  ///< per pixel (and lobe): the splats' sums
        std::vector<std::vector<Integrator::Splat>> chunkSplats;
        std::vector<std::vector<Photon>> chunkPhotons;
        std::vector<Photon> photons;  ///< all chunks' photons in path order
        PhotonGrid grid;
    } _causticStorage;
};

}  // namespace principled::embree
