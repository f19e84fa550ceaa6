// SPDX-License-Identifier: Apache-2.0
#include "delegate/iesProfile.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace principled::embree {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Token {
    std::string text;
    int line;
};

// The numbers after the TILT line, each with its line number (LM-63 lets them wrap freely and
// separates them by blanks or commas).
std::vector<Token> numbersFrom(const std::vector<std::string>& lines, size_t first) {
    std::vector<Token> out;
    for (size_t i = first; i < lines.size(); ++i) {
        std::string s = lines[i];
        std::replace(s.begin(), s.end(), ',', ' ');
        std::istringstream in(s);
        std::string t;
        while (in >> t) out.push_back({t, int(i) + 1});
    }
    return out;
}

// Where in the table phi falls, folded by the symmetry the horizontal angles imply.
float foldAzimuth(const std::vector<float>& h, float phi) {
    phi = std::fmod(phi, 360.0f);
    if (phi < 0.0f) phi += 360.0f;
    const float first = h.front(), last = h.back();
    if (h.size() == 1) return first;
    if (first == 0.0f && last <= 90.0f) {  // quadrant symmetry
        if (phi > 180.0f) phi = 360.0f - phi;
        if (phi > 90.0f) phi = 180.0f - phi;
    } else if (first == 0.0f && last <= 180.0f) {  // mirror about the 0-180 plane
        if (phi > 180.0f) phi = 360.0f - phi;
    } else if (first == 90.0f && last <= 270.0f) {  // mirror about the 90-270 plane
        if (phi < 90.0f) phi = 180.0f - phi;
        else if (phi > 270.0f) phi = 540.0f - phi;
    }
    return std::clamp(phi, first, last);
}

// Index i and weight t with x between a[i] and a[i + 1] (a increasing, x within its range).
void bracket(const std::vector<float>& a, float x, size_t* i, float* t) {
    if (a.size() == 1) {
        *i = 0;
        *t = 0.0f;
        return;
    }
    size_t k = size_t(std::upper_bound(a.begin(), a.end(), x) - a.begin());
    k = std::clamp<size_t>(k, 1, a.size() - 1);
    *i = k - 1;
    const float span = a[k] - a[k - 1];
    *t = span > 0.0f ? std::clamp((x - a[k - 1]) / span, 0.0f, 1.0f) : 0.0f;
}

}  // namespace

float IesProfile::evaluate(float thetaDeg, float phiDeg) const {
    if (vertical.empty() || horizontal.empty() || !std::isfinite(thetaDeg) || !std::isfinite(phiDeg)) return 0.0f;
    if (thetaDeg < vertical.front() || thetaDeg > vertical.back()) return 0.0f;
    size_t v, h;
    float tv, th;
    bracket(vertical, thetaDeg, &v, &tv);
    bracket(horizontal, foldAzimuth(horizontal, phiDeg), &h, &th);
    const size_t nv = vertical.size();
    const size_t v1 = std::min(v + 1, nv - 1), h1 = std::min(h + 1, horizontal.size() - 1);
    auto at = [&](size_t hi, size_t vi) { return candela[hi * nv + vi]; };
    const float a = at(h, v) + (at(h, v1) - at(h, v)) * tv;
    const float b = at(h1, v) + (at(h1, v1) - at(h1, v)) * tv;
    return a + (b - a) * th;
}

std::shared_ptr<const IesProfile> parseIes(const std::string& text, const std::string& where, std::string* error) {
    std::vector<std::string> lines;
    {
        std::istringstream in(text);
        std::string line;
        while (std::getline(in, line)) {
            if (!line.empty() && line.back() == '\r') line.pop_back();
            lines.push_back(line);
        }
    }
    auto fail = [&](int line, const std::string& what) {
        *error = where + ":" + std::to_string(line) + ": " + what;
        return nullptr;
    };
    size_t tilt = lines.size();
    for (size_t i = 0; i < lines.size(); ++i) {
        const size_t s = lines[i].find_first_not_of(" \t");
        if (s != std::string::npos && lines[i].compare(s, 5, "TILT=") == 0) {
            tilt = i;
            break;
        }
    }
    if (tilt == lines.size()) return fail(int(lines.size()), "expected a TILT= line (not an IES LM-63 file?)");
    std::vector<Token> tok = numbersFrom(lines, tilt + 1);
    size_t next = 0;
    auto number = [&](const char* what, double* out) {
        if (next >= tok.size()) {
            *error = where + ":" + std::to_string(lines.size()) + ": file ends where " + what + " was expected";
            return false;
        }
        const Token& t = tok[next++];
        char* end = nullptr;
        *out = std::strtod(t.text.c_str(), &end);
        if (end == t.text.c_str() || *end != '\0' || !std::isfinite(*out)) {
            *error = where + ":" + std::to_string(t.line) + ": expected " + what + ", found '" + t.text + "'";
            return false;
        }
        return true;
    };
    const std::string tiltValue = lines[tilt].substr(lines[tilt].find("TILT=") + 5);
    if (tiltValue.rfind("INCLUDE", 0) == 0) {
        // Lamp-to-luminaire geometry, then n tilt angles and n multipliers: a lamp's output
        // against its tilt, which a fixed light does not use.
        double geometry, n;
        if (!number("the tilt geometry", &geometry) || !number("the number of tilt angles", &n)) return nullptr;
        if (n < 0 || n > 10000) return fail(tok[next - 1].line, "expected a tilt angle count in [0, 10000]");
        for (int i = 0; i < 2 * int(n); ++i) {
            double skip;
            if (!number("a tilt angle or multiplier", &skip)) return nullptr;
        }
    }
    double lamps, lumens, multiplier, nv, nh, type, units, width, length, height, ballast, future, watts;
    if (!number("the number of lamps", &lamps) || !number("lumens per lamp", &lumens) ||
        !number("the candela multiplier", &multiplier) || !number("the number of vertical angles", &nv) ||
        !number("the number of horizontal angles", &nh) || !number("the photometric type", &type) ||
        !number("the units type", &units) || !number("the width", &width) || !number("the length", &length) ||
        !number("the height", &height) || !number("the ballast factor", &ballast) ||
        !number("the ballast-lamp factor", &future) || !number("the input watts", &watts))
        return nullptr;
    const int countLine = tok[std::min(next, tok.size()) - 1].line;
    if (type != 1.0)
        return fail(countLine, "photometric type " + std::string(type == 2.0 ? "B" : type == 3.0 ? "A" : "unknown") +
                                   " is not supported: only type C profiles are read");
    if (nv < 1 || nv > 10000 || nh < 1 || nh > 10000 || nv != std::floor(nv) || nh != std::floor(nh))
        return fail(countLine, "expected angle counts between 1 and 10000");
    // The file must hold the angles and the table before anything is sized by its counts.
    if (tok.size() - next < size_t(nv) + size_t(nh) + size_t(nv) * size_t(nh))
        return fail(countLine, "the file holds " + std::to_string(tok.size() - next) + " numbers after the counts, " +
                                   "fewer than the " + std::to_string(size_t(nv) + size_t(nh) + size_t(nv) * size_t(nh)) +
                                   " its angle counts need");
    auto profile = std::make_shared<IesProfile>();
    profile->vertical.resize(size_t(nv));
    profile->horizontal.resize(size_t(nh));
    for (auto* angles : {&profile->vertical, &profile->horizontal}) {
        const bool vertical = angles == &profile->vertical;
        for (float& a : *angles) {
            double x;
            if (!number(vertical ? "a vertical angle" : "a horizontal angle", &x)) return nullptr;
            if (&a != &angles->front() && x < *(&a - 1))
                return fail(tok[next - 1].line, std::string(vertical ? "vertical" : "horizontal") +
                                                    " angles must not decrease");
            a = float(x);
        }
    }
    if (profile->vertical.front() < 0.0f || profile->vertical.back() > 180.0f)
        return fail(countLine, "expected vertical angles within [0, 180] degrees");
    if (profile->horizontal.front() < 0.0f || profile->horizontal.back() > 360.0f)
        return fail(countLine, "expected horizontal angles within [0, 360] degrees");
    profile->candela.resize(size_t(nv) * size_t(nh));
    for (float& c : profile->candela) {
        double x;
        if (!number("a candela value", &x)) return nullptr;
        c = float(std::max(0.0, x * multiplier));
    }
    profile->maxCandela = *std::max_element(profile->candela.begin(), profile->candela.end());
    if (!(profile->maxCandela > 0.0f) || !std::isfinite(profile->maxCandela))
        return fail(countLine, "the profile emits nothing (every candela value is 0)");
    // Mean intensity over the sphere, by the midpoint rule (0.5-degree rings, 2.5-degree sectors).
    const int rings = 360, sectors = nh > 1 ? 144 : 1;
    double sum = 0.0;
    for (int i = 0; i < rings; ++i) {
        const double theta = (i + 0.5) * 180.0 / rings;
        double ring = 0.0;
        for (int j = 0; j < sectors; ++j)
            ring += profile->evaluate(float(theta), float((j + 0.5) * 360.0 / sectors));
        sum += ring / sectors * std::sin(theta * kPi / 180.0) * (kPi / rings);
    }
    profile->meanCandela = float(sum / 2.0);  // (1 / 4 pi) * 2 pi * integral of I sin(theta)
    if (!(profile->meanCandela > 0.0f) || !std::isfinite(profile->meanCandela))
        return fail(countLine, "the profile emits nothing over the sphere (its vertical angles cover less than "
                               "half a degree)");
    return profile;
}

std::shared_ptr<const IesProfile> loadIes(const std::string& path, std::string* error) {
    // Real profiles are kilobytes; a device (/dev/zero) or a huge file would never end.
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        *error = path + ": cannot open the IES file (not a regular file)";
        return nullptr;
    }
    const auto size = std::filesystem::file_size(path, ec);
    if (ec || size > (uintmax_t(64) << 20)) {
        *error = path + ": the IES file is larger than 64 MB";
        return nullptr;
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        *error = path + ": cannot open the IES file";
        return nullptr;
    }
    std::ostringstream text;
    text << in.rdbuf();
    return parseIes(text.str(), path, error);
}

}  // namespace principled::embree
