// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/implicitShapes.h"

#include <cmath>

namespace principled::adapter {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Shapes are generated about +Z as (u, v, w) and mapped to the authored axis by a cyclic
// permutation (a rotation, so windings and outward normals are kept).
glm::vec3 toAxis(char axis, double u, double v, double w) {
    if (axis == 'X') return glm::vec3(float(w), float(u), float(v));
    if (axis == 'Y') return glm::vec3(float(v), float(w), float(u));
    return glm::vec3(float(u), float(v), float(w));
}

struct Builder {
    char axis;
    ShapeMesh* m;
    std::vector<glm::vec3> vertexNormal;  // smooth normal per point (curved parts)

    int point(double u, double v, double w, glm::dvec3 n = glm::dvec3(0.0)) {
        m->points.push_back(toAxis(axis, u, v, w));
        vertexNormal.push_back(toAxis(axis, n.x, n.y, n.z));
        return int(m->points.size()) - 1;
    }
    // A face whose corners use the points' smooth normals.
    void smoothFace(std::initializer_list<int> idx) {
        m->faceVertexCounts.push_back(int(idx.size()));
        for (int i : idx) {
            m->faceVertexIndices.push_back(i);
            m->normals.push_back(vertexNormal[size_t(i)]);
        }
    }
    // A flat face (a cap) with one normal for all corners.
    void flatFace(const std::vector<int>& idx, glm::dvec3 n) {
        m->faceVertexCounts.push_back(int(idx.size()));
        for (int i : idx) {
            m->faceVertexIndices.push_back(i);
            m->normals.push_back(toAxis(axis, n.x, n.y, n.z));
        }
    }
};

double angle(int i) { return 2.0 * kPi * double(i % kShapeSegments) / kShapeSegments; }

void buildCube(double s, ShapeMesh* m) {
    double h = 0.5 * s;
    Builder b{'Z', m, {}};
    for (int i = 0; i < 8; ++i) b.point(i & 1 ? h : -h, (i & 2) ? h : -h, (i & 4) ? h : -h);
    // Corners 0..7 as bit patterns (x: bit 0, y: bit 1, z: bit 2); counter-clockwise seen from
    // outside.
    b.flatFace({0, 2, 3, 1}, {0, 0, -1});
    b.flatFace({4, 5, 7, 6}, {0, 0, 1});
    b.flatFace({0, 1, 5, 4}, {0, -1, 0});
    b.flatFace({2, 6, 7, 3}, {0, 1, 0});
    b.flatFace({0, 4, 6, 2}, {-1, 0, 0});
    b.flatFace({1, 3, 7, 5}, {1, 0, 0});
}

void buildCylinder(double r, double h, char axis, ShapeMesh* m) {
    Builder b{axis, m, {}};
    const int n = kShapeSegments;
    for (int k = 0; k < 2; ++k)
        for (int i = 0; i < n; ++i) {
            double c = std::cos(angle(i)), s = std::sin(angle(i));
            b.point(r * c, r * s, k ? 0.5 * h : -0.5 * h, {c, s, 0.0});
        }
    for (int i = 0; i < n; ++i) b.smoothFace({i, (i + 1) % n, n + (i + 1) % n, n + i});
    std::vector<int> bottom, top;
    for (int i = 0; i < n; ++i) bottom.push_back((n - i) % n), top.push_back(n + i);
    b.flatFace(bottom, {0, 0, -1});
    b.flatFace(top, {0, 0, 1});
}

void buildCone(double r, double h, char axis, ShapeMesh* m) {
    Builder b{axis, m, {}};
    const int n = kShapeSegments;
    // The side normal at angle phi is (h cos phi, h sin phi, r), normalised.
    auto sideNormal = [&](double phi) {
        glm::dvec3 v(h * std::cos(phi), h * std::sin(phi), r);
        double l = glm::length(v);
        return l > 0.0 ? v / l : glm::dvec3(0, 0, 1);
    };
    for (int i = 0; i < n; ++i)
        b.point(r * std::cos(angle(i)), r * std::sin(angle(i)), -0.5 * h, sideNormal(angle(i)));
    int apex = b.point(0.0, 0.0, 0.5 * h);
    for (int i = 0; i < n; ++i) {
        // The apex corner takes the normal halfway between its two base corners.
        glm::dvec3 mid = sideNormal(2.0 * kPi * (i + 0.5) / n);
        m->faceVertexCounts.push_back(3);
        for (int idx : {i, (i + 1) % n}) {
            m->faceVertexIndices.push_back(idx);
            m->normals.push_back(b.vertexNormal[size_t(idx)]);
        }
        m->faceVertexIndices.push_back(apex);
        m->normals.push_back(toAxis(axis, mid.x, mid.y, mid.z));
    }
    std::vector<int> base;
    for (int i = 0; i < n; ++i) base.push_back((n - i) % n);
    b.flatFace(base, {0, 0, -1});
}

void buildCapsule(double r, double h, char axis, ShapeMesh* m) {
    Builder b{axis, m, {}};
    const int n = kShapeSegments, rings = kCapsuleRings;
    int bottomPole = b.point(0, 0, -0.5 * h - r, {0, 0, -1});
    // 2 * rings latitude rings from the bottom: the lower hemisphere up to its equator, then
    // the upper one from its equator (the straight part joins the two equators).
    for (int k = 0; k < 2 * rings; ++k) {
        bool upper = k >= rings;
        double theta = upper ? 0.5 * kPi * (k - rings) / rings : -0.5 * kPi + 0.5 * kPi * (k + 1) / rings;
        double zc = upper ? 0.5 * h : -0.5 * h;
        double ct = std::cos(theta), st = std::sin(theta);
        for (int i = 0; i < n; ++i) {
            double c = std::cos(angle(i)), s = std::sin(angle(i));
            b.point(r * ct * c, r * ct * s, zc + r * st, {ct * c, ct * s, st});
        }
    }
    int topPole = b.point(0, 0, 0.5 * h + r, {0, 0, 1});
    auto ring = [&](int k, int i) { return 1 + k * n + (i % n); };
    for (int i = 0; i < n; ++i) b.smoothFace({bottomPole, ring(0, i + 1), ring(0, i)});
    for (int k = 0; k + 1 < 2 * rings; ++k)
        for (int i = 0; i < n; ++i)
            b.smoothFace({ring(k, i), ring(k, i + 1), ring(k + 1, i + 1), ring(k + 1, i)});
    for (int i = 0; i < n; ++i) b.smoothFace({ring(2 * rings - 1, i), ring(2 * rings - 1, i + 1), topPole});
}

bool validLength(double v) { return std::isfinite(v) && v >= 0.0; }

}  // namespace

ShapeParams shapeFallbacks(const std::string& type) {
    ShapeParams p;
    if (type == "Capsule") p.radius = 0.5, p.height = 1.0;  // UsdGeomCapsule's schema
    return p;
}

bool isImplicitShape(const std::string& t) {
    return t == "Cube" || t == "Cylinder" || t == "Cone" || t == "Capsule" || t == "Plane";
}

bool buildImplicitShape(const std::string& type, const ShapeParams& p, ShapeMesh* out,
                        std::string* error) {
    *out = ShapeMesh();
    char axis = (p.axis == 'X' || p.axis == 'Y') ? p.axis : 'Z';
    if (type == "Cube") {
        if (!validLength(p.size)) return *error = "size must be a finite number >= 0", false;
        buildCube(p.size, out);
        out->extentMin = glm::vec3(float(-0.5 * p.size));
        out->extentMax = glm::vec3(float(0.5 * p.size));
        return true;
    }
    if (type == "Plane") {
        if (!validLength(p.width) || !validLength(p.length))
            return *error = "width and length must be finite numbers >= 0", false;
        // One quad facing +axis: width along x (axis Z, Y) or z (axis X), length along y (axis
        // Z, X) or z (axis Y) (UsdGeomPlane schema), counter-clockwise seen from the front.
        const float w = float(0.5 * p.width), l = float(0.5 * p.length);
        glm::vec3 n(0.0f, 0.0f, 1.0f);
        if (axis == 'X') {
            out->points = {{0, -l, -w}, {0, l, -w}, {0, l, w}, {0, -l, w}};
            n = glm::vec3(1, 0, 0);
        } else if (axis == 'Y') {
            out->points = {{-w, 0, l}, {w, 0, l}, {w, 0, -l}, {-w, 0, -l}};
            n = glm::vec3(0, 1, 0);
        } else {
            out->points = {{-w, -l, 0}, {w, -l, 0}, {w, l, 0}, {-w, l, 0}};
        }
        out->faceVertexCounts = {4};
        out->faceVertexIndices = {0, 1, 2, 3};
        out->normals.assign(4, n);
        out->extentMin = glm::min(out->points[0], out->points[2]);
        out->extentMax = glm::max(out->points[0], out->points[2]);
        return true;
    }
    if (!validLength(p.radius) || !validLength(p.height))
        return *error = "radius and height must be finite numbers >= 0", false;
    double halfAxis = 0.5 * p.height;
    if (type == "Cylinder") buildCylinder(p.radius, p.height, axis, out);
    else if (type == "Cone") buildCone(p.radius, p.height, axis, out);
    else if (type == "Capsule") buildCapsule(p.radius, p.height, axis, out), halfAxis += p.radius;
    else return *error = "'" + type + "' is not an implicit shape", false;
    out->extentMin = toAxis(axis, -p.radius, -p.radius, -halfAxis);
    out->extentMax = toAxis(axis, p.radius, p.radius, halfAxis);
    return true;
}

}  // namespace principled::adapter
