// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/primvars.h"

#include <set>

namespace principled::adapter {

using hd::Interpolation;

Interpolation parseInterpolation(const std::string& s, Interpolation fallback) {
    if (s == "constant") return Interpolation::Constant;
    if (s == "uniform") return Interpolation::Uniform;
    if (s == "varying") return Interpolation::Varying;
    if (s == "vertex") return Interpolation::Vertex;
    if (s == "faceVarying") return Interpolation::FaceVarying;
    return fallback;
}

Interpolation attributeInterpolation(const usd::Attribute& a, Interpolation fallback) {
    if (const usd::Value* m = a.metadata("interpolation"))
        if (auto s = m->getString()) return parseInterpolation(*s, fallback);
    return fallback;
}

namespace {

bool isConstant(const usd::Attribute& a) {
    return attributeInterpolation(a, Interpolation::Constant) == Interpolation::Constant;
}

}  // namespace

std::vector<InheritedPrimvar> inheritablePrimvars(const usd::Prim* from) {
    std::vector<InheritedPrimvar> out;
    std::set<std::string> seen;
    for (const usd::Prim* p = from; p && p->path() != "/"; p = p->parent())
        for (const usd::Attribute* a : p->attributes()) {
            const std::string& n = a->name();
            if (n.rfind("primvars:", 0) != 0 || n.rfind("primvars:skel:", 0) == 0) continue;
            if (n.size() > 8 && n.compare(n.size() - 8, 8, ":indices") == 0) continue;
            if (!a->hasValue() || !seen.insert(n).second) continue;
            if (isConstant(*a)) out.push_back({p, a});
        }
    return out;
}

InheritedPrimvar inheritedPrimvar(const usd::Prim& prim, const std::string& attrName) {
    for (const usd::Prim* p = prim.parent(); p && p->path() != "/"; p = p->parent())
        if (const usd::Attribute* a = p->attribute(attrName); a && a->hasValue())
            return isConstant(*a) ? InheritedPrimvar{p, a} : InheritedPrimvar{};
    return {};
}

std::string inheritablePrimvarKey(const usd::Prim& prim, double time) {
    std::string key;
    for (const InheritedPrimvar& i : inheritablePrimvars(&prim)) {
        key += i.attribute->name() + "=" + i.attribute->get(time).toString();
        if (const usd::Attribute* idx = i.owner->attribute(i.attribute->name() + ":indices"); idx && idx->hasValue())
            key += "[" + idx->get(time).toString() + "]";
        key += ";";
    }
    return key;
}

}  // namespace principled::adapter
