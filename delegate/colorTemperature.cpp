// SPDX-License-Identifier: Apache-2.0
#include "delegate/colorTemperature.h"

#include <algorithm>
#include <cmath>

namespace principled::embree {

glm::vec3 blackbodyColor(float kelvin) {
    double T = std::clamp(std::isfinite(kelvin) ? double(kelvin) : 6500.0, 1000.0, 25000.0);
    double t = 1e3 / T, t2 = t * t, t3 = t2 * t;
    // Kang et al. 2002, eq. 1: x_c(T).
    double x = T <= 4000.0 ? -0.2661239 * t3 - 0.2343589 * t2 + 0.8776956 * t + 0.179910
                           : -3.0258469 * t3 + 2.1070379 * t2 + 0.2226347 * t + 0.240390;
    double x2 = x * x, x3 = x2 * x;
    // Kang et al. 2002, eq. 2: y_c(x).
    double y = T <= 2222.0   ? -1.1063814 * x3 - 1.34811020 * x2 + 2.18555832 * x - 0.20219683
               : T <= 4000.0 ? -0.9549476 * x3 - 1.37418593 * x2 + 2.09137015 * x - 0.16748867
                             : 3.0817580 * x3 - 5.87338670 * x2 + 3.75112997 * x - 0.37001483;
    // xyY (Y = 1) -> XYZ -> linear Rec.709 (IEC 61966-2-1 matrix).
    double X = x / y, Y = 1.0, Z = (1.0 - x - y) / y;
    glm::vec3 rgb(float(3.2404542 * X - 1.5371385 * Y - 0.4985314 * Z),
                  float(-0.9692660 * X + 1.8760108 * Y + 0.0415560 * Z),
                  float(0.0556434 * X - 0.2040259 * Y + 1.0572252 * Z));
    return glm::max(rgb, glm::vec3(0.0f));
}

}  // namespace principled::embree
