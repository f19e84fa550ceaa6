// SPDX-License-Identifier: Apache-2.0
// The AOVs this delegate renders: names, formats, whether samples are averaged, clear values.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "delegate/hd/aov.h"

namespace principled::embree {

enum class AovKind {
    Color, Alpha, Depth, CameraDepth, Position, Normal, Neye, Albedo,
    Diffuse, Sheen, Specular, Clearcoat, Transmission, Emission,
    PrimId, InstanceId, ElementId, MaterialId, SampleCount, Variance,
    Primvar  ///< "primvars:NAME": the primvar interpolated at the first hit (up to 3 components)
};

struct AovInfo {
    AovKind kind;
    const char* name;
    hd::Format format;
    bool multiSampled;  ///< false: the first sample's value (IDs, depth, geometry) is kept
    float clear;        ///< value of pixels no ray hit (IDs: -1)
    const char* help;
};

/// Every AOV, in the order `--aov all` writes them.
const std::vector<AovInfo>& allAovs();
/// Looks an AOV up by name ("color", "primId", "primvars:st"...).
std::optional<AovInfo> findAov(const std::string& name);

}  // namespace principled::embree
