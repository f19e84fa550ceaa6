// SPDX-License-Identifier: Apache-2.0
// IesProfile: a luminaire's measured intensity distribution from an IES file (ANSI/IES LM-63,
// the 1986, 1991, 1995 and 2002 layouts), for UsdLux ShapingAPI's shaping:ies:file. Only type C
// photometry (vertical angle 0 = nadir, horizontal angles about the vertical axis) is read: it is
// what architectural and product luminaire files use; types A and B are refused with an error.
// The table's symmetries follow the standard: one horizontal angle (the same in every plane),
// 0-90 (quadrant symmetry), 0-180 or 90-270 (mirror symmetry) and 0-360 (none).
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace principled::embree {

struct IesProfile {
    std::vector<float> vertical;    ///< degrees, increasing, within [0, 180]
    std::vector<float> horizontal;  ///< degrees, increasing
    std::vector<float> candela;     ///< horizontal-major: candela[h * vertical.size() + v]
    float maxCandela = 0.0f;        ///< the largest table value
    float meanCandela = 0.0f;       ///< intensity averaged over the whole sphere (power / 4 pi)

    /// Intensity (candela, bilinear in the table) at vertical angle theta from the nadir and
    /// horizontal angle phi, both in degrees (phi any value: it is wrapped and folded by the
    /// table's symmetry); 0 outside the table's vertical range.
    float evaluate(float thetaDeg, float phiDeg) const;
};

/// Parses LM-63 text; `where` names it in errors ("where:line: what was expected"). Returns null
/// and sets *error on malformed or unsupported input.
std::shared_ptr<const IesProfile> parseIes(const std::string& text, const std::string& where, std::string* error);

/// Reads and parses an IES file.
std::shared_ptr<const IesProfile> loadIes(const std::string& path, std::string* error);

}  // namespace principled::embree
