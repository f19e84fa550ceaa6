// SPDX-License-Identifier: Apache-2.0
#include "delegate/embreeInstance.h"

namespace principled::embree {

void EmbreeInstance::setGeometry(RTCDevice device, RTCScene top, RTCGeometry geom,
                                 void* userData) {
    if (_blas) {
        // Replace the BLAS content: detach the old geometry, attach the new one.
        rtcReleaseScene(_blas);
    }
    _blas = rtcNewScene(device);
    rtcSetSceneFlags(_blas, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(_blas, RTC_BUILD_QUALITY_HIGH);
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
