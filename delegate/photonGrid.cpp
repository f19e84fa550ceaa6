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
    // Counting sort by bucket, stable, straight into the grid's array (no index indirection).
    _key.resize(photons.size());
    _start.assign(size_t(buckets) + 1, 0);
    for (size_t i = 0; i < photons.size(); ++i) {
        _key[i] = hash(cell(photons[i].position * _invCell));
        ++_start[_key[i] + 1];
    }
    for (uint32_t b = 0; b < buckets; ++b) _start[b + 1] += _start[b];
    _fill.assign(_start.begin(), _start.end() - 1);
    _photons.resize(photons.size());
    for (size_t i = 0; i < photons.size(); ++i) _photons[_fill[_key[i]]++] = photons[i];
    photons.clear();
}

}  // namespace principled::embree
