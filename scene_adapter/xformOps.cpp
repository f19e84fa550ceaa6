// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/xformOps.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "scene_adapter/usda/stage.h"

namespace principled::adapter {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

glm::dmat4 rotateAxis(int axis, double degrees) {
    glm::dvec3 a(0.0);
    a[axis] = 1.0;
    return glm::rotate(glm::dmat4(1.0), degrees * kDegToRad, a);
}

bool startsWith(const std::string& s, const std::string& p) { return s.rfind(p, 0) == 0; }

// Prim types that are not UsdGeomXformable (untyped prims, Scope, shading and render
// description, UsdSkel data): USD ignores ops authored on them. Types not known here (custom
// schemas) are taken to be Xformable.
bool notXformable(const std::string& type) {
    static const char* const kTypes[] = {"",          "Scope",         "Material",      "Shader",
                                         "NodeGraph", "GeomSubset",    "RenderSettings", "RenderProduct",
                                         "RenderVar", "RenderPass",    "SkelAnimation", "BlendShape"};
    for (const char* t : kTypes)
        if (type == t) return true;
    return false;
}

}  // namespace

LocalTransform computeLocalTransform(const usd::Prim& prim, double time, std::string* warning) {
    LocalTransform out;
    const usd::Attribute* orderAttr = prim.attribute("xformOpOrder");
    if (!orderAttr) return out;
    if (notXformable(prim.typeName())) {
        if (warning && warning->empty() && orderAttr->hasValue())
            *warning = (prim.typeName().empty() ? std::string("an untyped prim") : "a " + prim.typeName()) +
                       " is not Xformable: its xformOps are ignored (make it an Xform to move its children)";
        return out;
    }
    usd::Value orderValue = orderAttr->get(time);
    const std::vector<std::string>* order = orderValue.strings();
    if (!order) return out;
    auto warn = [&](const std::string& m) {
        if (warning && warning->empty()) *warning = m;
    };
    // USD composes ops so that later ops are more local: with column vectors,
    // M = op[0] * op[1] * ... * op[n-1] (UsdGeomXformable, "xformOpOrder").
    glm::dmat4 m(1.0);
    for (size_t i = 0; i < order->size(); ++i) {
        std::string name = (*order)[i];
        if (name == "!resetXformStack!") {
            if (i == 0)
                out.resetsXformStack = true;
            else
                warn("!resetXformStack! must be the first op in xformOpOrder; ignored");
            continue;
        }
        bool invert = false;
        if (startsWith(name, "!invert!")) {
            invert = true;
            name = name.substr(8);
        }
        const usd::Attribute* attr = prim.attribute(name);
        if (!attr || !attr->hasValue()) {
            warn("xformOpOrder names '" + name + "', which has no value; op skipped");
            continue;
        }
        if (!attr->timeSamples().empty()) out.timeVarying = true;
        usd::Value v = attr->get(time);
        if (v.isNone()) {
            warn("xformOp '" + name + "' is blocked (None) at this time; op skipped");
            continue;
        }
        // The op type is the second namespace element: xformOp:<type>[:suffix].
        std::string type = name.substr(name.find(':') + 1);
        type = type.substr(0, type.find(':'));
        std::optional<std::vector<double>> t = v.getTuple();
        std::optional<double> s = v.getDouble();
        glm::dmat4 op(1.0);
        bool ok = true;
        if (type == "translate" && t && t->size() == 3) {
            op = glm::translate(glm::dmat4(1.0), glm::dvec3((*t)[0], (*t)[1], (*t)[2]));
        } else if (type == "scale" && t && t->size() == 3) {
            op = glm::scale(glm::dmat4(1.0), glm::dvec3((*t)[0], (*t)[1], (*t)[2]));
        } else if (type == "scale" && s) {
            op = glm::scale(glm::dmat4(1.0), glm::dvec3(*s));
        } else if ((type == "rotateX" || type == "rotateY" || type == "rotateZ") && s) {
            op = rotateAxis(type[6] - 'X', *s);
        } else if (type.size() == 9 && startsWith(type, "rotate") && t && t->size() == 3) {
            // rotateABC: the first axis named is the most local, so with column vectors the
            // matrix is R_C * R_B * R_A.
            glm::dmat4 r(1.0);
            bool valid = true;
            for (int k = 0; k < 3; ++k) {
                int axis = type[6 + k] - 'X';
                if (axis < 0 || axis > 2) valid = false;
                else r = rotateAxis(axis, (*t)[axis]) * r;
            }
            ok = valid;
            op = r;
        } else if (type == "orient" && t && t->size() == 4) {
            glm::dquat q((*t)[0], (*t)[1], (*t)[2], (*t)[3]);  // (real, i, j, k)
            double len = glm::length(q);
            if (len > 0.0) op = glm::dmat4(glm::mat3_cast(q / len));
            else ok = false;
        } else if (type == "transform" && t && t->size() == 16) {
            // USD matrices are row-vector with translation in the last row; reading the rows
            // into glm's columns gives the column-vector matrix directly.
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r) op[c][r] = (*t)[c * 4 + r];
        } else {
            ok = false;
        }
        if (!ok) {
            warn("xform op '" + name + "' has an unsupported type or value shape (" +
                 attr->typeName() + "); op skipped");
            continue;
        }
        if (invert) {
            if (std::abs(glm::determinant(op)) < 1e-300) {
                warn("!invert! of singular op '" + name + "'; op skipped");
                continue;
            }
            op = glm::inverse(op);
        }
        m = m * op;
    }
    out.matrix = m;
    return out;
}

}  // namespace principled::adapter
