// SPDX-License-Identifier: Apache-2.0
#include "delegate/distribution2d.h"

#include <algorithm>
#include <cmath>

namespace principled::embree {
namespace {

// Builds a CDF over n cells of f (Pharr et al., "Physically Based Rendering", 4th ed., §A.1:
// piecewise-constant 1D distributions); returns the integral over [0,1].
float buildCdf(const float* f, int n, float* cdf) {
    cdf[0] = 0.0f;
    for (int i = 0; i < n; ++i) cdf[i + 1] = cdf[i] + f[i] / float(n);
    float integral = cdf[n];
    if (!(integral > 0.0f) || !std::isfinite(integral)) {
        for (int i = 1; i <= n; ++i) cdf[i] = float(i) / float(n);
        return 0.0f;
    }
    for (int i = 1; i <= n; ++i) cdf[i] /= integral;
    cdf[n] = 1.0f;
    return integral;
}

// Finds the cell of u in a CDF and the position within it.
int findCell(const float* cdf, int n, float u, float* within) {
    int lo = int(std::upper_bound(cdf, cdf + n + 1, u) - cdf) - 1;
    lo = std::clamp(lo, 0, n - 1);
    float width = cdf[lo + 1] - cdf[lo];
    *within = width > 0.0f ? (u - cdf[lo]) / width : 0.5f;
    return lo;
}

}  // namespace

Distribution2D::Distribution2D(const std::vector<float>& weights, int width, int height)
    : _width(width), _height(height) {
    if (width <= 0 || height <= 0 || weights.size() < size_t(width) * height) {
        _width = _height = 0;
        return;
    }
    _rowFunc.resize(size_t(width) * height);
    for (size_t i = 0; i < _rowFunc.size(); ++i) {
        float w = weights[i];
        _rowFunc[i] = (std::isfinite(w) && w > 0.0f) ? w : 0.0f;
    }
    _conditionalCdf.resize(size_t(width + 1) * height);
    _rowIntegral.resize(height);
    for (int y = 0; y < height; ++y)
        _rowIntegral[y] = buildCdf(&_rowFunc[size_t(y) * width], width, &_conditionalCdf[size_t(y) * (width + 1)]);
    _marginalCdf.resize(height + 1);
    _integral = buildCdf(_rowIntegral.data(), height, _marginalCdf.data());
    if (!(_integral > 0.0f)) {
        // Uniform fallback.
        std::fill(_rowFunc.begin(), _rowFunc.end(), 1.0f);
        for (int y = 0; y < height; ++y)
            _rowIntegral[y] = buildCdf(&_rowFunc[size_t(y) * width], width, &_conditionalCdf[size_t(y) * (width + 1)]);
        _integral = buildCdf(_rowIntegral.data(), height, _marginalCdf.data());
    }
}

glm::vec2 Distribution2D::sample(const glm::vec2& u, float* pdfOut) const {
    float dy, dx;
    int y = findCell(_marginalCdf.data(), _height, u.y, &dy);
    const float* cdf = &_conditionalCdf[size_t(y) * (_width + 1)];
    int x = findCell(cdf, _width, u.x, &dx);
    glm::vec2 p((x + dx) / _width, (y + dy) / _height);
    *pdfOut = _integral > 0.0f ? _rowFunc[size_t(y) * _width + x] / _integral : 0.0f;
    return p;
}

float Distribution2D::pdf(const glm::vec2& p) const {
    if (_width == 0 || !(_integral > 0.0f)) return 0.0f;
    int x = std::clamp(int(p.x * _width), 0, _width - 1);
    int y = std::clamp(int(p.y * _height), 0, _height - 1);
    return _rowFunc[size_t(y) * _width + x] / _integral;
}

}  // namespace principled::embree
