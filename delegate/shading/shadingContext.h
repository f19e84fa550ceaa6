// SPDX-License-Identifier: Apache-2.0
// ShadingContext: what a MaterialProgram may ask about the shading point (primvars and their
// screen-space footprint). Implemented by the integrator for each hit.
#pragma once

#include <glm/glm.hpp>

#include "delegate/hd/token.h"

namespace principled::shading {

/// The shading point as seen by a material. Called from render threads; implementations must
/// be cheap and must not allocate.
class ShadingContext {
  public:
    virtual ~ShadingContext() = default;

    /// The primvar `name` interpolated at the shading point, `components` floats (1-4) written
    /// to out. Returns false if the prim has no primvar of that name (the reader's fallback is
    /// used then).
    virtual bool primvar(const hd::Token& name, int components, float* out) const = 0;

    /// Screen-space derivatives of a 2-component primvar (d/dx and d/dy of one pixel step),
    /// the footprint used for mip-map filtering. False (the default) means point sampling.
    virtual bool primvarDerivatives(const hd::Token& name, glm::vec2* ddx, glm::vec2* ddy) const {
        (void)name;
        (void)ddx;
        (void)ddy;
        return false;
    }
};

}  // namespace principled::shading
