// SPDX-License-Identifier: Apache-2.0
#include "delegate/aovs.h"

namespace principled::embree {

const std::vector<AovInfo>& allAovs() {
    using F = hd::Format;
    static const std::vector<AovInfo> aovs{
        {AovKind::Color, "color", F::Float32Vec4, true, 0.0f, "radiance (RGB) and coverage (A)"},
        {AovKind::Alpha, "alpha", F::Float32, true, 0.0f, "coverage: fraction of samples that hit geometry"},
        {AovKind::Depth, "depth", F::Float32, false, 1.0f, "clip-space depth in [0,1] (1 = far plane or nothing)"},
        {AovKind::CameraDepth, "cameraDepth", F::Float32, false, 0.0f, "distance from the camera along the ray"},
        {AovKind::Position, "position", F::Float32Vec3, false, 0.0f, "world-space position of the first hit"},
        {AovKind::Normal, "normal", F::Float32Vec3, false, 0.0f, "world-space shading normal of the first hit"},
        {AovKind::Neye, "Neye", F::Float32Vec3, false, 0.0f, "camera-space shading normal of the first hit"},
        {AovKind::Albedo, "albedo", F::Float32Vec3, true, 0.0f, "base colour at the first hit"},
        {AovKind::Diffuse, "diffuse", F::Float32Vec3, true, 0.0f, "light leaving the first hit through the diffuse lobe"},
        {AovKind::Sheen, "sheen", F::Float32Vec3, true, 0.0f, "... through the sheen lobe"},
        {AovKind::Specular, "specular", F::Float32Vec3, true, 0.0f, "... through the specular lobe"},
        {AovKind::Clearcoat, "clearcoat", F::Float32Vec3, true, 0.0f, "... through the clearcoat lobe"},
        {AovKind::Transmission, "transmission", F::Float32Vec3, true, 0.0f, "... through the transmission lobe"},
        {AovKind::Emission, "emission", F::Float32Vec3, true, 0.0f, "emitters and lights seen directly (incl. a visible dome)"},
        {AovKind::PrimId, "primId", F::Int32, false, -1.0f, "render index id of the first-hit prim"},
        {AovKind::InstanceId, "instanceId", F::Int32, false, -1.0f, "instance of the first hit (0 if not instanced)"},
        {AovKind::ElementId, "elementId", F::Int32, false, -1.0f, "authored face of the first hit"},
        {AovKind::MaterialId, "materialId", F::Int32, false, -1.0f, "material of the first hit (-1: none bound)"},
        {AovKind::SampleCount, "sampleCount", F::Float32, false, 0.0f, "samples taken at the pixel"},
        {AovKind::Variance, "variance", F::Float32, false, 0.0f, "variance of the pixel's mean luminance"},
    };
    return aovs;
}

std::optional<AovInfo> findAov(const std::string& name) {
    for (const auto& a : allAovs())
        if (name == a.name) return a;
    if (name.rfind("primvars:", 0) == 0 && name.size() > 9)
        return AovInfo{AovKind::Primvar, "primvars:", hd::Format::Float32Vec3, false, 0.0f,
                       "a primvar at the first hit, padded to 3 components"};
    return std::nullopt;
}

}  // namespace principled::embree
