// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/skinning.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string_view>
#include <tuple>
#include <unordered_map>

#include <glm/gtc/quaternion.hpp>

#include "scene_adapter/usda/prim.h"
#include "scene_adapter/usda/stage.h"
#include "scene_adapter/usda/value.h"
#include "scene_adapter/xformOps.h"

namespace principled::adapter {

namespace {

// The nearest prim at or above `p`, up to its SkelRoot, with a value (or targets) for `name`:
// UsdSkel resolves bindings within the SkelRoot.
const usd::Attribute* inheritedAttribute(const usd::Prim* p, const char* name) {
    for (; p; p = p->parent()) {
        if (const usd::Attribute* a = p->attribute(name); a && a->hasValue()) return a;
        if (p->typeName() == "SkelRoot") break;
    }
    return nullptr;
}
const usd::Relationship* inheritedRelationship(const usd::Prim* p, const char* name) {
    for (; p; p = p->parent()) {
        if (const usd::Relationship* r = p->relationship(name); r && !r->targets().empty()) return r;
        if (p->typeName() == "SkelRoot") break;
    }
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
// elementSize metadata (1 when absent); 0 when it is not a usable count.
int elementSize(const usd::Attribute* a) {
    if (const usd::Value* m = a->metadata("elementSize")) {
        const auto i = m->getInt();
        return i && *i >= 1 && *i <= 4096 ? int(*i) : 0;
    }
    return 1;
}
std::string interpolation(const usd::Attribute* a, const char* fallback) {
    if (const usd::Value* m = a->metadata("interpolation"))
        if (auto s = m->getString()) return *s;
    return fallback;
}

// One sub-shape of a BlendShape: its weight and its offsets (3 per point of the shape; empty
// for the rest shape at weight 0).
struct SubShape {
    double weight = 0.0;
    std::vector<double> offsets, normalOffsets;
};

// A BlendShape's sub-shapes sorted by weight: the rest (0), the shape itself (1) and its
// inbetweens (`inbetweens:NAME` point offsets with a `weight` metadatum, optional
// `inbetweens:NAME:normalOffsets`). Inbetweens at 0 or 1, without a weight, or with offsets
// that do not match the shape's points are left out with a warning.
std::vector<SubShape> blendSubShapes(const usd::Prim& shape, const std::vector<double>& offsets,
                                     const std::vector<double>& normalOffsets, size_t count, double time,
                                     std::vector<std::string>* warnings) {
    std::vector<SubShape> out{{0.0, {}, {}}, {1.0, offsets, normalOffsets}};
    constexpr std::string_view kPrefix = "inbetweens:";
    for (const usd::Attribute* a : shape.attributes()) {
        const std::string& name = a->name();
        if (name.rfind(kPrefix, 0) != 0 || name.find(':', kPrefix.size()) != std::string::npos) continue;
        const usd::Value* wm = a->metadata("weight");
        const std::optional<double> weight = wm ? wm->getDouble() : std::nullopt;
        // UsdSkelBlendShapeQuery's rule: within 1e-6 of 0 or 1 an inbetween would divide by ~0.
        if (!weight || !std::isfinite(*weight) || std::abs(*weight) <= 1e-6 || std::abs(*weight - 1.0) <= 1e-6) {
            warnings->push_back(shape.path() + "." + name + ": an inbetween needs a weight other than 0 and 1; skipped");
            continue;
        }
        SubShape sub{*weight, numbers(a, time, 3), {}};
        if (const usd::Attribute* n = shape.attribute(name + ":normalOffsets")) sub.normalOffsets = numbers(n, time, 3);
        if (sub.offsets.size() != 3 * count || (!sub.normalOffsets.empty() && sub.normalOffsets.size() != 3 * count)) {
            warnings->push_back(shape.path() + "." + name + ": inbetween offsets do not match the shape's " +
                                std::to_string(count) + " points; skipped");
            continue;
        }
        out.push_back(std::move(sub));
    }
    std::stable_sort(out.begin(), out.end(), [](const SubShape& a, const SubShape& b) { return a.weight < b.weight; });
    // Two sub-shapes at (nearly) one weight leave nothing to blend between: the first stays.
    for (size_t i = 1; i < out.size();) {
        if (out[i].weight - out[i - 1].weight <= 1e-6) {
            warnings->push_back(shape.path() + ": two inbetweens at weight " + std::to_string(out[i].weight) +
                                "; one is skipped");
            out.erase(out.begin() + std::ptrdiff_t(out[i].offsets.empty() ? i - 1 : i));
        } else {
            ++i;
        }
    }
    return out;
}

// The two sub-shapes a blend weight w falls between (the nearest two beyond the ends) and w's
// position from the lower to the upper one.
std::tuple<const SubShape*, const SubShape*, double> bracketSubShapes(const std::vector<SubShape>& subs, double w) {
    auto it = std::upper_bound(subs.begin(), subs.end(), w, [](double v, const SubShape& s) { return v < s.weight; });
    const size_t upper = it == subs.end() ? subs.size() - 1 : std::max<size_t>(1, size_t(it - subs.begin()));
    const SubShape* lo = &subs[upper - 1];
    const SubShape* hi = &subs[upper];
    return {lo, hi, (w - lo->weight) / (hi->weight - lo->weight)};
}

// Joint i's parent: the joint whose path is the longest proper prefix of its own ("A/B/C" ->
// "A/B", or "A" when "A/B" is not a joint), found in one walk down a trie of path segments
// (linear in the total length: hashing every prefix was quadratic in a path's length).
std::vector<int> jointParents(const std::vector<std::string>& joints) {
    struct Node {
        std::unordered_map<std::string_view, size_t> children;
        int joint = -1;
    };
    std::vector<Node> trie(1);
    auto forEachSegment = [](const std::string& path, auto&& fn) {
        size_t start = 0;
        while (start <= path.size()) {
            size_t end = path.find('/', start);
            if (end == std::string::npos) end = path.size();
            fn(std::string_view(path).substr(start, end - start));
            start = end + 1;
        }
    };
    std::vector<size_t> nodeOf(joints.size());
    for (size_t i = 0; i < joints.size(); ++i) {
        size_t node = 0;
        forEachSegment(joints[i], [&](std::string_view seg) {
            auto it = trie[node].children.find(seg);
            if (it == trie[node].children.end()) {
                trie.emplace_back();
                it = trie[node].children.emplace(seg, trie.size() - 1).first;
            }
            node = it->second;
        });
        if (trie[node].joint < 0) trie[node].joint = int(i);  // the first of duplicate names
        nodeOf[i] = node;
    }
    std::vector<int> parent(joints.size(), -1);
    for (size_t i = 0; i < joints.size(); ++i) {
        size_t node = 0;
        int last = -1;
        forEachSegment(joints[i], [&](std::string_view seg) {
            if (trie[node].joint >= 0 && node != 0) last = trie[node].joint;
            node = trie[node].children.at(seg);
        });
        parent[i] = last == int(i) ? -1 : last;
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

namespace {

// The pose of Skeleton `skel` at `time` (see SkeletonPose); warnings about its animation.
std::shared_ptr<const SkeletonPose> computePose(const usd::Stage& stage, const usd::Prim& skel, double time,
                                                std::vector<std::string>* warnings) {
    auto pose = std::make_shared<SkeletonPose>();
    auto fail = [&](const std::string& why) {
        pose->error = why;
        return pose;
    };
    // The skeleton: joints, bind pose (skeleton space), rest pose (joint-local).
    pose->joints = tokens(skel.attribute("joints"), time);
    const std::vector<std::string>& joints = pose->joints;
    const size_t nj = joints.size();
    if (nj == 0) return fail("its Skeleton has no joints");
    const std::vector<glm::dmat4> bind = matrices(skel.attribute("bindTransforms"), time);
    if (bind.size() != nj)
        return fail("bindTransforms has " + std::to_string(bind.size()) + " matrices for " + std::to_string(nj) + " joints");
    const std::vector<glm::dmat4> rest = matrices(skel.attribute("restTransforms"), time);
    if (!rest.empty() && rest.size() != nj)
        warnings->push_back(skel.path() + ": restTransforms has " + std::to_string(rest.size()) + " matrices for " +
                            std::to_string(nj) + " joints; the bind pose is used");
    const std::vector<int> parent = jointParents(joints);
    std::vector<glm::dmat4> local(nj);
    for (size_t j = 0; j < nj; ++j) {
        // Without a rest pose the bind pose stands in: each joint's local transform from it.
        local[j] = rest.size() == nj ? rest[j] : (parent[j] < 0 ? bind[j] : glm::inverse(bind[size_t(parent[j])]) * bind[j]);
    }
    // The animation's joints override theirs (skel:animationSource on the Skeleton or above).
    if (const usd::Relationship* animRel = inheritedRelationship(&skel, "skel:animationSource")) {
        const usd::Prim* anim = stage.prim(animRel->targets().front());
        if (!anim || anim->typeName() != "SkelAnimation" || !anim->isActive()) {
            warnings->push_back(skel.path() + ": skel:animationSource <" + animRel->targets().front() +
                                "> is not an active SkelAnimation; the rest pose is used");
        } else {
            const std::vector<std::string> animJoints = tokens(anim->attribute("joints"), time);
            const std::vector<double> t = numbers(anim->attribute("translations"), time, 3);
            const std::vector<double> r = numbers(anim->attribute("rotations"), time, 4);
            const std::vector<double> sc = numbers(anim->attribute("scales"), time, 3);
            const size_t na = animJoints.size();
            const bool haveT = t.size() == 3 * na, haveR = r.size() == 4 * na, haveS = sc.size() == 3 * na;
            if (na > 0 && !(haveT && haveR && haveS))
                warnings->push_back(anim->path() + ": translations, rotations or scales do not match its " +
                                    std::to_string(na) + " joints; the rest pose stands in for them");
            const std::vector<std::string> shapes = tokens(anim->attribute("blendShapes"), time);
            const std::vector<double> shapeWeights = numbers(anim->attribute("blendShapeWeights"), time, 1);
            if (shapes.size() == shapeWeights.size()) {
                for (size_t k = 0; k < shapes.size(); ++k)
                    if (std::isfinite(shapeWeights[k])) pose->blendShapeWeights.emplace(shapes[k], shapeWeights[k]);
            } else {
                warnings->push_back(anim->path() + ": blendShapeWeights has " + std::to_string(shapeWeights.size()) +
                                    " values for " + std::to_string(shapes.size()) + " blendShapes; ignored");
            }
            std::unordered_map<std::string, size_t> skelIndex;
            for (size_t j = 0; j < nj; ++j) skelIndex.emplace(joints[j], j);
            for (size_t a = 0; a < na && (haveT || haveR || haveS); ++a) {
                auto it = skelIndex.find(animJoints[a]);
                if (it == skelIndex.end()) continue;  // a joint this skeleton does not have
                // Components the animation does not give come from the rest pose's columns.
                const glm::dmat4& base = local[it->second];
                glm::dvec3 tr(base[3]);
                glm::dvec3 scale(glm::length(glm::dvec3(base[0])), glm::length(glm::dvec3(base[1])),
                                 glm::length(glm::dvec3(base[2])));
                glm::dquat q(1.0, 0.0, 0.0, 0.0);
                if (scale.x > 0.0 && scale.y > 0.0 && scale.z > 0.0)
                    q = glm::quat_cast(glm::dmat3(glm::dvec3(base[0]) / scale.x, glm::dvec3(base[1]) / scale.y,
                                                  glm::dvec3(base[2]) / scale.z));
                if (haveT) tr = glm::dvec3(t[3 * a], t[3 * a + 1], t[3 * a + 2]);
                if (haveR) q = glm::dquat(r[4 * a], r[4 * a + 1], r[4 * a + 2], r[4 * a + 3]);  // (real, i, j, k)
                if (haveS) scale = glm::dvec3(sc[3 * a], sc[3 * a + 1], sc[3 * a + 2]);
                local[it->second] = compose(tr, q, scale);
            }
        }
    }
    // Skeleton space: each joint's local transform under its parent's (any order of joints;
    // parents are proper path prefixes, so there is no cycle).
    std::vector<glm::dmat4> skelSpace(nj);
    std::vector<char> done(nj, 0);
    std::vector<size_t> chain;
    for (size_t j = 0; j < nj; ++j) {
        for (size_t k = j; !done[k]; k = size_t(parent[k])) {
            chain.push_back(k);
            if (parent[k] < 0) break;
        }
        for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
            const size_t k = *it;
            if (done[k]) continue;
            skelSpace[k] = parent[k] < 0 ? local[k] : skelSpace[size_t(parent[k])] * local[k];
            done[k] = 1;
        }
        chain.clear();
    }
    pose->skinning.resize(nj);
    for (size_t j = 0; j < nj; ++j) pose->skinning[j] = skelSpace[j] * glm::inverse(bind[j]);
    pose->world = worldTransform(skel, time);
    return pose;
}

}  // namespace

std::optional<SkinnedMesh> skinMesh(const usd::Stage& stage, const usd::Prim& mesh, double time,
                                    std::vector<std::string>* warnings, SkeletonPoseCache* cache) {
    // Skinning applies under a SkelRoot, to a prim with joint influences and a bound skeleton.
    bool underRoot = false;
    for (const usd::Prim* p = &mesh; p && !underRoot; p = p->parent()) underRoot = p->typeName() == "SkelRoot";
    if (!underRoot) return std::nullopt;
    const usd::Attribute* indicesAttr = inheritedAttribute(&mesh, "primvars:skel:jointIndices");
    const usd::Attribute* weightsAttr = inheritedAttribute(&mesh, "primvars:skel:jointWeights");
    const usd::Relationship* skelRel = inheritedRelationship(&mesh, "skel:skeleton");
    const bool haveInfluences = indicesAttr && weightsAttr;
    const usd::Relationship* shapeTargets = mesh.relationship("skel:blendShapeTargets");
    const bool haveShapes = shapeTargets && !shapeTargets->targets().empty() && mesh.attribute("skel:blendShapes");
    if (!skelRel || (!haveInfluences && !haveShapes)) return std::nullopt;
    auto fail = [&](const std::string& why) -> std::optional<SkinnedMesh> {
        warnings->push_back("not skinned (drawn as authored): " + why);
        return std::nullopt;
    };
    const std::string& skelPath = skelRel->targets().front();
    const usd::Prim* skel = stage.prim(skelPath);
    if (!skel || skel->typeName() != "Skeleton") return fail("skel:skeleton <" + skelPath + "> is not a Skeleton");
    if (!skel->isActive()) return fail("its Skeleton <" + skelPath + "> is inactive");
    std::shared_ptr<const SkeletonPose> pose;
    if (cache)
        if (auto it = cache->find(skelPath); it != cache->end()) pose = it->second;
    if (!pose) {
        pose = computePose(stage, *skel, time, warnings);
        if (cache) cache->emplace(skelPath, pose);
    }
    if (!pose->error.empty()) return fail(pose->error);
    const std::vector<std::string>& joints = pose->joints;
    const size_t nj = joints.size();

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
    std::vector<glm::dvec3> base(np);
    for (size_t i = 0; i < np; ++i) base[i] = glm::dvec3((*pts)[3 * i], (*pts)[3 * i + 1], (*pts)[3 * i + 2]);
    std::vector<glm::dvec3> normalOffsets;  // per point, from the blend shapes (empty: none)
    if (haveShapes) {
        // Blend shapes, in the mesh's bind space before skinning: weight * offsets per shape.
        const std::vector<std::string> names = tokens(mesh.attribute("skel:blendShapes"), time);
        const std::vector<std::string>& targets = shapeTargets->targets();
        if (names.size() != targets.size())
            return fail("skel:blendShapes names " + std::to_string(names.size()) + " shapes for " +
                        std::to_string(targets.size()) + " skel:blendShapeTargets");
        for (size_t k = 0; k < names.size(); ++k) {
            const auto w = pose->blendShapeWeights.find(names[k]);
            if (w == pose->blendShapeWeights.end() || w->second == 0.0) continue;
            const usd::Prim* shape = stage.prim(targets[k]);
            if (!shape || shape->typeName() != "BlendShape" || !shape->isActive())
                return fail("skel:blendShapeTargets <" + targets[k] + "> is not an active BlendShape");
            const std::vector<double> offsets = numbers(shape->attribute("offsets"), time, 3);
            const std::vector<double> nOffsets = numbers(shape->attribute("normalOffsets"), time, 3);
            const usd::Attribute* sparse = shape->attribute("pointIndices");
            const std::vector<double> indices = numbers(sparse, time, 1);
            const size_t count = sparse && sparse->hasValue() ? indices.size() : np;
            if (offsets.size() != 3 * count || (!nOffsets.empty() && nOffsets.size() != 3 * count))
                return fail(shape->path() + ": offsets (" + std::to_string(offsets.size() / 3) + ") do not match its " +
                            std::to_string(count) + " points");
            // Sub-shapes (UsdSkelBlendShapeQuery): the rest at weight 0, the shape at 1 and its
            // inbetweens at their own weights; a weight between two of them blends those two
            // linearly, one beyond them all extrapolates the nearest two.
            const std::vector<SubShape> subShapes = blendSubShapes(*shape, offsets, nOffsets, count, time, warnings);
            const auto [lower, upper, alpha] = bracketSubShapes(subShapes, w->second);
            if ((!lower->normalOffsets.empty() || !upper->normalOffsets.empty()) && normalOffsets.empty())
                normalOffsets.assign(np, glm::dvec3(0.0));
            for (const auto& [sub, weight] : {std::pair{lower, 1.0 - alpha}, std::pair{upper, alpha}}) {
                if (sub->offsets.empty() || weight == 0.0) continue;  // the rest shape adds nothing
                for (size_t j = 0; j < count; ++j) {
                    const double target = sparse && sparse->hasValue() ? indices[j] : double(j);
                    if (!(target >= 0.0 && target < double(np))) return fail(shape->path() + ": a point index is out of range");
                    const size_t point = size_t(target);
                    const std::vector<double>& o = sub->offsets;
                    base[point] += weight * glm::dvec3(o[3 * j], o[3 * j + 1], o[3 * j + 2]);
                    if (!sub->normalOffsets.empty()) {
                        const std::vector<double>& n = sub->normalOffsets;
                        normalOffsets[point] += weight * glm::dvec3(n[3 * j], n[3 * j + 1], n[3 * j + 2]);
                    }
                }
            }
        }
    }
    const int ni = haveInfluences ? elementSize(indicesAttr) : 1, nw = haveInfluences ? elementSize(weightsAttr) : 1;
    if (ni != nw || ni <= 0)
        return fail("jointIndices and jointWeights have elementSize " + std::to_string(ni) + " and " + std::to_string(nw));
    // Without joint influences (blend shapes alone) the mesh is not skinned: one empty influence
    // set (weight 0), i.e. the identity, and the mesh keeps its own transform.
    const std::vector<double> jointIndices = haveInfluences ? numbers(indicesAttr, time, 1) : std::vector<double>{0.0};
    const std::vector<double> jointWeights = haveInfluences ? numbers(weightsAttr, time, 1) : std::vector<double>{0.0};
    const bool rigid = !haveInfluences || interpolation(indicesAttr, "constant") == "constant";
    const size_t influences = rigid ? 1 : np;
    if (jointIndices.size() != influences * size_t(ni) || jointWeights.size() != influences * size_t(ni))
        return fail("jointIndices/jointWeights hold " + std::to_string(jointIndices.size()) + "/" +
                    std::to_string(jointWeights.size()) + " values, expected " + std::to_string(influences * size_t(ni)));
    const glm::dmat4 geomBind = [&] {
        const usd::Attribute* a = haveInfluences ? inheritedAttribute(&mesh, "primvars:skel:geomBindTransform") : nullptr;
        if (a)
            if (auto flat = a->get(time).getTuple(); flat && flat->size() == 16) return matrixAt(*flat, 0);
        return glm::dmat4(1.0);
    }();

    // Blended matrix per influence set.
    std::vector<glm::dmat4> blended(influences);
    for (size_t k = 0; k < influences; ++k) {
        glm::dmat4 m(0.0);
        double sum = 0.0;
        for (int e = 0; e < ni; ++e) {
            const double w = jointWeights[k * size_t(ni) + size_t(e)];
            const double jiD = jointIndices[k * size_t(ni) + size_t(e)];
            if (!(w > 0.0) || !std::isfinite(w)) continue;  // unused slots hold weight 0
            const double range = double(remap.empty() ? nj : remap.size());
            if (!(jiD >= 0.0 && jiD < range) || jiD != std::floor(jiD))
                return fail("joint index " + std::to_string(jiD) + " is out of range");
            int ji = int(jiD);
            if (!remap.empty()) ji = remap[size_t(ji)];
            if (!finiteMatrix(pose->skinning[size_t(ji)]))
                return fail("joint '" + joints[size_t(ji)] + "' has a singular or non-finite transform");
            m += w * pose->skinning[size_t(ji)];
            sum += w;
        }
        blended[k] = (sum > 0.0 ? m / sum : glm::dmat4(1.0)) * geomBind;  // normalised; none: as bound
    }

    SkinnedMesh out;
    out.skeleton = skel->path();
    out.world = haveInfluences ? pose->world : worldTransform(mesh, time);
    out.inSkeletonSpace = haveInfluences;
    out.points.resize(np);
    for (size_t i = 0; i < np; ++i) out.points[i] = glm::vec3(blended[rigid ? 0 : i] * glm::dvec4(base[i], 1.0));
    // Normals per point (vertex/varying) or per corner (faceVarying), unindexed. Interpolation
    // fallbacks as the delegate reads them: vertex for `normals`, constant for the primvar.
    const usd::Attribute* normalsAttr = mesh.attribute("primvars:normals");
    const bool primvar = normalsAttr && normalsAttr->hasValue();
    if (!primvar) normalsAttr = mesh.attribute("normals");
    if (normalsAttr && normalsAttr->hasValue()) {
        const std::vector<double> n = numbers(normalsAttr, time, 3);
        const std::string interp = interpolation(normalsAttr, primvar ? "constant" : "vertex");
        const std::vector<double> corners = numbers(mesh.attribute("faceVertexIndices"), time, 1);
        const bool indexed = mesh.attribute("primvars:normals:indices") != nullptr;
        const bool perPoint = !indexed && (interp == "vertex" || interp == "varying") && n.size() == 3 * np;
        const bool perCorner = !indexed && interp == "faceVarying" && n.size() == 3 * corners.size();
        if (perPoint || perCorner) {
            std::vector<glm::dmat3> normalMatrix(influences);
            for (size_t k = 0; k < influences; ++k) normalMatrix[k] = glm::transpose(glm::inverse(glm::dmat3(blended[k])));
            out.normals.resize(n.size() / 3);
            for (size_t c = 0; c < out.normals.size(); ++c) {
                const double corner = perPoint ? double(c) : corners[c];
                const size_t point = corner >= 0.0 && corner < double(np) ? size_t(corner) : 0;
                glm::dvec3 authored(n[3 * c], n[3 * c + 1], n[3 * c + 2]);
                if (!normalOffsets.empty()) authored += normalOffsets[point];
                glm::dvec3 nn = normalMatrix[rigid ? 0 : point] * authored;
                double l = glm::length(nn);
                if (!(l > 0.0) || !std::isfinite(l)) nn = authored, l = glm::length(authored);  // a singular blend
                out.normals[c] = l > 0.0 && std::isfinite(l) ? glm::vec3(nn / l) : glm::vec3(0.0f, 0.0f, 1.0f);
            }
        } else {
            warnings->push_back("normals (" + interp + (indexed ? ", indexed" : "") +
                                ") are not posed with the skeleton; they are dropped");
        }
    }
    for (const glm::vec3& p : out.points)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return fail("the posed points are not finite");
    return out;
}

}  // namespace principled::adapter
