// SPDX-License-Identifier: Apache-2.0
#include "delegate/instancer.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/quaternion.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "delegate/hd/sceneDelegate.h"
#include "delegate/hd/tokens.h"
#include "delegate/transformCheck.h"

namespace principled::embree {

using namespace hd;

glm::mat4 instanceTransform(const glm::mat4& instancer, const glm::vec3& position,
                            const glm::vec4& rotation, const glm::vec3& scale,
                            const glm::mat4& prototype) {
    glm::quat q(rotation.x, rotation.y, rotation.z, rotation.w);  // glm: (w, x, y, z)
    float len = glm::length(q);
    glm::mat3 r = (len > 0.0f && std::isfinite(len)) ? glm::mat3_cast(q / len) : glm::mat3(1.0f);
    // Column-vector convention: scale first, then rotate, then translate.
    glm::mat4 m(1.0f);
    m[0] = glm::vec4(r[0] * scale.x, 0.0f);
    m[1] = glm::vec4(r[1] * scale.y, 0.0f);
    m[2] = glm::vec4(r[2] * scale.z, 0.0f);
    m[3] = glm::vec4(position, 1.0f);
    return instancer * m * prototype;
}

std::vector<InstanceRecord> computeInstances(const SceneDelegate* delegate, const Path& instancerId,
                                             const Path& prototypeId,
                                             const glm::mat4& prototypeTransform,
                                             std::vector<std::string>* warnings,
                                             InstancerPrimvarCache* primvarCache) {
    std::vector<int> indices = delegate->getInstanceIndices(instancerId, prototypeId);
    // Shared by every prototype of the instancer (no per-prototype copy of the arrays).
    const std::shared_ptr<const InstancerArrays> arrays = delegate->getInstancerArrays(instancerId);
    const auto* t = arrays->translations ? &*arrays->translations : nullptr;
    const auto* r = arrays->rotations ? &*arrays->rotations : nullptr;
    const auto* s = arrays->scales ? &*arrays->scales : nullptr;
    // Whole matrices per instance (native USD instancing), applied before scale.
    const auto* x = arrays->transforms ? &*arrays->transforms : nullptr;
    size_t count = t ? t->size() : x ? x->size() : 0;
    if (x && x->size() != count) {
        warnings->push_back("instanceTransforms has the wrong length; ignored");
        x = nullptr;
    }
    if (t && t->size() != count) t = nullptr;
    if (!t && !x && !indices.empty())
        warnings->push_back("instancer has no positions; its instances are not drawn");
    if (r && r->size() != count) {
        warnings->push_back("orientations has " + std::to_string(r->size()) + " values for " +
                            std::to_string(count) + " positions; ignored");
        r = nullptr;
    }
    if (s && s->size() != count) {
        warnings->push_back("scales has " + std::to_string(s->size()) + " values for " +
                            std::to_string(count) + " positions; ignored");
        s = nullptr;
    }
    glm::mat4 instancer(delegate->getTransform(instancerId));
    // The instancer's per-instance primvars, for the prototypes' materials.
    const InstancerPrimvars shared = primvarCache ? primvarCache->get(delegate, instancerId, arrays, count, warnings)
                                                  : readInstancerPrimvars(delegate, instancerId, count, warnings);
    std::vector<InstanceRecord> out;
    out.reserve(indices.size());
    size_t outOfRange = 0, unusable = 0;
    for (int i : indices) {
        if (i < 0 || size_t(i) >= count) {
            ++outOfRange;
            continue;
        }
        InstanceRecord rec;
        rec.instanceIndex = i;
        rec.primvars = shared;
        glm::mat4 local = x ? glm::mat4((*x)[size_t(i)]) * prototypeTransform : prototypeTransform;
        rec.objectToWorld = instanceTransform(instancer, t ? (*t)[size_t(i)] : glm::vec3(0.0f),
                                              r ? (*r)[size_t(i)] : glm::vec4(1, 0, 0, 0),
                                              s ? (*s)[size_t(i)] : glm::vec3(1.0f), local);
        const glm::mat4& m = rec.objectToWorld;
        // A zero scale, a singular instance matrix or NaN cannot place the prototype: Embree
        // would get invalid rays or degenerate bounds (delegate/transformCheck.h).
        if (unusableTransform(m)) {
            ++unusable;
            continue;
        }
        rec.normalToWorld = glm::transpose(glm::inverse(glm::mat3(m)));
        out.push_back(rec);
    }
    if (unusable > 0)
        warnings->push_back(std::to_string(unusable) + " instance(s) of " + prototypeId.str() +
                            " have a transform that is singular (a zero scale), projective or not finite; not drawn");
    if (outOfRange > 0 && count > 0)
        warnings->push_back(std::to_string(outOfRange) + " instance(s) of " + prototypeId.str() +
                            " have no position (protoIndices is longer than positions); not drawn");
    return out;
}

void InstanceSet::rebuild(RTCDevice device, RTCScene top, RTCScene blas, void* userData,
                          std::vector<InstanceRecord> records) {
    release();
    _top = top;
    _records = std::move(records);
    if (!blas) {
        _records.clear();
        return;
    }
    _geoms.resize(_records.size());
    _geomIds.resize(_records.size());
    // Creating the instance geometries is most of the cost for large instancers; it runs in
    // parallel (rtcAttachGeometry is thread-safe, Embree 3.13 docs).
    tbb::parallel_for(tbb::blocked_range<size_t>(0, _records.size(), 1024),
                      [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i != range.end(); ++i) {
            RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
            rtcSetGeometryInstancedScene(g, blas);
            rtcSetGeometryTimeStepCount(g, 1);
            rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR,
                                    &_records[i].objectToWorld[0][0]);
            rtcSetGeometryUserData(g, userData);
            rtcCommitGeometry(g);
            _geomIds[i] = rtcAttachGeometry(top, g);
            _geoms[i] = g;
        }
    });
}

void InstanceSet::release() {
    for (size_t i = 0; i < _geoms.size(); ++i) {
        rtcDetachGeometry(_top, _geomIds[i]);
        rtcReleaseGeometry(_geoms[i]);
    }
    _geoms.clear();
    _geomIds.clear();
    _records.clear();
}

}  // namespace principled::embree
