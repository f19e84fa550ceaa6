// SPDX-License-Identifier: Apache-2.0
#include "delegate/renderBuffer.h"

#include <cmath>

namespace principled::embree {

bool EmbreeRenderBuffer::allocate(int width, int height, hd::Format format, bool multiSampled) {
    int c = hd::componentCount(format);
    if (width <= 0 || height <= 0 || c == 0 || size_t(width) * size_t(height) > (size_t(1) << 28))
        return false;
    _width = width;
    _height = height;
    _format = format;
    _components = c;
    _multiSampled = multiSampled && format != hd::Format::Int32;
    size_t n = size_t(width) * size_t(height);
    _sum.assign(format == hd::Format::Int32 ? 0 : n * c, 0.0);
    _ints.assign(format == hd::Format::Int32 ? n : 0, -1);
    _count.assign(n, 0);
    _resolved.assign(format == hd::Format::Int32 ? 0 : n * c, 0.0f);
    _converged = false;
    _clearValue = format == hd::Format::Int32 ? -1.0f : 0.0f;  // IDs: -1 means "nothing"
    return true;
}

void EmbreeRenderBuffer::clear() {
    std::fill(_sum.begin(), _sum.end(), 0.0);
    std::fill(_ints.begin(), _ints.end(), static_cast<int32_t>(_clearValue));
    std::fill(_count.begin(), _count.end(), 0);
    _converged = false;
}

void EmbreeRenderBuffer::addSample(int x, int y, const float* values) {
    size_t p = size_t(y) * _width + x;
    double* s = &_sum[p * _components];
    if (_multiSampled) {
        for (int i = 0; i < _components; ++i) s[i] += values[i];
    } else if (_count[p] == 0) {
        for (int i = 0; i < _components; ++i) s[i] = values[i];
    }
    ++_count[p];
}

void EmbreeRenderBuffer::addToSum(int x, int y, const float* values) {
    if (!_multiSampled || _format == hd::Format::Int32) return;
    double* s = &_sum[(size_t(y) * _width + x) * _components];
    for (int i = 0; i < _components; ++i) s[i] += values[i];
}

void EmbreeRenderBuffer::addSample(int x, int y, int32_t value) {
    size_t p = size_t(y) * _width + x;
    if (_count[p] == 0) _ints[p] = value;
    ++_count[p];
}

void EmbreeRenderBuffer::setPixel(int x, int y, const float* values) {
    size_t p = size_t(y) * _width + x;
    if (_format == hd::Format::Int32) {
        _ints[p] = static_cast<int32_t>(values[0]);
    } else {
        for (int i = 0; i < _components; ++i) _sum[p * _components + i] = values[i];
    }
    _count[p] = _multiSampled ? 1 : std::max(_count[p], 1);
}

bool EmbreeRenderBuffer::setAccumulation(std::vector<double> sums, std::vector<int32_t> ints,
                                         std::vector<int32_t> counts) {
    if (sums.size() != _sum.size() || ints.size() != _ints.size() || counts.size() != _count.size())
        return false;
    _sum = std::move(sums);
    _ints = std::move(ints);
    _count = std::move(counts);
    return true;
}

void EmbreeRenderBuffer::resolve() {
    if (_format == hd::Format::Int32) return;
    size_t n = size_t(_width) * _height;
    for (size_t p = 0; p < n; ++p) {
        if (_count[p] == 0) {
            for (int i = 0; i < _components; ++i) _resolved[p * _components + i] = _clearValue;
            continue;
        }
        double inv = _multiSampled ? 1.0 / _count[p] : 1.0;
        for (int i = 0; i < _components; ++i) {
            float v = static_cast<float>(_sum[p * _components + i] * inv);
            _resolved[p * _components + i] = std::isfinite(v) ? v : 0.0f;  // never NaN/Inf
        }
    }
}

const void* EmbreeRenderBuffer::map() {
    if (_format == hd::Format::Int32) return _ints.data();
    return _resolved.data();
}

}  // namespace principled::embree
