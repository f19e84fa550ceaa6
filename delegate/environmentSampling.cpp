// SPDX-License-Identifier: Apache-2.0
#include "delegate/environmentSampling.h"

#include <algorithm>
#include <cmath>

namespace principled::embree {
namespace {

constexpr float kPi = 3.14159265358979323846f;

float rowSin(int y, int height) { return std::sin(kPi * (float(y) + 0.5f) / float(height)); }

}  // namespace

std::vector<float> environmentWeights(const EnvironmentMap& env) {
    std::vector<float> w(env.texels.size());
    for (int y = 0; y < env.height; ++y) {
        const float sinTheta = rowSin(y, env.height);
        for (int x = 0; x < env.width; ++x) {
            const size_t i = size_t(y) * size_t(env.width) + size_t(x);
            const glm::vec3& c = env.texels[i];
            w[i] = (0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z) * sinTheta;
        }
    }
    return w;
}

void prepareEnvironmentSampling(EnvironmentMap& env) {
    env.latLong = env.width > 0 && env.height > 0 && env.texels.size() == size_t(env.width) * size_t(env.height);
    env.compensated = Distribution2D();
    if (!env.latLong) return;
    std::vector<float> w = environmentWeights(env);
    // The mean luminance over the sphere: the sin(theta)-weighted mean of the texels.
    double lumSinSum = 0.0, sinSum = 0.0;
    for (int y = 0; y < env.height; ++y) sinSum += double(rowSin(y, env.height)) * env.width;
    for (float v : w) lumSinSum += v;
    const float meanLum = sinSum > 0.0 ? float(lumSinSum / sinSum) : 0.0f;
    double kept = 0.0;
    for (int y = 0; y < env.height; ++y) {
        const float sinTheta = rowSin(y, env.height);
        for (int x = 0; x < env.width; ++x) {
            float& v = w[size_t(y) * size_t(env.width) + size_t(x)];
            v = std::max(0.0f, v - meanLum * sinTheta);
            kept += v;
        }
    }
    // A near-constant map keeps almost nothing above its mean: sampling that remnant would only
    // add noise, so the plain distribution stays in use.
    if (kept > 1e-3 * lumSinSum) env.compensated = Distribution2D(w, env.width, env.height);
}

const Distribution2D& EnvironmentMap::plain() const {
    std::call_once(*_plainOnce, [this] { _plain = Distribution2D(environmentWeights(*this), width, height); });
    return _plain;
}

}  // namespace principled::embree
