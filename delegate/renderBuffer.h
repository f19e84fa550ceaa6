// SPDX-License-Identifier: Apache-2.0
// EmbreeRenderBuffer: an AOV image that accumulates samples. Multi-sampled buffers keep a
// per-pixel sum and count and resolve to the mean; single-sampled ones keep the first sample
// (IDs, depth), so edges are exact and never averaged.
#pragma once

#include <cstdint>
#include <vector>

#include "delegate/hd/renderBuffer.h"

namespace principled::embree {

class EmbreeRenderBuffer : public hd::RenderBuffer {
public:
    using RenderBuffer::RenderBuffer;

    bool allocate(int width, int height, hd::Format format, bool multiSampled) override;
    int width() const override { return _width; }
    int height() const override { return _height; }
    hd::Format format() const override { return _format; }
    bool isMultiSampled() const override { return _multiSampled; }
    const void* map() override;
    void resolve() override;
    bool isConverged() const override { return _converged; }
    void setConverged(bool c) { _converged = c; }

    /// Clears accumulation (the resolved image keeps its last content until resolve()).
    void clear();
    /// Value resolved for pixels that received no sample (default 0; IDs -1).
    void setClearValue(float v) { _clearValue = v; }
    /// Adds one sample to pixel (x, y): componentCount(format) values. Thread-safe for
    /// distinct pixels.
    void addSample(int x, int y, const float* values);
    void addSample(int x, int y, int32_t value);
    /// Adds values to pixel (x, y)'s sum without counting a sample (multi-sampled float buffers
    /// only): light tracing's share of the samples the pass already added there.
    void addToSum(int x, int y, const float* values);
    /// Overwrites pixel (x, y) with one value per component, counted as one sample (for
    /// statistics the pass computes itself, e.g. sampleCount and variance).
    void setPixel(int x, int y, const float* values);
    /// Raw accumulation, for merging partial renders of disjoint sample ranges (another process,
    /// a checkpoint): float sums (or first samples), int32 first samples, per-pixel counts.
    const std::vector<double>& sums() const { return _sum; }
    const std::vector<int32_t>& ints() const { return _ints; }
    const std::vector<int32_t>& counts() const { return _count; }
    /// Replaces the accumulation; sizes must match the allocation (returns false otherwise).
    bool setAccumulation(std::vector<double> sums, std::vector<int32_t> ints, std::vector<int32_t> counts);
    /// Samples accumulated at a pixel.
    int sampleCount(int x, int y) const { return _count[size_t(y) * _width + x]; }

private:
    int _width = 0, _height = 0, _components = 0;
    hd::Format _format = hd::Format::Invalid;
    bool _multiSampled = true;
    bool _converged = false;
    float _clearValue = 0.0f;
    std::vector<double> _sum;     // float formats: sum (multi) or first sample (single)
    std::vector<int32_t> _ints;   // Int32 format: first sample
    std::vector<int32_t> _count;
    std::vector<float> _resolved;
};

}  // namespace principled::embree
