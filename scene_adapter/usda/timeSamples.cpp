// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/timeSamples.h"

#include <cmath>

#include "scene_adapter/usda/valueType.h"

namespace principled::usd {

namespace {

// Shoemake 1985, "Animating Rotation with Quaternion Curves", SIGGRAPH: slerp along the shorter
// arc. Components are (real, i, j, k) as USDA writes them.
void slerp(const double* a, const double* b, double u, double* out) {
    double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    double sign = dot < 0.0 ? -1.0 : 1.0;
    dot *= sign;
    double wa = 1.0 - u, wb = u;
    if (dot < 0.9995) {  // 0.9995: below this the sin() denominator is well conditioned
        double theta = std::acos(dot);
        double s = std::sin(theta);
        wa = std::sin((1.0 - u) * theta) / s;
        wb = std::sin(u * theta) / s;
    }
    double len = 0.0;
    for (int i = 0; i < 4; ++i) {
        out[i] = wa * a[i] + wb * sign * b[i];
        len += out[i] * out[i];
    }
    len = std::sqrt(len);
    if (len > 0.0)
        for (int i = 0; i < 4; ++i) out[i] /= len;
}

void blend(const std::vector<double>& a, const std::vector<double>& b, double u, bool quat,
           std::vector<double>& out) {
    out.resize(a.size());
    if (quat) {
        for (std::size_t i = 0; i + 3 < a.size(); i += 4) slerp(&a[i], &b[i], u, &out[i]);
        return;
    }
    for (std::size_t i = 0; i < a.size(); ++i) out[i] = a[i] + (b[i] - a[i]) * u;
}

}  // namespace

Value interpolateValues(const Value& a, const Value& b, double u) {
    const ValueType* type = findValueType(a.typeName());
    if (!type || !type->interpolates() || a.kind() != b.kind() || a.typeName() != b.typeName() ||
        a.size() != b.size())
        return a;
    switch (a.kind()) {
        case Value::Kind::Number: {
            double x = *a.getDouble(), y = *b.getDouble();
            return Value::number(a.typeName(), x + (y - x) * u, a.location());
        }
        case Value::Kind::Tuple: {
            std::vector<double> out;
            blend(*a.getTuple(), *b.getTuple(), u, type->quaternion, out);
            return Value::tuple(a.typeName(), std::move(out), a.location());
        }
        case Value::Kind::NumberArray: {
            std::vector<double> out;
            blend(*a.numbers(), *b.numbers(), u, type->quaternion, out);
            return Value::numberArray(a.typeName(), a.components(), std::move(out), a.location());
        }
        default:
            return a;
    }
}

Value evaluateTimeSamples(const std::map<double, Value>& samples, double time) {
    if (samples.empty()) return {};
    auto upper = samples.upper_bound(time);              // first sample strictly after `time`
    if (upper == samples.begin()) return upper->second;  // before the first: held
    auto lower = std::prev(upper);
    if (upper == samples.end() || lower->first == time) return lower->second;
    const Value& a = lower->second;
    const Value& b = upper->second;
    if (a.isNone() || b.isNone()) return a;
    double u = (time - lower->first) / (upper->first - lower->first);
    return interpolateValues(a, b, u);
}

}  // namespace principled::usd
