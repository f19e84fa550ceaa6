// SPDX-License-Identifier: Apache-2.0
#include "delegate/photonGrid.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <vector>

namespace principled::embree {

PhotonGrid::PhotonGrid(std::vector<Photon> photons, float radius) : _photons(std::move(photons)) {
    std::erase_if(_photons, [](const Photon& p) {
        return !std::isfinite(p.position.x) || !std::isfinite(p.position.y) || !std::isfinite(p.position.z);
    });
    if (_photons.empty() || !(radius > 0.0f) || !std::isfinite(radius)) {
        _photons.clear();
        return;
    }
    _radius = radius;
    _lo = glm::vec3(std::numeric_limits<float>::max());
    _hi = -_lo;
    for (const Photon& ph : _photons) {
        _lo = glm::min(_lo, ph.position);
        _hi = glm::max(_hi, ph.position);
    }
    _lo -= radius;
    _hi += radius;
    _invCell = 1.0f / (2.0f * radius);
    const uint32_t buckets = std::bit_ceil(uint32_t(std::max<size_t>(64, 2 * _photons.size())));
    _mask = buckets - 1;
    std::vector<uint32_t> key(_photons.size());
    _start.assign(size_t(buckets) + 1, 0);
    for (size_t i = 0; i < _photons.size(); ++i) {
        key[i] = hash(cell(_photons[i].position * _invCell));
        ++_start[key[i] + 1];
    }
    for (uint32_t b = 0; b < buckets; ++b) _start[b + 1] += _start[b];
    _order.resize(_photons.size());
    std::vector<uint32_t> fill(_start.begin(), _start.end() - 1);
    for (size_t i = 0; i < _photons.size(); ++i) _order[fill[key[i]]++] = uint32_t(i);  // stable
}

}  // namespace principled::embree
