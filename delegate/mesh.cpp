// SPDX-License-Identifier: Apache-2.0
#include "delegate/mesh.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <sys/resource.h>
#include <utility>

#include "delegate/hd/sceneDelegate.h"
#include "delegate/hd/tokens.h"
#include "delegate/primvarUtil.h"
#include "delegate/subdiv/adaptiveLevel.h"
#include "delegate/subdiv/deviationLevel.h"
#include "delegate/transformCheck.h"
#include "delegate/triangulate.h"

namespace principled::embree {

using namespace hd;

namespace {

constexpr Interpolation kInterpolations[] = {Interpolation::Constant, Interpolation::Uniform,
                                             Interpolation::Varying, Interpolation::Vertex,
                                             Interpolation::FaceVarying};

// PRINCIPLED_MEM_TRACE=1: resident and peak memory and minor faults at each stage of a
// subdivided mesh's build, on stderr (docs/geometry.md, subdivision memory).
bool memTraceOn() {
    static const bool on = std::getenv("PRINCIPLED_MEM_TRACE") != nullptr;
    return on;
}
void memTrace(const char* what) {
    if (!memTraceOn()) return;
    long pages = 0, rss = 0;
    if (FILE* f = std::fopen("/proc/self/statm", "r")) {
        if (std::fscanf(f, "%ld %ld", &pages, &rss) != 2) rss = 0;
        std::fclose(f);
    }
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    std::fprintf(stderr, "[mem] %-28s rss %7.1f MB  peak %7.1f MB  minflt %ld\n", what,
                 rss * 4096.0 / 1e6, ru.ru_maxrss * 1024.0 / 1e6, ru.ru_minflt);
}

bool isGeometryPrimvar(const Token& name) {
    return name == tokens::normals() || name == tokens::points();
}

}  // namespace

DirtyBits Mesh::geometryBits() const {
    return RprimDirty::Points | RprimDirty::Topology | RprimDirty::Normals | RprimDirty::Primvar |
           RprimDirty::DisplayStyle | RprimDirty::SubdivTags;
}

namespace {

// The level a mesh asks for, as a budget plan: fixed (per-prim refineLevel, the refineLevel
// setting, or the fallback without a view) or adaptive from its world bounds.
subdiv::LevelPlan planLevel(const MeshTopology& topo, const SubdivTags& tags, const std::vector<glm::vec3>& points,
                            const glm::mat4& objectToWorld, const EmbreeRenderParam::Dicing& d,
                            const std::function<bool()>& primvarsFollowTheCage) {
    subdiv::LevelPlan plan;
    auto fixed = [&](int level) {
        plan.log2Ratio = float(level);
        plan.maxLevel = level;
    };
    if (topo.refineLevel >= 0) {
        fixed(std::min(topo.refineLevel, 8));  // per-prim override
    } else if (d.level >= 0) {
        fixed(std::min(d.level, 8));
    } else if (!d.haveView) {
        fixed(d.fallbackLevel);
    } else {
        glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
        std::vector<glm::vec3> world;
        world.reserve(points.size());
        for (const auto& p : points) {
            glm::vec3 w = glm::vec3(objectToWorld * glm::vec4(p, 1.0f));
            lo = glm::min(lo, w);
            hi = glm::max(hi, w);
            world.push_back(w);
        }
        subdiv::ScreenMetric view;
        view.cameraPosition = d.cameraPosition;
        view.verticalFov = d.verticalFov;
        view.imageHeight = d.imageHeight;
        view.targetEdgePixels = d.targetEdgePixels;
        view.maxLevel = d.maxLevel;
        plan.log2Ratio = subdiv::adaptiveLog2Ratio(lo, hi, topo.faceVertexCounts.size(), view);
        // Edges need not shrink below the dicing rate where the surface already lies within
        // the tolerance of its limit (flat parts need no refinement at all).
        // Only where every primvar the refinement smooths is already its own limit: else the
        // refined values differ from the cage's whatever the shape (asked last: it reads them).
        if (d.tolerancePixels > 0.0f) {
            const float deviation = subdiv::deviationLevel(world, topo, tags, view, d.tolerancePixels);
            if (deviation < plan.log2Ratio && primvarsFollowTheCage()) plan.log2Ratio = deviation;
        }
        plan.maxLevel = d.maxLevel;
    }
    // Triangles per level: the cage fan-triangulated; after the first step an n-gon is n quads
    // (two triangles each) under Catmull-Clark and bilinear, a triangle four under Loop (which
    // sdcSetup applies to all-triangle meshes only; others refine as Catmull-Clark).
    bool loop = topo.scheme == Token("loop");
    for (int n : topo.faceVertexCounts) loop = loop && n == 3;
    double level1 = 0.0, faces1 = 0.0;  // triangles and faces after one step
    for (int n : topo.faceVertexCounts) {
        if (n < 3) continue;  // an invalid face (the build rejects the mesh)
        plan.cageTriangles += size_t(n - 2);
        level1 += loop ? 4.0 : 2.0 * double(n);
        faces1 += loop ? 4.0 : double(n);
    }
    plan.trianglesAtLevel1 = level1;
    // SubdivTopology lowers a level past its per-mesh face cap (refinedFaceEstimate: faces1
    // times 4 per further step); the budget counts what it builds.
    const double cap = double(subdiv::BuildOptions{}.maxRefinedFaces);
    plan.faceCapLevel = 0;
    for (double faces = faces1; plan.faceCapLevel < 8 && faces <= cap; faces *= 4.0) ++plan.faceCapLevel;
    return plan;
}

// The checks the cage and OpenSubdiv builds make before refining: finite points, faces of at
// least three corners whose counts add up to the indices, indices in range.
bool cageIsValid(const MeshTopology& topo, const std::vector<glm::vec3>& points) {
    for (const glm::vec3& p : points)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
    size_t corners = 0;
    for (int n : topo.faceVertexCounts) {
        if (n < 3) return false;
        corners += size_t(n);
    }
    if (topo.faceVertexCounts.empty() || corners != topo.faceVertexIndices.size()) return false;
    for (int i : topo.faceVertexIndices)
        if (i < 0 || size_t(i) >= points.size()) return false;
    return true;
}

// Whether every vertex and face-varying primvar of the mesh equals its own limit under the
// subdivision rules (subdiv::valuesFollowTheCage, 1e-4 of its range): then the cage and the
// refined surface carry the same values. Varying primvars are linear in both; constant and
// uniform ones do not vary over a face.
bool primvarsFollowTheCage(SceneDelegate* delegate, const Path& id, const MeshTopology& topo, const SubdivTags& tags) {
    constexpr double kTolerance = 1e-4;
    std::vector<int> valueIndices;
    std::vector<float> flat;
    int components = 0;
    // The primvar's values (flattened) and indices; false for one that is not numeric data.
    auto read = [&](const PrimvarDescriptor& desc) {
        valueIndices.clear();
        flat.clear();
        components = 0;
        return !isGeometryPrimvar(desc.name) &&
               flattenFloats(delegate->getIndexedPrimvar(id, desc.name, &valueIndices), &flat, &components) &&
               components > 0;
    };
    for (const auto& desc : delegate->getPrimvarDescriptors(id, Interpolation::Vertex)) {
        if (!read(desc)) continue;
        if (!valueIndices.empty()) {  // one value per point through the indices
            std::vector<float> perPoint;
            perPoint.reserve(valueIndices.size() * size_t(components));
            for (int i : valueIndices) {
                if (i < 0 || size_t(i + 1) * size_t(components) > flat.size()) return false;
                perPoint.insert(perPoint.end(), flat.begin() + std::ptrdiff_t(size_t(i) * size_t(components)),
                                flat.begin() + std::ptrdiff_t(size_t(i + 1) * size_t(components)));
            }
            flat.swap(perPoint);
        }
        if (!subdiv::valuesFollowTheCage(flat, components, topo, topo.faceVertexIndices,
                                         tags.interpolateBoundary == Token("edgeAndCorner"), kTolerance))
            return false;
    }
    const Token fvarRule = tags.faceVaryingLinearInterpolation;
    if (fvarRule == Token("all")) return true;  // face-varying values stay linear
    for (const auto& desc : delegate->getPrimvarDescriptors(id, Interpolation::FaceVarying)) {
        if (!read(desc)) continue;
        if (valueIndices.empty()) {  // one value per corner: every face its own island
            valueIndices.resize(flat.size() / size_t(components));
            for (size_t i = 0; i < valueIndices.size(); ++i) valueIndices[i] = int(i);
        }
        if (!subdiv::valuesFollowTheCage(flat, components, topo, valueIndices, fvarRule != Token("none"), kTolerance))
            return false;
    }
    return true;
}

// The transform GeometryPrim::sync renders with: the authored one, or identity when unusable.
glm::mat4 renderedTransform(const glm::mat4& m) { return unusableTransform(m) ? glm::mat4(1.0f) : m; }

}  // namespace

int Mesh::chooseLevel(SceneDelegate* delegate, const MeshTopology& topo, const SubdivTags& tags,
                      const std::vector<glm::vec3>& points, EmbreeRenderParam* param, int granted) {
    if (topo.scheme == Token("none")) {
        _plan.reset();
        return 0;
    }
    // The budget's level, planned before this sync from the same inputs.
    if (granted >= 0 && _plan) return granted;
    const subdiv::LevelPlan plan = planLevel(topo, tags, points, _record.objectToWorld, param->dicing(),
                                             [&] { return primvarsFollowTheCage(delegate, id(), topo, tags); });
    _plan = cageIsValid(topo, points) ? std::optional(plan) : std::nullopt;  // else not built
    return plan.levelAt(0);
}

std::optional<subdiv::LevelPlan> Mesh::levelPlan(SceneDelegate* delegate, EmbreeRenderParam* param) const {
    MeshTopology topo = delegate->getMeshTopology(id());
    if (topo.scheme == Token("none")) return std::nullopt;
    Value pointsValue = delegate->get(id(), tokens::points());
    const auto* points = getIf<std::vector<glm::vec3>>(pointsValue);
    if (!points || !cageIsValid(topo, *points)) return std::nullopt;  // not built: takes nothing
    const glm::mat4 m = renderedTransform(glm::mat4(delegate->getTransform(id())));
    const SubdivTags tags = delegate->getSubdivTags(id());
    return planLevel(topo, tags, *points, m, param->dicing(),
                     [&] { return primvarsFollowTheCage(delegate, id(), topo, tags); });
}

void Mesh::finalize(RenderParam* param) {
    if (_plan) static_cast<EmbreeRenderParam*>(param)->requestSubdivisionRefit();
    GeometryPrim::finalize(param);
}

RTCGeometry Mesh::rebuildGeometry(SceneDelegate* delegate, EmbreeRenderParam* param) {
    // A level granted for this rebuild is used by it or by nothing (never by a later one).
    const int granted = std::exchange(_grantedLevel, -1);
    RTCGeometry geom = buildGeometry(delegate, param, granted);
    if (!geom) _plan.reset();  // nothing built: holds nothing against the budget
    return geom;
}

RTCGeometry Mesh::buildGeometry(SceneDelegate* delegate, EmbreeRenderParam* param, int granted) {
    Value pointsValue = delegate->get(id(), tokens::points());
    const auto* points = getIf<std::vector<glm::vec3>>(pointsValue);
    if (!points || points->empty()) {
        param->warn(id(), "mesh not rendered: it has no points");
        return nullptr;
    }
    bool beyond = false;
    for (const glm::vec3& p : *points) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            param->warn(id(), "mesh not rendered: points contain NaN or Inf");
            return nullptr;
        }
        // Embree's range (FLT_LARGE): faces with such points are never hit.
        beyond = beyond || std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) > 1.8e18f;
    }
    if (beyond)
        param->warn(id(), "points beyond 1.8e18 units from the origin (outside the ray tracer's range): "
                          "the faces that use them are not drawn");
    MeshTopology topo = delegate->getMeshTopology(id());
    // GeometryPrim syncs the transform before the geometry, so adaptive dicing sees it.
    int level = chooseLevel(delegate, topo, delegate->getSubdivTags(id()), *points, param, granted);
    bool ok = level > 0 ? buildSubdivided(delegate, param, topo, *points, level)
                        : buildCage(delegate, param, topo, *points);
    if (!ok || _record.triangles.empty()) return nullptr;
    if (auto c = constantDisplayColor(delegate, id())) _record.displayColor = *c;

    RTCGeometry geom = rtcNewGeometry(param->device(), RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree reads the record's own arrays (no copy: 12 bytes per triangle and per vertex
    // saved). They stay unchanged until the next rebuildGeometry, which replaces this geometry.
    // Embree reads vertices with 16-byte loads: one spare element keeps the last load inside
    // the allocation (rtcSetSharedGeometryBuffer, Embree 3.13 API docs).
    _record.points.reserve(_record.points.size() + 1);
    _record.triangles.reserve(_record.triangles.size() + 1);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                               _record.points.data(), 0, sizeof(glm::vec3), _record.points.size());
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                               _record.triangles.data(), 0, sizeof(glm::uvec3),
                               _record.triangles.size());
    param->meshesRebuilt++;
    memTrace("end rebuildGeometry");
    if (memTraceOn())
        std::fprintf(stderr, "[mem] %zu tris record %.1f B/tri mesh %.1f B/tri\n", _record.triangles.size(),
                     double(_record.memoryBytes()) / double(_record.triangles.size()),
                     double(memoryBytes()) / double(_record.triangles.size()));
    return geom;
}

size_t Mesh::memoryBytes() const {
    return _record.memoryBytes() + (_subdiv ? _subdiv->memoryBytes() : 0);
}

bool Mesh::buildCage(SceneDelegate* delegate, EmbreeRenderParam* param, const MeshTopology& topo,
                     const std::vector<glm::vec3>& points) {
    _level = 0;
    _subdiv.reset();
    _refinedTopologyId = 0;
    std::vector<glm::vec3>().swap(_record.vertexNormals);
    Triangulation tri;
    std::string error;
    if (!triangulate(topo, points.size(), &tri, &error, points.data())) {
        param->warn(id(), "mesh not rendered: " + error);
        return false;
    }
    if (tri.badHoles > 0)
        param->warn(id(), std::to_string(tri.badHoles) + " holeIndices entr" + (tri.badHoles == 1 ? "y names" : "ies name") +
                              " no face (faces are 0 to " + std::to_string(topo.faceVertexCounts.size()) + " - 1); ignored");
    if (tri.skippedFaces > 0)
        param->warn(id(), "skipped " + std::to_string(tri.skippedFaces) + " invalid face(s); " +
                              tri.firstProblem);
    _record.kind = GeometryRecord::Kind::Triangles;
    _record.points = points;
    _record.triangles = std::move(tri.triangles);
    _record.triangleFace = std::move(tri.triangleFace);
    CornerLayout layout{points.size(), topo.faceVertexCounts.size(), topo.faceVertexIndices.size(),
                        &_record.triangles, &tri.corners, &_record.triangleFace};
    // A subdivision surface drawn as its cage is shaded smooth, from its own shape: authored
    // normals are for polygons (UsdGeomMesh: a subdivided mesh defines its own), as at any
    // refined level. Polygons ("none") keep theirs or stay faceted.
    if (topo.scheme == Token("none")) {
        std::string problem;
        _record.cornerNormals = authoredCornerNormals(delegate, id(), layout, &problem);
        if (!problem.empty()) param->warn(id(), problem);
    } else
        _record.cornerNormals = smoothCornerNormals(_record.points, _record.triangles);
    _record.primvars.clear();
    for (Interpolation interp : kInterpolations)
        for (const auto& d : delegate->getPrimvarDescriptors(id(), interp)) {
            if (isGeometryPrimvar(d.name)) continue;
            std::vector<int> indices;
            std::vector<float> flat;
            int components = 0;
            Value v = delegate->getIndexedPrimvar(id(), d.name, &indices);
            if (!flattenFloats(v, &flat, &components) || components > 4) continue;
            PrimvarChannel ch;
            ch.name = d.name;
            ch.components = components;
            ch.constant = interp == Interpolation::Constant;
            if (ch.constant) {
                if (flat.size() < size_t(components)) continue;
                ch.data.assign(flat.begin(), flat.begin() + components);
            } else if (!expandToCorners(flat, components, indices, interp, layout, &ch.data)) {
                param->warn(id(), "primvar '" + d.name.str() + "' has the wrong number of values for its interpolation; ignored");
                continue;
            }
            _record.primvars.push_back(std::move(ch));
        }
    return true;
}

bool Mesh::buildSubdivided(SceneDelegate* delegate, EmbreeRenderParam* param,
                           const MeshTopology& topo, const std::vector<glm::vec3>& points,
                           int level) {
    SubdivTags tags = delegate->getSubdivTags(id());
    // Face-varying primvars get their own OpenSubdiv channel (their own topology).
    struct Pending {
        Token name;
        Interpolation interp;
        std::vector<float> flat;
        std::vector<int> indices;
        int components;
        int channel = -1;
    };
    std::vector<Pending> pending;
    subdiv::BuildOptions opts;
    opts.level = level;
    for (Interpolation interp : kInterpolations)
        for (const auto& d : delegate->getPrimvarDescriptors(id(), interp)) {
            if (isGeometryPrimvar(d.name)) continue;
            Pending p{d.name, interp, {}, {}, 0};
            Value v = delegate->getIndexedPrimvar(id(), d.name, &p.indices);
            if (!flattenFloats(v, &p.flat, &p.components) || p.components > 4) continue;
            if (interp == Interpolation::FaceVarying) {
                subdiv::FaceVaryingChannel ch;
                size_t values = p.flat.size() / size_t(p.components);
                if (p.indices.empty()) {
                    ch.indices.resize(values);
                    for (size_t i = 0; i < values; ++i) ch.indices[i] = int(i);
                } else {
                    ch.indices = p.indices;
                }
                ch.valueCount = values;
                p.channel = int(opts.faceVarying.size());
                opts.faceVarying.push_back(std::move(ch));
            } else if (!p.indices.empty()) {
                // Indexed non-face-varying primvars are de-indexed first.
                std::vector<float> flat;
                flat.reserve(p.indices.size() * p.components);
                bool good = true;
                for (int i : p.indices) {
                    if (i < 0 || size_t(i) * p.components >= p.flat.size()) { good = false; break; }
                    flat.insert(flat.end(), p.flat.begin() + size_t(i) * p.components,
                                p.flat.begin() + size_t(i + 1) * p.components);
                }
                if (!good) continue;
                p.flat = std::move(flat);
                p.indices.clear();
            }
            pending.push_back(std::move(p));
        }
    // Varying (linear) stencils only when a varying primvar needs them: about 19 bytes per
    // refined point otherwise held for nothing. A varying primvar added later changes the
    // options, so matches() rebuilds.
    opts.varying = false;
    for (const auto& p : pending) opts.varying = opts.varying || p.interp == Interpolation::Varying;
    memTrace("before subdiv create");
    if (!_subdiv || !_subdiv->matches(topo, tags, points.size(), opts)) {
        std::string error;
        _subdiv = subdiv::SubdivTopology::create(topo, tags, points.size(), opts, &error);
        if (!_subdiv) {
            // A cage OpenSubdiv cannot take (a face of fewer than 3 vertices, a bad index): the
            // polygons are drawn instead, their bad faces skipped (as a polygon mesh would be).
            param->warn(id(), "not subdivided: " + error + "; drawn as its polygons");
            return buildCage(delegate, param, topo, points);
        }
        for (const auto& w : _subdiv->warnings()) param->warn(id(), w);
    }
    // Refine straight into the record's arrays (no second copy of the refined mesh): they move
    // into a RefinedMesh for refine() and back. Capacity for one spare element is reserved
    // first, for Embree's 16-byte loads (rebuildGeometry), so nothing is reallocated later.
    subdiv::RefinedMesh refined;
    refined.points.swap(_record.points);
    refined.normals.swap(_record.vertexNormals);
    refined.triangles.swap(_record.triangles);
    refined.triangleFace.swap(_record.triangleFace);
    refined.topologyId = _refinedTopologyId;
    if (refined.topologyId != _subdiv->id()) {
        refined.triangles.clear();
        refined.triangles.shrink_to_fit();
        refined.triangles.reserve(_subdiv->triangleCount() + 1);
        refined.triangleFace.clear();
        refined.triangleFace.shrink_to_fit();
        refined.triangleFace.reserve(_subdiv->triangleCount());
    }
    if (refined.points.capacity() < _subdiv->refinedPointCount() + 1) {
        refined.points.clear();
        refined.points.shrink_to_fit();
        refined.points.reserve(_subdiv->refinedPointCount() + 1);
    }
    memTrace("after subdiv create");
    std::string error;
    const bool refinedOk = _subdiv->refine(points, &refined, &error);
    _record.points.swap(refined.points);
    _record.vertexNormals.swap(refined.normals);
    _record.triangles.swap(refined.triangles);
    _record.triangleFace.swap(refined.triangleFace);
    _refinedTopologyId = refinedOk ? refined.topologyId : 0;
    if (!refinedOk) {
        param->warn(id(), "mesh not rendered: " + error);
        return false;
    }
    memTrace("after refine");
    _level = _subdiv->level();
    _record.kind = GeometryRecord::Kind::Triangles;
    // Normals per point (vertexNormals, indexed by the triangles), not per corner.
    std::vector<glm::vec3>().swap(_record.cornerNormals);
    // Primvars on the refined mesh: vertex and varying ones per point (perVertex), uniform
    // ones per triangle (perPrimitive), face-varying ones per value (cornerIndex).
    _record.primvars.clear();
    for (auto& p : pending) {
        PrimvarChannel ch;
        ch.name = p.name;
        ch.components = p.components;
        size_t count = p.flat.size() / size_t(p.components);
        bool ok = true;
        switch (p.interp) {
            case Interpolation::Constant:
                ch.constant = true;
                ch.data.assign(p.flat.begin(), p.flat.begin() + std::min<size_t>(p.flat.size(), p.components));
                ok = ch.data.size() == size_t(p.components);
                break;
            case Interpolation::FaceVarying:
                // Limit values + the topology's shared corner -> value map, not per corner.
                ok = _subdiv->refineFaceVaryingValues(p.channel, p.flat.data(), count,
                                                      p.components, &ch.data);
                ch.cornerIndex = _subdiv->faceVaryingCorners(p.channel);
                ok = ok && ch.cornerIndex;
                break;
            case Interpolation::Uniform:
                ch.perPrimitive = true;
                ok = _subdiv->refineUniform(p.flat.data(), count, p.components, &ch.data);
                break;
            default:  // vertex, varying
                ch.perVertex = true;
                ok = p.interp == Interpolation::Vertex
                         ? _subdiv->refineVertex(p.flat.data(), count, p.components, &ch.data)
                         : _subdiv->refineVarying(p.flat.data(), count, p.components, &ch.data);
        }
        if (!ok) {
            param->warn(id(), "primvar '" + p.name.str() + "' could not be refined (wrong count for its interpolation); ignored");
            continue;
        }
        _record.primvars.push_back(std::move(ch));
    }
    return true;
}

}  // namespace principled::embree
