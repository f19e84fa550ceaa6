// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/usdSdc.h"

#include <algorithm>

namespace principled::subdiv {

namespace {

template <typename E>
struct TokenValue {
    const char* token;
    E value;
};

/// Looks `token` up in `table`; empty gives `fallback` silently, unknown gives it with a warning.
template <typename E, size_t N>
E lookup(const hd::Token& token, const TokenValue<E> (&table)[N], E fallback, const char* what,
         std::vector<std::string>* warnings) {
    if (token.empty()) return fallback;
    for (const auto& tv : table)
        if (token.str() == tv.token) return tv.value;
    warnings->push_back(std::string("unknown ") + what + " \"" + token.str() +
                        "\", using the default");
    return fallback;
}

}  // namespace

SdcSetup sdcSetup(const hd::MeshTopology& topology, const hd::SubdivTags& tags,
                  std::vector<std::string>* warnings) {
    static const TokenValue<Sdc::SchemeType> kSchemes[] = {{"catmullClark", Sdc::SCHEME_CATMARK},
                                                           {"loop", Sdc::SCHEME_LOOP},
                                                           {"bilinear", Sdc::SCHEME_BILINEAR}};
    static const TokenValue<Sdc::Options::VtxBoundaryInterpolation> kBoundary[] = {
        {"none", Sdc::Options::VTX_BOUNDARY_NONE},
        {"edgeOnly", Sdc::Options::VTX_BOUNDARY_EDGE_ONLY},
        {"edgeAndCorner", Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER}};
    static const TokenValue<Sdc::Options::FVarLinearInterpolation> kFVar[] = {
        {"none", Sdc::Options::FVAR_LINEAR_NONE},
        {"cornersOnly", Sdc::Options::FVAR_LINEAR_CORNERS_ONLY},
        {"cornersPlus1", Sdc::Options::FVAR_LINEAR_CORNERS_PLUS1},
        {"cornersPlus2", Sdc::Options::FVAR_LINEAR_CORNERS_PLUS2},
        {"boundaries", Sdc::Options::FVAR_LINEAR_BOUNDARIES},
        {"all", Sdc::Options::FVAR_LINEAR_ALL}};
    static const TokenValue<Sdc::Options::TriangleSubdivision> kTriangle[] = {
        {"catmullClark", Sdc::Options::TRI_SUB_CATMARK}, {"smooth", Sdc::Options::TRI_SUB_SMOOTH}};

    SdcSetup s;
    s.scheme =
        lookup(topology.scheme, kSchemes, Sdc::SCHEME_CATMARK, "subdivisionScheme", warnings);
    if (s.scheme == Sdc::SCHEME_LOOP) {
        const auto& counts = topology.faceVertexCounts;
        if (!std::all_of(counts.begin(), counts.end(), [](int c) { return c == 3; })) {
            warnings->push_back(
                "loop subdivision needs triangles only; this mesh has other faces, using "
                "catmullClark");
            s.scheme = Sdc::SCHEME_CATMARK;
        }
    }
    s.options.SetVtxBoundaryInterpolation(lookup(tags.interpolateBoundary, kBoundary,
                                                 Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER,
                                                 "interpolateBoundary", warnings));
    if (s.scheme == Sdc::SCHEME_BILINEAR)
        s.options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
    s.options.SetFVarLinearInterpolation(lookup(tags.faceVaryingLinearInterpolation, kFVar,
                                                Sdc::Options::FVAR_LINEAR_CORNERS_PLUS1,
                                                "faceVaryingLinearInterpolation", warnings));
    s.options.SetTriangleSubdivision(lookup(tags.triangleSubdivisionRule, kTriangle,
                                            Sdc::Options::TRI_SUB_CATMARK,
                                            "triangleSubdivisionRule", warnings));
    s.options.SetCreasingMethod(Sdc::Options::CREASE_UNIFORM);  // USD's creaseMethod default
    return s;
}

}  // namespace principled::subdiv
