// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/metadataFields.h"

#include <algorithm>
#include <array>

namespace principled::usd {

namespace {
// Sorted, for binary search.
constexpr std::array<std::string_view, 67> kRegistered = {
    "active",
    "allowedTokens",
    "apiSchemas",
    "assetInfo",
    "bindMaterialAs",
    "clipSets",
    "clips",
    "colorConfiguration",
    "colorManagementSystem",
    "colorSpace",
    "comment",
    "connectability",
    "custom",
    "customData",
    "customLayerData",
    "default",
    "defaultPrim",
    "displayGroup",
    "displayGroupOrder",
    "displayName",
    "displayUnit",
    "doc",
    "documentation",
    "elementSize",
    "endFrame",
    "endTimeCode",
    "expressionVariables",
    "fallbackPrimTypes",
    "framePrecision",
    "framesPerSecond",
    "hasOwnedSubLayers",
    "hidden",
    "inheritPaths",
    "instanceable",
    "interpolation",
    "kind",
    "layerRelocates",
    "metersPerUnit",
    "noLoadHint",
    "outputName",
    "owner",
    "payload",
    "permission",
    "prefix",
    "prefixSubstitutions",
    "primOrder",
    "propertyOrder",
    "references",
    "relocates",
    "renderType",
    "sdrMetadata",
    "sessionOwner",
    "specializes",
    "specifier",
    "startFrame",
    "startTimeCode",
    "subLayerOffsets",
    "subLayers",
    "suffix",
    "suffixSubstitutions",
    "symmetricPeer",
    "symmetryArguments",
    "symmetryFunction",
    "timeCodesPerSecond",
    "typeName",
    "upAxis",
    "variantSetNames",
};
}  // namespace

bool isRegisteredMetadataField(std::string_view key) {
    return std::binary_search(kRegistered.begin(), kRegistered.end(), key);
}

}  // namespace principled::usd
