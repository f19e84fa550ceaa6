// SPDX-License-Identifier: Apache-2.0
// SubdivTopology: a mesh topology refined once with OpenSubdiv (Far), re-posed by stencils.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

#include "delegate/hd/meshTopology.h"
#include "delegate/subdiv/refinedMesh.h"
#include "delegate/subdiv/stencils.h"

namespace principled::subdiv {

/// Face-varying topology of one primvar channel (e.g. indexed st): one value index per
/// face-vertex, parallel to faceVertexIndices, into valueCount values.
struct FaceVaryingChannel {
    std::vector<int> indices;
    size_t valueCount = 0;

    bool operator==(const FaceVaryingChannel&) const = default;
};

struct BuildOptions {
    int level = 1;  ///< uniform level; 0 = the cage itself (fan triangles, no normals)
    std::vector<FaceVaryingChannel> faceVarying;
    bool varying = true;  ///< also build the varying (linear) stencils
    /// Refinement as one flattened Far::StencilTableFactory table per interpolation instead of
    /// one small table per level. Same results; the reference path, kept for comparison
    /// (about 2x the refinement-stencil memory and a slower build and re-pose).
    bool flatStencils = false;
    /// Face budget, so bad or hostile input cannot allocate without bound: a level whose
    /// refinement would exceed it is lowered (with a warning). 8M faces is 16M triangles,
    /// about 3.5 GB at the ~230 bytes per triangle measured with one st channel.
    size_t maxRefinedFaces = size_t(8) << 20;

    bool operator==(const BuildOptions&) const = default;
};

enum class Scheme { None, CatmullClark, Loop, Bilinear };

/// Where build time went (seconds), for docs/subdivision.md and profiling. The stencil
/// phases (vertex, varying, limit masks, each fvar channel) run as concurrent tasks, so they
/// can add up to more than `total`.
struct BuildTimings {
    double refiner = 0;         ///< TopologyRefinerFactory::Create + RefineUniform
    double vertexStencils = 0;  ///< StencilTableFactory, vertex interpolation
    double varyingStencils = 0;
    double limitMasks = 0;   ///< position + tangent masks
    double faceVarying = 0;  ///< fvar stencils + limit masks, all channels
    double triangles = 0;    ///< coarse-face map, triangles, fvar corners
    double total = 0;
};

/// One topology (hd::MeshTopology + hd::SubdivTags + level + face-varying channels) refined
/// uniformly with OpenSubdiv, reduced to stencil tables. Building does the expensive work
/// once (TopologyRefiner, RefineUniform, per-level stencil tables, limit masks) and then drops the
/// refiner; every refine*() call only applies cached stencils, so re-posing an animated cage
/// costs milliseconds. A SubdivTopology is immutable: all methods are const and may be called
/// concurrently. Rebuild it when topology, tags, level or face-varying indices change
/// (matches() tells).
///
/// Scheme "none" and level 0 give the cage itself: points copied, fan-triangulated faces,
/// no normals (the caller computes them as for any polygon mesh).
///
/// refine() and the primvar calls keep per-thread scratch buffers (about 12 bytes per refined
/// point for positions) so that re-posing does not fault in fresh pages every frame; they stay
/// allocated at the largest size a thread has used.
/// Faces after `level` uniform steps: a quad-splitting scheme turns an n-gon into n quads and
/// then quadruples them; loop quadruples triangles. What SubdivTopology's face budget
/// (BuildOptions::maxRefinedFaces) is checked against.
size_t refinedFaceEstimate(const hd::MeshTopology& t, bool loop, int level);

class SubdivTopology {
  public:
    /// Validates and builds. Returns nullptr with *error for unusable topology (bad counts,
    /// out-of-range indices, faces < 3 vertices, topology OpenSubdiv rejects). Recoverable
    /// problems (bad creases, corners, holes, unknown tokens, loop on non-triangles, a bad
    /// face-varying channel, a level lowered to fit maxRefinedFaces) become warnings().
    static std::unique_ptr<SubdivTopology> create(const hd::MeshTopology& topology,
                                                  const hd::SubdivTags& tags, size_t pointCount,
                                                  const BuildOptions& options, std::string* error);

    /// True when create() with these inputs would build the same thing (compares copies).
    bool matches(const hd::MeshTopology& topology, const hd::SubdivTags& tags, size_t pointCount,
                 const BuildOptions& options) const;

    /// Re-poses: refined (limit) points and normals for these cage points; copies the
    /// triangles and triangle -> coarse face map unless out already holds them (topologyId).
    /// False with *error when coarsePoints.size() != coarsePointCount().
    bool refine(const std::vector<glm::vec3>& coarsePoints, RefinedMesh* out,
                std::string* error = nullptr) const;

    /// Vertex-interpolated primvar (count == coarsePointCount() elements of `components`
    /// floats) -> one element per refined point, with the same stencils as the points.
    bool refineVertex(const float* values, size_t count, int components, std::vector<float>* out,
                      std::string* error = nullptr) const;
    /// Varying primvar: linear interpolation -> one element per refined point.
    bool refineVarying(const float* values, size_t count, int components, std::vector<float>* out,
                       std::string* error = nullptr) const;
    /// Face-varying primvar of BuildOptions::faceVarying[channel] (count == valueCount values)
    /// -> one element per refined triangle corner (3 * triangleCount() elements), honouring
    /// faceVaryingLinearInterpolation.
    bool refineFaceVarying(int channel, const float* values, size_t count, int components,
                           std::vector<float>* out, std::string* error = nullptr) const;
    /// The same primvar as its refined (limit) values, one element per face-varying value of
    /// the last level, without the per-corner gather: faceVaryingCorners(channel) gives the
    /// value of each triangle corner. Same floats as refineFaceVarying().
    bool refineFaceVaryingValues(int channel, const float* values, size_t count, int components,
                                 std::vector<float>* out, std::string* error = nullptr) const;
    /// Value index of each triangle corner of channel (3 per triangle), into
    /// refineFaceVaryingValues() output; null for an unavailable channel. Immutable and shared,
    /// so a record can keep it instead of a per-corner copy of the values.
    std::shared_ptr<const std::vector<int>> faceVaryingCorners(int channel) const;
    /// Uniform (per coarse face) primvar -> one element per refined triangle.
    bool refineUniform(const float* values, size_t count, int components, std::vector<float>* out,
                       std::string* error = nullptr) const;

    Scheme scheme() const { return _scheme; }  ///< after fallbacks (loop -> catmullClark)
    int level() const { return _level; }       ///< 0 for the cage
    bool subdivided() const { return _level > 0; }
    size_t coarsePointCount() const { return _pointCount; }
    size_t coarseFaceCount() const { return _topology.faceVertexCounts.size(); }
    size_t refinedPointCount() const { return _refinedPoints; }
    size_t triangleCount() const { return _triangles.size(); }
    const std::vector<glm::uvec3>& triangles() const { return _triangles; }
    const std::vector<int>& triangleFace() const { return _triangleFace; }
    const std::vector<std::string>& warnings() const { return _warnings; }
    bool faceVaryingAvailable(int channel) const;
    uint64_t id() const { return _id; }  ///< unique per instance, never 0
    size_t memoryBytes() const;          ///< stencils + triangle arrays
    /// One line: scheme, level, counts, and the rows / entries of every stencil table.
    std::string describe() const;
    const BuildTimings& timings() const { return _timings; }

    /// Number of Far::TopologyRefiner objects ever built (process-wide); tests use it to
    /// check that re-posing does not rebuild.
    static uint64_t refinerBuildCount();

  private:
    SubdivTopology() = default;
    bool build(std::string* error);
    void buildCage();
    /// Limit points (when there are position masks) and normals from the last-level points.
    void computeLimit(const std::vector<glm::vec3>& levelPoints, RefinedMesh* out) const;

    struct FaceVaryingTables {
        bool available = false;
        size_t coarseValues = 0;
        StencilChain toLevel;      ///< coarse values -> last-level values (empty: identity)
        Stencils limit;            ///< last-level values -> limit values (empty: identity)
        /// Value of each triangle corner (3 per triangle); shared with the records that index
        /// refineFaceVaryingValues() output through it (faceVaryingCorners()).
        std::shared_ptr<std::vector<int>> corners = std::make_shared<std::vector<int>>();
    };

    // Inputs (kept for matches()).
    hd::MeshTopology _topology;
    hd::SubdivTags _tags;
    size_t _pointCount = 0;
    BuildOptions _options;

    Scheme _scheme = Scheme::None;
    int _level = 0;
    uint64_t _id = 0;
    BuildTimings _timings;
    size_t _refinedPoints = 0;
    std::vector<std::string> _warnings;

    StencilChain _vertex;   ///< coarse points -> last-level points (empty: identity, the cage)
    StencilChain _varying;  ///< linear; empty when not built or for the cage
    Stencils _limitP;       ///< last level -> limit position (empty: the refined point itself)
    Stencils _limitDu;      ///< last level -> limit tangents (empty: normals from triangles)
    Stencils _limitDv;
    std::vector<glm::uvec3> _triangles;
    std::vector<int> _triangleFace;
    std::vector<FaceVaryingTables> _fvar;
};

}  // namespace principled::subdiv
