// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/sharpnessTags.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace principled::subdiv {

namespace {

// OpenSubdiv's infinitely sharp (Sdc::Crease::SHARPNESS_INFINITE): larger values, +inf
// included, mean the same; negative ones are smooth (0). NaN has no meaning.
constexpr float kInfinitelySharp = 10.0f;
bool usableSharpness(float s) { return !std::isnan(s); }
float sharpness(float s) { return std::clamp(s, 0.0f, kInfinitelySharp); }

void splitCreases(const hd::SubdivTags& tags, size_t pointCount, SharpnessTags* out,
                  std::vector<std::string>* warnings) {
    const auto& idx = tags.creaseIndices;
    const auto& len = tags.creaseLengths;
    const auto& sharp = tags.creaseSharpnesses;
    if (len.empty() && idx.empty()) return;
    size_t vertexTotal = 0, edgeTotal = 0;
    for (int n : len) {
        if (n < 2) {
            warnings->push_back("creaseLengths has a crease of " + std::to_string(n) +
                                " vertices (at least 2 needed); creases ignored");
            return;
        }
        vertexTotal += size_t(n);
        edgeTotal += size_t(n - 1);
    }
    if (vertexTotal != idx.size()) {
        warnings->push_back("creaseLengths sum to " + std::to_string(vertexTotal) +
                            " but creaseIndices has " + std::to_string(idx.size()) +
                            " entries; creases ignored");
        return;
    }
    const bool perCrease = sharp.size() == len.size();
    const bool perEdge = sharp.size() == edgeTotal;
    if (!perCrease && !perEdge) {
        warnings->push_back("creaseSharpnesses has " + std::to_string(sharp.size()) +
                            " entries, expected " + std::to_string(len.size()) +
                            " (per crease) or " + std::to_string(edgeTotal) +
                            " (per edge); creases ignored");
        return;
    }
    size_t start = 0, edge = 0, bad = 0;
    std::string first;
    for (size_t c = 0; c < len.size(); ++c) {
        for (int k = 0; k + 1 < len[c]; ++k, ++edge) {
            int a = idx[start + k], b = idx[start + k + 1];
            float s = perCrease ? sharp[c] : sharp[edge];
            const bool pointsOk = a >= 0 && b >= 0 && size_t(a) < pointCount && size_t(b) < pointCount && a != b;
            if (!pointsOk || !usableSharpness(s)) {
                if (bad++ == 0)
                    first = "crease " + std::to_string(c) + " edge (" + std::to_string(a) + ", " + std::to_string(b) +
                            ")" + (pointsOk ? " has sharpness NaN" : " names a point outside [0, " + std::to_string(pointCount) + ") or twice the same");
                continue;
            }
            out->edgeVertices.push_back(a);
            out->edgeVertices.push_back(b);
            out->edgeSharpness.push_back(sharpness(s));
        }
        start += size_t(len[c]);
    }
    if (bad > 0)
        warnings->push_back(std::to_string(bad) + " crease edge(s) ignored; the first: " + first);
}

void corners(const hd::SubdivTags& tags, size_t pointCount, SharpnessTags* out,
             std::vector<std::string>* warnings) {
    if (tags.cornerIndices.size() != tags.cornerSharpnesses.size()) {
        if (!tags.cornerIndices.empty() || !tags.cornerSharpnesses.empty())
            warnings->push_back(
                "cornerIndices and cornerSharpnesses differ in size; corners ignored");
        return;
    }
    size_t bad = 0;
    std::string first;
    for (size_t i = 0; i < tags.cornerIndices.size(); ++i) {
        int v = tags.cornerIndices[i];
        float s = tags.cornerSharpnesses[i];
        if (v < 0 || size_t(v) >= pointCount || !usableSharpness(s)) {
            if (bad++ == 0)
                first = "corner " + std::to_string(i) + " (point " + std::to_string(v) + ")" +
                        (usableSharpness(s) ? " is outside [0, " + std::to_string(pointCount) + ")" : " has sharpness NaN");
            continue;
        }
        out->cornerVertices.push_back(v);
        out->cornerSharpness.push_back(sharpness(s));
    }
    if (bad > 0) warnings->push_back(std::to_string(bad) + " corner(s) ignored; the first: " + first);
}

}  // namespace

SharpnessTags sharpnessTags(const hd::SubdivTags& tags, size_t pointCount,
                            std::vector<std::string>* warnings) {
    SharpnessTags out;
    splitCreases(tags, pointCount, &out, warnings);
    corners(tags, pointCount, &out, warnings);
    return out;
}

}  // namespace principled::subdiv
