// SPDX-License-Identifier: Apache-2.0
// Distribution2D: piecewise-constant 2D sampling (marginal over rows, conditional per row),
// used to importance-sample a lat-long environment by its luminance.
#pragma once

#include <vector>

#include <glm/glm.hpp>

namespace principled::embree {

class Distribution2D {
public:
    Distribution2D() = default;
    /// weights: width*height non-negative values, row-major. All-zero or non-finite input gives
    /// a uniform distribution.
    Distribution2D(const std::vector<float>& weights, int width, int height);

    /// Maps u in [0,1)^2 to a point in [0,1)^2 with density pdf(point) (w.r.t. area of [0,1]^2).
    glm::vec2 sample(const glm::vec2& u, float* pdf) const;
    float pdf(const glm::vec2& p) const;
    bool empty() const { return _width == 0; }
    int width() const { return _width; }
    int height() const { return _height; }

private:
    int _width = 0, _height = 0;
    std::vector<float> _conditionalCdf;  // height rows of (width + 1)
    std::vector<float> _rowFunc;          // width*height normalised weights per row
    std::vector<float> _rowIntegral;      // per row
    std::vector<float> _marginalCdf;      // height + 1
    float _integral = 0.0f;
};

}  // namespace principled::embree
