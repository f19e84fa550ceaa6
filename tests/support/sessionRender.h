// SPDX-License-Identifier: Apache-2.0
// Session helpers for end-to-end tests: render a USDA string to convergence and read its
// colour, AOVs and warnings; a one-quad mesh to write scenes with.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "plugins/renderSession.h"

namespace principled::test {

/// Opens `usda` (as `name`) at w x h and steps it until its spp are done.
inline std::unique_ptr<host::RenderSession> renderUsda(const std::string& usda, int w, int h, int spp,
                                                       const std::vector<std::string>& aovs = {},
                                                       const std::map<std::string, std::string>& settings = {},
                                                       const std::string& name = "test.usda") {
    host::SessionOptions o;
    o.width = w;
    o.height = h;
    o.samplesPerPixel = spp;
    o.aovs = aovs;
    o.settings = settings;
    auto s = host::RenderSession::openString(usda, name, o);
    while (!s->step()) {
    }
    return s;
}

/// The first three components of AOV `aov` ("color" included) at pixel (x, y); -1 if unbound.
inline glm::vec3 aovAt(const host::RenderSession& s, const std::string& aov, int x, int y) {
    if (aov == "color") {
        const float* c = s.color() + (size_t(y) * size_t(s.width()) + size_t(x)) * 4;
        return {c[0], c[1], c[2]};
    }
    for (const auto& a : s.aovs())
        if (a.name == aov && !a.isInt) {
            const float* p = static_cast<const float*>(a.pixels) + (size_t(y) * size_t(s.width()) + size_t(x)) * size_t(a.components);
            return {p[0], a.components > 1 ? p[1] : 0.0f, a.components > 2 ? p[2] : 0.0f};
        }
    return glm::vec3(-1.0f);
}

/// The mean alpha of the colour buffer.
inline double meanAlpha(const host::RenderSession& s) {
    const size_t n = size_t(s.width()) * size_t(s.height());
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) sum += s.color()[4 * i + 3];
    return sum / double(n);
}

/// Every warning so far, one per line.
inline std::string warningsText(host::RenderSession& s) {
    std::string all;
    for (const auto& w : s.takeWarnings()) all += w + "\n";
    return all;
}

/// A polygon mesh of one quad (corners in order, as USDA tuples) with `extra` lines in its body.
inline std::string quadMesh(const std::string& name, const std::string& corners, const std::string& extra = "") {
    return "def Mesh \"" + name + "\" {\n    uniform token subdivisionScheme = \"none\"\n    int[] faceVertexCounts = [4]\n"
           "    int[] faceVertexIndices = [0, 1, 2, 3]\n    point3f[] points = [" + corners + "]\n    " + extra + "\n}\n";
}

}  // namespace principled::test
