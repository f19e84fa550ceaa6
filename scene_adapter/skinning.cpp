// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/skinning.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <glm/gtc/quaternion.hpp>

#include "scene_adapter/usda/prim.h"
#include "scene_adapter/usda/stage.h"
#include "scene_adapter/usda/value.h"
#include "scene_adapter/xformOps.h"

namespace principled::adapter {

namespace {

// The nearest prim at or above `p` with a value (or targets) for `name`.
const usd::Attribute* inheritedAttribute(const usd::Prim* p, const char* name) {
    for (; p; p = p->parent())
        if (const usd::Attribute* a = p->attribute(name); a && a->hasValue()) return a;
    return nullptr;
}
const usd::Relationship* inheritedRelationship(const usd::Prim* p, const char* name) {
    for (; p; p = p->parent())
        if (const usd::Relationship* r = p->relationship(name); r && !r->targets().empty()) return r;
    return nullptr;
}

// USD matrices are row-vector with the translation in the last row: their rows are the
// column-vector matrix's columns (as xformOp:transform reads them).
glm::dmat4 matrixAt(const std::vector<double>& flat, size_t i) {
    glm::dmat4 m;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m[c][r] = flat[16 * i + size_t(c * 4 + r)];
    return m;
}
std::vector<glm::dmat4> matrices(const usd::Attribute* a, double time) {
    std::vector<glm::dmat4> out;
    if (!a) return out;
    const usd::Value v = a->get(time);
    const std::vector<double>* n = v.numbers();
    if (!n || v.components() != 16) return out;
    for (size_t i = 0; i < n->size() / 16; ++i) out.push_back(matrixAt(*n, i));
    return out;
}
std::vector<std::string> tokens(const usd::Attribute* a, double time) {
    if (!a) return {};
    const usd::Value v = a->get(time);
    const std::vector<std::string>* s = v.strings();
    return s ? *s : std::vector<std::string>();
}
std::vector<double> numbers(const usd::Attribute* a, double time, int components) {
    if (!a) return {};
    const usd::Value v = a->get(time);
    const std::vector<double>* n = v.numbers();
    if (!n || v.components() != components) return {};
    return *n;
}
int elementSize(const usd::Attribute* a) {
    if (const usd::Value* m = a->metadata("elementSize"))
        if (auto i = m->getInt()) return int(*i);
    return 1;
}
std::string interpolation(const usd::Attribute* a, const char* fallback) {
    if (const usd::Value* m = a->metadata("interpolation"))
        if (auto s = m->getString()) return *s;
    return fallback;
}

// Joint i's parent: the longest proper prefix of its path that is a joint ("A/B/C" -> "A/B").
std::vector<int> jointParents(const std::vector<std::string>& joints) {
    std::unordered_map<std::string, int> index;
    for (size_t i = 0; i < joints.size(); ++i) index.emplace(joints[i], int(i));
    std::vector<int> parent(joints.size(), -1);
    for (size_t i = 0; i < joints.size(); ++i) {
        std::string p = joints[i];
        for (size_t slash = p.rfind('/'); slash != std::string::npos; slash = p.rfind('/')) {
            p.resize(slash);
            if (auto it = index.find(p); it != index.end()) {
                parent[i] = it->second;
                break;
            }
        }
    }
    return parent;
}

// Translation, rotation (real first) and scale as one column-vector matrix: T * R * S
// (UsdSkel's component order: scale, then rotate, then translate).
glm::dmat4 compose(const glm::dvec3& t, const glm::dquat& r, const glm::dvec3& s) {
    const double len = glm::length(r);
    const glm::dmat3 rot = len > 0.0 && std::isfinite(len) ? glm::mat3_cast(r / len) : glm::dmat3(1.0);
    glm::dmat4 m(1.0);
    m[0] = glm::dvec4(rot[0] * s.x, 0.0);
    m[1] = glm::dvec4(rot[1] * s.y, 0.0);
    m[2] = glm::dvec4(rot[2] * s.z, 0.0);
    m[3] = glm::dvec4(t, 1.0);
    return m;
}

bool finiteMatrix(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

}  // namespace

glm::dmat4 worldTransform(const usd::Prim& prim, double time) {
    std::vector<const usd::Prim*> chain;
    for (const usd::Prim* p = &prim; p && p->parent(); p = p->parent()) chain.push_back(p);
    glm::dmat4 world(1.0);
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
        std::string warning;
        const LocalTransform local = computeLocalTransform(**it, time, &warning);
        world = local.resetsXformStack ? local.matrix : world * local.matrix;
    }
    return world;
}

std::optional<SkinnedMesh> skinMesh(const usd::Stage& stage, const usd::Prim& mesh, double time,
                                    std::vector<std::string>* warnings) {
    // Skinning applies under a SkelRoot, to a prim with joint influences and a bound skeleton.
    bool underRoot = false;
    for (const usd::Prim* p = &mesh; p && !underRoot; p = p->parent()) underRoot = p->typeName() == "SkelRoot";
    const usd::Attribute* indicesAttr = inheritedAttribute(&mesh, "primvars:skel:jointIndices");
    const usd::Attribute* weightsAttr = inheritedAttribute(&mesh, "primvars:skel:jointWeights");
    const usd::Relationship* skelRel = inheritedRelationship(&mesh, "skel:skeleton");
    if (!indicesAttr || !weightsAttr || !skelRel) return std::nullopt;
    auto fail = [&](const std::string& why) -> std::optional<SkinnedMesh> {
        warnings->push_back("not skinned (drawn in its bind pose): " + why);
        return std::nullopt;
    };
    if (!underRoot) return fail("it is not under a SkelRoot");
    const usd::Prim* skel = stage.prim(skelRel->targets().front());
    if (!skel || skel->typeName() != "Skeleton") return fail("skel:skeleton <" + skelRel->targets().front() + "> is not a Skeleton");

    // The skeleton: joints, bind pose (world space), rest pose (local space).
    const std::vector<std::string> joints = tokens(skel->attribute("joints"), time);
    const size_t nj = joints.size();
    if (nj == 0) return fail("its Skeleton has no joints");
    const std::vector<glm::dmat4> bind = matrices(skel->attribute("bindTransforms"), time);
    if (bind.size() != nj) return fail("bindTransforms has " + std::to_string(bind.size()) + " matrices for " + std::to_string(nj) + " joints");
    std::vector<glm::dmat4> rest = matrices(skel->attribute("restTransforms"), time);
    const std::vector<int> parent = jointParents(joints);
    std::vector<glm::dmat4> local(nj);
    for (size_t j = 0; j < nj; ++j) {
        // Without a rest pose the bind pose stands in: each joint's local transform from it.
        local[j] = rest.size() == nj ? rest[j] : (parent[j] < 0 ? bind[j] : glm::inverse(bind[size_t(parent[j])]) * bind[j]);
    }
    // The animation's joints override theirs (skel:animationSource on the Skeleton or above).
    if (const usd::Relationship* animRel = inheritedRelationship(skel, "skel:animationSource")) {
        const usd::Prim* anim = stage.prim(animRel->targets().front());
        if (!anim || anim->typeName() != "SkelAnimation") {
            warnings->push_back(skel->path() + ": skel:animationSource <" + animRel->targets().front() +
                                "> is not a SkelAnimation; the rest pose is used");
        } else {
            const std::vector<std::string> animJoints = tokens(anim->attribute("joints"), time);
            const std::vector<double> t = numbers(anim->attribute("translations"), time, 3);
            const std::vector<double> r = numbers(anim->attribute("rotations"), time, 4);
            const std::vector<double> s = numbers(anim->attribute("scales"), time, 3);
            const size_t na = animJoints.size();
            const bool haveT = t.size() == 3 * na, haveR = r.size() == 4 * na, haveS = s.size() == 3 * na;
            if (na > 0 && !(haveT || haveR || haveS))
                warnings->push_back(anim->path() + ": translations, rotations and scales do not match its " +
                                    std::to_string(na) + " joints; the rest pose is used");
            std::unordered_map<std::string, size_t> skelIndex;
            for (size_t j = 0; j < nj; ++j) skelIndex.emplace(joints[j], j);
            for (size_t a = 0; a < na && (haveT || haveR || haveS); ++a) {
                auto it = skelIndex.find(animJoints[a]);
                if (it == skelIndex.end()) continue;  // a joint this skeleton does not have
                // Components the animation does not give come from the rest pose's columns.
                const glm::dmat4& base = local[it->second];
                glm::dvec3 tr(base[3]);
                glm::dvec3 sc(glm::length(glm::dvec3(base[0])), glm::length(glm::dvec3(base[1])), glm::length(glm::dvec3(base[2])));
                glm::dmat3 rot(glm::dvec3(base[0]) / sc.x, glm::dvec3(base[1]) / sc.y, glm::dvec3(base[2]) / sc.z);
                glm::dquat q = glm::quat_cast(rot);
                if (haveT) tr = glm::dvec3(t[3 * a], t[3 * a + 1], t[3 * a + 2]);
                if (haveR) q = glm::dquat(r[4 * a], r[4 * a + 1], r[4 * a + 2], r[4 * a + 3]);  // (real, i, j, k)
                if (haveS) sc = glm::dvec3(s[3 * a], s[3 * a + 1], s[3 * a + 2]);
                local[it->second] = compose(tr, q, sc);
            }
        }
    }
    // Skeleton space: each joint's local transform under its parent's (any order of joints).
    std::vector<glm::dmat4> skelSpace(nj);
    std::vector<char> state(nj, 0);  // 0 todo, 1 in progress, 2 done
    bool cycle = false;
    auto resolve = [&](auto&& self, size_t j) -> const glm::dmat4& {
        if (state[j] == 2) return skelSpace[j];
        if (state[j] == 1) {  // cannot happen with path prefixes; guard anyway
            cycle = true;
            return skelSpace[j];
        }
        state[j] = 1;
        skelSpace[j] = parent[j] < 0 ? local[j] : self(self, size_t(parent[j])) * local[j];
        state[j] = 2;
        return skelSpace[j];
    };
    std::vector<glm::dmat4> skinning(nj);
    for (size_t j = 0; j < nj; ++j) {
        skinning[j] = resolve(resolve, j) * glm::inverse(bind[j]);
        if (!finiteMatrix(skinning[j])) return fail("joint '" + joints[j] + "' has a singular or non-finite transform");
    }
    if (cycle) return fail("the joint hierarchy has a cycle");

    // The mesh's influences, through its own joint order when it has one (skel:joints).
    std::vector<int> remap;
    if (const usd::Attribute* own = inheritedAttribute(&mesh, "skel:joints")) {
        std::unordered_map<std::string, int> skelIndex;
        for (size_t j = 0; j < nj; ++j) skelIndex.emplace(joints[j], int(j));
        for (const std::string& name : tokens(own, time)) {
            auto it = skelIndex.find(name);
            if (it == skelIndex.end()) return fail("skel:joints names '" + name + "', which its Skeleton does not have");
            remap.push_back(it->second);
        }
    }
    const usd::Value pointsValue = mesh.attribute("points") ? mesh.attribute("points")->get(time) : usd::Value();
    const std::vector<double>* pts = pointsValue.numbers();
    if (!pts || pointsValue.components() != 3 || pts->empty()) return std::nullopt;  // nothing to pose
    const size_t np = pts->size() / 3;
    const int ni = elementSize(indicesAttr), nw = elementSize(weightsAttr);
    const std::vector<double> jointIndices = numbers(indicesAttr, time, 1);
    const std::vector<double> jointWeights = numbers(weightsAttr, time, 1);
    if (ni != nw || ni <= 0) return fail("jointIndices and jointWeights have elementSize " + std::to_string(ni) + " and " + std::to_string(nw));
    const bool rigid = interpolation(indicesAttr, "constant") == "constant";
    const size_t influences = rigid ? 1 : np;
    if (jointIndices.size() != influences * size_t(ni) || jointWeights.size() != influences * size_t(ni))
        return fail("jointIndices/jointWeights hold " + std::to_string(jointIndices.size()) + "/" +
                    std::to_string(jointWeights.size()) + " values, expected " + std::to_string(influences * size_t(ni)));
    const glm::dmat4 geomBind = [&] {
        std::vector<glm::dmat4> g = matrices(inheritedAttribute(&mesh, "primvars:skel:geomBindTransform"), time);
        if (g.empty()) {  // a single matrix4d, not an array
            if (const usd::Attribute* a = inheritedAttribute(&mesh, "primvars:skel:geomBindTransform"))
                if (auto flat = a->get(time).getTuple(); flat && flat->size() == 16) return matrixAt(*flat, 0);
            return glm::dmat4(1.0);
        }
        return g.front();
    }();

    // Blended matrix per influence set.
    std::vector<glm::dmat4> blended(influences);
    for (size_t k = 0; k < influences; ++k) {
        glm::dmat4 m(0.0);
        double sum = 0.0;
        for (int e = 0; e < ni; ++e) {
            const double w = jointWeights[k * size_t(ni) + size_t(e)];
            const double jiD = jointIndices[k * size_t(ni) + size_t(e)];
            if (!(w > 0.0)) continue;  // unused slots hold weight 0
            int ji = int(jiD);
            if (!remap.empty()) ji = (ji >= 0 && size_t(ji) < remap.size()) ? remap[size_t(ji)] : -1;
            if (ji < 0 || size_t(ji) >= nj || double(int(jiD)) != jiD)
                return fail("joint index " + std::to_string(jiD) + " is out of range");
            m += w * skinning[size_t(ji)];
            sum += w;
        }
        blended[k] = sum > 0.0 ? m / sum : glm::dmat4(1.0);  // weights normalised; none: bind pose
        blended[k] = blended[k] * geomBind;
    }

    SkinnedMesh out;
    out.skeleton = skel->path();
    out.world = worldTransform(*skel, time);
    out.points.resize(np);
    for (size_t i = 0; i < np; ++i) {
        const glm::dvec4 p((*pts)[3 * i], (*pts)[3 * i + 1], (*pts)[3 * i + 2], 1.0);
        out.points[i] = glm::vec3(blended[rigid ? 0 : i] * p);
    }
    // Normals per point (vertex/varying) or per corner (faceVarying), unindexed.
    const usd::Attribute* normalsAttr = mesh.attribute("primvars:normals");
    if (!normalsAttr || !normalsAttr->hasValue()) normalsAttr = mesh.attribute("normals");
    if (normalsAttr && normalsAttr->hasValue()) {
        const std::vector<double> n = numbers(normalsAttr, time, 3);
        const std::string interp = interpolation(normalsAttr, "vertex");
        const std::vector<double> corners = numbers(mesh.attribute("faceVertexIndices"), time, 1);
        const bool indexed = mesh.attribute("primvars:normals:indices") != nullptr;
        const bool perPoint = !indexed && (interp == "vertex" || interp == "varying") && n.size() == 3 * np;
        const bool perCorner = !indexed && interp == "faceVarying" && n.size() == 3 * corners.size();
        if (perPoint || perCorner) {
            std::vector<glm::dmat3> normalMatrix(influences);
            for (size_t k = 0; k < influences; ++k) normalMatrix[k] = glm::transpose(glm::inverse(glm::dmat3(blended[k])));
            out.normals.resize(n.size() / 3);
            for (size_t c = 0; c < out.normals.size(); ++c) {
                size_t point = perPoint ? c : size_t(corners[c]);
                if (point >= np) point = 0;
                const glm::dvec3 nn = normalMatrix[rigid ? 0 : point] * glm::dvec3(n[3 * c], n[3 * c + 1], n[3 * c + 2]);
                const double l = glm::length(nn);
                out.normals[c] = l > 0.0 && std::isfinite(l) ? glm::vec3(nn / l) : glm::vec3(0.0f, 0.0f, 1.0f);
            }
        } else {
            warnings->push_back("normals (" + interp + ", or indexed) are not posed with the skeleton; they are dropped");
        }
    }
    for (const glm::vec3& p : out.points)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return fail("the posed points are not finite");
    return out;
}

}  // namespace principled::adapter
