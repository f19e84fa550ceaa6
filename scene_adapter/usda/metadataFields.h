// SPDX-License-Identifier: Apache-2.0
// The metadata fields OpenUSD registers (SdfFieldKeys in sdf/schema.h, and the fields Usd and
// its schema libraries add in their plugInfo). The parser checks the values of these; any
// other field is "unregistered" and, as in Sdf (SdfUnregisteredValue), any value the grammar
// allows is kept.
#pragma once

#include <string_view>

namespace principled::usd {

/// `key` is a registered metadata field (layer, prim or property).
bool isRegisteredMetadataField(std::string_view key);

}  // namespace principled::usd
