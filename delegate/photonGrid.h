// SPDX-License-Identifier: Apache-2.0
// Caustic photons (light-path vertices after a sharp scattering) in a uniform hash grid, for
// the density estimate that gives the path tracer the caustic light it leaves out at vertices
// after the first hit (photon mapping; Jensen 1996, "Global Illumination using Photon Maps").
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace principled::embree {

struct Photon {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f};   ///< geometric normal on the side the light arrived from
    glm::vec3 toLight{0.0f};  ///< unit direction back along the light path
    glm::vec3 power{0.0f};    ///< the light path's weight on arrival (EmittedRay::weight units)
    int sharpVertices = 0;    ///< sharp scatterings before it (for the bounce limit)
};

/// Photons binned in cells of twice the search radius; a query visits the 2x2x2 cells around
/// the point. Built once per pass, read-only while the pass shades.
class PhotonGrid {
public:
    PhotonGrid() = default;
    /// Photons in the order given (kept within a cell: queries visit them in that order, so
    /// results do not depend on thread scheduling).
    PhotonGrid(std::vector<Photon> photons, float radius) { rebuild(photons, radius); }
    /// The same for a new set, sorted in place and taken over; `photons` is left empty.
    void rebuild(std::vector<Photon>& photons, float radius);
    /// Empties the grid, handing its photon storage to `into` (cleared, capacity kept), so
    /// the next set is collected into it and one photon array serves every pass.
    void release(std::vector<Photon>& into);

    bool empty() const { return _photons.empty(); }
    float radius() const { return _radius; }
    size_t size() const { return _photons.size(); }

    /// Calls fn(photon) for every photon within the radius of p.
    template <typename Fn>
    void query(const glm::vec3& p, Fn&& fn) const {
        if (_photons.empty()) return;
        // Outside the photons' bounds (grown by the radius): nothing to visit.
        if (glm::any(glm::lessThan(p, _lo)) || glm::any(glm::greaterThan(p, _hi))) return;
        const glm::ivec3 base = cell(p * _invCell - 0.5f);
        const float r2 = _radius * _radius;
        uint32_t seen[8];
        for (int c = 0; c < 8; ++c) {
            const uint32_t h = hash(base + glm::ivec3(c & 1, (c >> 1) & 1, c >> 2));
            seen[c] = h;
            if (std::find(seen, seen + c, h) != seen + c) continue;  // two cells, one bucket
            for (uint32_t i = _start[h]; i < _start[h + 1]; ++i) {
                const Photon& ph = _photons[i];
                const glm::vec3 d = ph.position - p;
                if (glm::dot(d, d) <= r2) fn(ph);
            }
        }
    }

private:
    /// The integer cell of a point in cell units, clamped (no overflow far from the origin).
    static glm::ivec3 cell(const glm::vec3& g) {
        return glm::ivec3(glm::clamp(glm::floor(g), glm::vec3(-1e9f), glm::vec3(1e9f)));
    }
    uint32_t hash(const glm::ivec3& c) const {
        // Teschner et al. 2003, "Optimized Spatial Hashing for Collision Detection", section 4.
        const uint32_t h = (uint32_t(c.x) * 73856093u) ^ (uint32_t(c.y) * 19349663u) ^ (uint32_t(c.z) * 83492791u);
        return h & _mask;
    }

    std::vector<Photon> _photons;  ///< sorted by cell hash (stable: given order within a bucket)
    std::vector<uint32_t> _start;  ///< per hash bucket: first index into _photons; size buckets + 1
    std::vector<uint32_t> _key, _fill;  ///< build scratch (keys, then places), kept for the next rebuild
    glm::vec3 _lo{0.0f}, _hi{0.0f};  ///< the photons' bounds grown by the radius
    float _radius = 0.0f, _invCell = 0.0f;
    uint32_t _mask = 0;
};

}  // namespace principled::embree
