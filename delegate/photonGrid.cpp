// SPDX-License-Identifier: Apache-2.0
#include "delegate/photonGrid.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <vector>

namespace principled::embree {

void PhotonGrid::rebuild(std::vector<Photon>& photons, float radius) {
    std::erase_if(photons, [](const Photon& p) {
        return !std::isfinite(p.position.x) || !std::isfinite(p.position.y) || !std::isfinite(p.position.z);
    });
    _photons.clear();
    _radius = 0.0f;
    if (photons.empty() || !(radius > 0.0f) || !std::isfinite(radius)) {
        photons.clear();
        return;
    }
    _radius = radius;
    _lo = glm::vec3(std::numeric_limits<float>::max());
    _hi = -_lo;
    for (const Photon& ph : photons) {
        _lo = glm::min(_lo, ph.position);
        _hi = glm::max(_hi, ph.position);
    }
    _lo -= radius;
    _hi += radius;
    _invCell = 1.0f / (2.0f * radius);
    const uint32_t buckets = std::bit_ceil(uint32_t(std::max<size_t>(64, 2 * photons.size())));
    _mask = buckets - 1;
    // Counting sort by bucket, stable, in place (queries then need no index indirection, and
    // no second photon array is held): _key[i] becomes photon i's place, then the permutation
    // is applied by following its cycles.
    const size_t n = photons.size();
    _key.resize(n);
    _start.assign(size_t(buckets) + 1, 0);
    for (size_t i = 0; i < n; ++i) {
        _key[i] = hash(cell(photons[i].position * _invCell));
        ++_start[_key[i] + 1];
    }
    for (uint32_t b = 0; b < buckets; ++b) _start[b + 1] += _start[b];
    _fill.assign(_start.begin(), _start.end() - 1);
    for (size_t i = 0; i < n; ++i) _key[i] = _fill[_key[i]]++;
    for (size_t i = 0; i < n; ++i)
        while (_key[i] != i) {
            const uint32_t j = _key[i];
            std::swap(photons[i], photons[j]);
            std::swap(_key[i], _key[j]);
        }
    _photons.swap(photons);
    photons.clear();
}

void PhotonGrid::release(std::vector<Photon>& into) {
    into.swap(_photons);
    into.clear();
    _photons = std::vector<Photon>();
}

}  // namespace principled::embree
