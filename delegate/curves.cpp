// SPDX-License-Identifier: Apache-2.0
#include "delegate/curves.h"

#include <cmath>
#include <string>

#include "delegate/hd/sceneDelegate.h"
#include "delegate/hd/tokens.h"
#include "delegate/primitivePrimvars.h"
#include "delegate/primvarUtil.h"

namespace principled::embree {

using namespace hd;

namespace {

enum class Basis { Linear, Bezier, BSpline, CatmullRom };

// Vertices a curve needs for one segment, and how far the next segment starts.
int minVertices(Basis b) { return b == Basis::Linear ? 2 : 4; }
int vertexStep(Basis b) { return b == Basis::Bezier ? 3 : 1; }

RTCGeometryType embreeType(Basis b) {
    switch (b) {
        case Basis::Linear: return RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE;
        case Basis::Bezier: return RTC_GEOMETRY_TYPE_ROUND_BEZIER_CURVE;
        case Basis::BSpline: return RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE;
        case Basis::CatmullRom: return RTC_GEOMETRY_TYPE_ROUND_CATMULL_ROM_CURVE;
    }
    return RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE;
}

bool finite(const glm::vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

}  // namespace

DirtyBits BasisCurves::geometryBits() const {
    return RprimDirty::Points | RprimDirty::Primvar | RprimDirty::Topology | RprimDirty::Widths;
}

RTCGeometry BasisCurves::rebuildGeometry(SceneDelegate* delegate, EmbreeRenderParam* param) {
    Value pv = delegate->get(id(), tokens::points());
    Value cv = delegate->get(id(), tokens::curveVertexCounts());
    const auto* pts = getIf<std::vector<glm::vec3>>(pv);
    const auto* counts = getIf<std::vector<int>>(cv);
    if (!pts || !counts || pts->empty() || counts->empty()) {
        param->warn(id(), "basis curves need points and curveVertexCounts; not rendered");
        return nullptr;
    }
    size_t total = 0;
    for (int n : *counts) total += n > 0 ? size_t(n) : 0;
    if (total != pts->size()) {
        param->warn(id(), "curveVertexCounts sum to " + std::to_string(total) + " but there are " +
                              std::to_string(pts->size()) + " points; not rendered");
        return nullptr;
    }
    // UsdGeomBasisCurves: type linear|cubic (fallback cubic), basis bezier|bspline|catmullRom
    // (fallback bezier), wrap nonperiodic|periodic|pinned (fallback nonperiodic).
    std::string type = getString(delegate->get(id(), Token("type"))).value_or("cubic");
    std::string basisName = getString(delegate->get(id(), Token("basis"))).value_or("bezier");
    std::string wrap = getString(delegate->get(id(), Token("wrap"))).value_or("nonperiodic");
    Basis basis = Basis::Linear;
    if (type == "cubic") {
        if (basisName == "bezier") basis = Basis::Bezier;
        else if (basisName == "bspline") basis = Basis::BSpline;
        else if (basisName == "catmullRom") basis = Basis::CatmullRom;
        else param->warn(id(), "curve basis '" + basisName + "' is not bezier|bspline|catmullRom; drawn as linear");
    } else if (type != "linear") {
        param->warn(id(), "curve type '" + type + "' is not linear|cubic; drawn as linear");
    }
    if (wrap != "nonperiodic" && wrap != "periodic" && wrap != "pinned") {
        param->warn(id(), "curve wrap '" + wrap + "' is not nonperiodic|periodic|pinned; using nonperiodic");
        wrap = "nonperiodic";
    }
    // Widths (diameters): constant, one per curve (uniform), per vertex, or per varying
    // point (segment ends); without widths, 1.
    std::vector<float> widths;
    int wc = 0;
    flattenFloats(delegate->get(id(), tokens::widths()), &widths, &wc);
    if (wc != 1) widths.clear();
    const size_t curveCount = counts->size();
    auto segmentsOf = [&](int n) -> int {  // authored vertices -> segments (wrap and basis)
        if (n < 1) return 0;
        if (wrap == "periodic") return basis == Basis::Bezier ? n / 3 : n;
        if (wrap == "pinned" && (basis == Basis::BSpline || basis == Basis::CatmullRom)) n += 2;
        if (n < minVertices(basis)) return 0;
        return (n - (basis == Basis::Linear ? 1 : 3) + vertexStep(basis) - 1) / vertexStep(basis);
    };
    size_t varyingTotal = 0;
    for (int n : *counts) varyingTotal += size_t(segmentsOf(n)) + (wrap == "periodic" ? 0 : 1);
    enum class WidthMode { Default, Constant, Uniform, Vertex, Varying } wmode = WidthMode::Default;
    if (widths.size() == 1) wmode = WidthMode::Constant;
    else if (widths.size() == pts->size()) wmode = WidthMode::Vertex;
    else if (widths.size() == curveCount) wmode = WidthMode::Uniform;
    else if (!widths.empty() && widths.size() == varyingTotal) wmode = WidthMode::Varying;
    else if (!widths.empty())
        param->warn(id(), "widths has " + std::to_string(widths.size()) + " values, which fits no interpolation; using 1");
    if (wmode != WidthMode::Default) {
        size_t bad = 0;
        for (float w : widths) bad += !(std::isfinite(w) && w > 0.0f);
        if (bad > 0)
            param->warn(id(), std::to_string(bad) + " of " + std::to_string(widths.size()) +
                                  " widths are not positive (or not finite): the curves are invisible there");
    }

    _record.kind = GeometryRecord::Kind::Curves;
    _record.points.clear();
    _record.triangleFace.clear();
    std::vector<glm::vec4> verts;
    std::vector<uint32_t> starts;
    std::vector<size_t> segmentVertex, segmentVarying;  // authored vertex / varying value of each segment
    size_t offset = 0, varyingOffset = 0, badCurves = 0;
    for (size_t c = 0; c < curveCount; ++c) {
        const int n = std::max(0, (*counts)[c]);
        const int segments = segmentsOf(n);
        const size_t o = offset, vo = varyingOffset;
        offset += size_t(n);
        varyingOffset += size_t(segments) + (wrap == "periodic" ? 0 : 1);
        bool ok = segments > 0;
        for (int j = 0; j < n && ok; ++j) ok = finite((*pts)[o + size_t(j)]);
        if (!ok) {
            ++badCurves;
            continue;
        }
        auto width = [&](int j) {  // j: authored vertex in the curve, clamped
            j = std::clamp(j, 0, n - 1);
            switch (wmode) {
                case WidthMode::Constant: return widths[0];
                case WidthMode::Uniform: return widths[c];
                case WidthMode::Vertex: return widths[o + size_t(j)];
                case WidthMode::Varying: {
                    int nv = segments + (wrap == "periodic" ? 0 : 1);
                    int k = n > 1 ? int(std::lround(double(j) * (nv - 1) / (n - 1))) : 0;
                    return widths[vo + size_t(std::clamp(k, 0, nv - 1))];
                }
                default: return 1.0f;
            }
        };
        auto radius = [&](int j) {
            float w = width(j);
            return std::isfinite(w) && w > 0.0f ? 0.5f * w : 0.0f;
        };
        // The control points Embree sees: the authored ones, plus the wrap's extra ones.
        const size_t first = verts.size();
        const bool pinned = wrap == "pinned" && (basis == Basis::BSpline || basis == Basis::CatmullRom);
        auto P = [&](int j) { return (*pts)[o + size_t(j)]; };
        if (pinned) {
            // Phantom end points P(-1) = 2 P0 - P1 and P(n) = 2 P(n-1) - P(n-2) (UsdGeomBasisCurves,
            // "pinned" curves), so the curve reaches its end points.
            glm::vec3 a = n > 1 ? 2.0f * P(0) - P(1) : P(0);
            verts.emplace_back(a, radius(0));
        }
        for (int j = 0; j < n; ++j) verts.emplace_back(P(j), radius(j));
        if (pinned) {
            glm::vec3 b = n > 1 ? 2.0f * P(n - 1) - P(n - 2) : P(n - 1);
            verts.emplace_back(b, radius(n - 1));
        }
        if (wrap == "periodic") {
            int extra = basis == Basis::Linear || basis == Basis::Bezier ? 1 : 3;
            for (int j = 0; j < extra; ++j) verts.emplace_back(P(j % n), radius(j % n));
        }
        for (int s = 0; s < segments; ++s) {
            starts.push_back(uint32_t(first + size_t(s) * size_t(vertexStep(basis))));
            _record.triangleFace.push_back(int(c));
            segmentVertex.push_back(o + size_t(std::min(n - 1, s * vertexStep(basis))));
            segmentVarying.push_back(vo + size_t(s));
        }
    }
    if (badCurves)
        param->warn(id(), std::to_string(badCurves) +
                              " curves with too few vertices for their basis or non-finite points skipped");
    if (starts.empty()) return nullptr;
    for (const glm::vec4& v : verts) _record.points.emplace_back(v);
    if (auto col = constantDisplayColor(delegate, id())) _record.displayColor = *col;
    std::vector<Token> dropped;
    const size_t pointCount = pts->size();
    _record.primvars = primitivePrimvars(
        delegate, id(), starts.size(),
        [&](Interpolation interp, size_t s, size_t count) -> size_t {
            switch (interp) {
                case Interpolation::Uniform: return count == curveCount ? size_t(_record.triangleFace[s]) : count;
                case Interpolation::Varying:
                    if (count == varyingTotal) return segmentVarying[s];
                    return count == pointCount ? segmentVertex[s] : count;
                default: return count == pointCount ? segmentVertex[s] : count;
            }
        },
        &dropped);
    for (const Token& t : dropped) param->warn(id(), "primvar '" + t.str() + "' does not fit the curves; ignored");
    RTCGeometry geom = rtcNewGeometry(param->device(), embreeType(basis));
    auto* v = static_cast<glm::vec4*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, sizeof(glm::vec4), verts.size()));
    std::copy(verts.begin(), verts.end(), v);
    auto* ix = static_cast<uint32_t*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(uint32_t), starts.size()));
    std::copy(starts.begin(), starts.end(), ix);
    return geom;
}

}  // namespace principled::embree
