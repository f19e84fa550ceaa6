// SPDX-License-Identifier: Apache-2.0
#include "delegate/embreeInstance.h"

namespace principled::embree {

void EmbreeInstance::setGeometry(RTCDevice device, RTCScene top, RTCGeometry geom,
                                 void* userData) {
    // Build quality per use: the first build of a prim is for the frames it will be in (MEDIUM:
    // the binned SAH builder; HIGH's spatial splits cost 2-3x the build time for a few % of
    // traversal speed on this renderer's scenes, docs/performance.md section 1); a rebuild is an
    // edit a viewport is waiting for, so it takes the fastest builder (LOW).
    const RTCBuildQuality quality = _blas ? RTC_BUILD_QUALITY_LOW : RTC_BUILD_QUALITY_MEDIUM;
    if (_blas) {
        // Replace the BLAS content: detach the old geometry, attach the new one.
        rtcReleaseScene(_blas);
    }
    _blas = rtcNewScene(device);
    rtcSetSceneFlags(_blas, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(_blas, quality);
    rtcSetGeometryBuildQuality(geom, quality);
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(_blas, geom, 0);
    rtcReleaseGeometry(geom);
    rtcCommitScene(_blas);
    if (!_instance) {
        _top = top;
        _instance = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryTimeStepCount(_instance, 1);
        glm::mat4 identity(1.0f);
        rtcSetGeometryTransform(_instance, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &identity[0][0]);
        _instId = rtcAttachGeometry(top, _instance);  // thread-safe (Embree 3.13 docs)
    }
    rtcSetGeometryInstancedScene(_instance, _blas);
    rtcSetGeometryUserData(_instance, userData);
    rtcCommitGeometry(_instance);
}

void EmbreeInstance::setTransform(const glm::mat4& objectToWorld) {
    if (!_instance) return;
    rtcSetGeometryTransform(_instance, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &objectToWorld[0][0]);
    rtcCommitGeometry(_instance);
}

void EmbreeInstance::setEnabled(bool enabled) {
    if (!_instance) return;
    if (enabled)
        rtcEnableGeometry(_instance);
    else
        rtcDisableGeometry(_instance);
    rtcCommitGeometry(_instance);
}

void EmbreeInstance::release() {
    if (_instance) {
        rtcDetachGeometry(_top, _instId);
        rtcReleaseGeometry(_instance);
        _instance = nullptr;
        _instId = RTC_INVALID_GEOMETRY_ID;
    }
    if (_blas) {
        rtcReleaseScene(_blas);
        _blas = nullptr;
    }
}

}  // namespace principled::embree
