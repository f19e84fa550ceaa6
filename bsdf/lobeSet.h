// SPDX-License-Identifier: Apache-2.0
// The concrete lobes of one material, as built by disney.h or ue4.h and combined by Bsdf.
#pragma once

#include "bsdf/types.h"
#include "bsdf/clearcoat.h"
#include "bsdf/disneyDiffuse.h"
#include "bsdf/lambert.h"
#include "bsdf/sheen.h"
#include "bsdf/specular.h"
#include "bsdf/transmission.h"

namespace principled::bsdf {

struct LobeSet {
    bool lambertDiffuse = false;  ///< UE4: Lambert in the Diffuse slot instead of Burley
    DisneyDiffuse diffuse;
    Lambert lambert;
    Sheen sheen;
    Specular specular;
    Clearcoat clearcoat;
    Dielectric transmission;        ///< seen from outside (eta = ior)
    Dielectric transmissionInside;  ///< seen from inside a solid (eta = 1 / ior)
    bool thin = false;
    LobeMask mask = 0;       ///< lobes kept after pruning
    LobeMask deltaMask = 0;  ///< lobes that are perfect specular
};

/// Keeps the lobes whose weight passes the pruning cutoff (and Options::lobeMask).
inline bool keepLobe(const Options& o, Lobe l, float scale) {
    if (!(o.lobeMask & lobeBit(l))) return false;
    float cutoff = o.pruneLobes ? o.pruneCutoff : 0.0f;
    return scale > cutoff;
}

}  // namespace principled::bsdf
