// SPDX-License-Identifier: Apache-2.0
// Evaluating `.timeSamples` at a time code: linear interpolation for floating types (component-
// wise for vectors, matrices and arrays of equal length; slerp for quaternions), held values for
// everything else (bool, integers, token, string, asset) and outside the first/last sample.
#pragma once

#include <map>

#include "scene_adapter/usda/value.h"

namespace principled::usd {

/// The value of `samples` at `time` (samples must be non-empty). A None sample blocks the value
/// until the next sample (it is held, never interpolated).
Value evaluateTimeSamples(const std::map<double, Value>& samples, double time);

/// Linear blend a + (b - a) * u for interpolable values of the same shape; returns `a` (held)
/// for anything else.
Value interpolateValues(const Value& a, const Value& b, double u);

}  // namespace principled::usd
