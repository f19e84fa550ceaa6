// SPDX-License-Identifier: Apache-2.0
// PrdSceneBuilder: host data (meshes, materials, lights, cameras) written as USDA text, so a
// host without files still goes through the one stage -> adapter -> index path.
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <new>
#include <string>
#include <vector>

#include "plugins/abi/principled_c.h"

struct PrdSceneBuilder {
    struct Prim {
        std::string type;
        std::vector<std::string> schemas;
        std::vector<std::string> lines;  ///< attribute lines, authored order
    };
    std::vector<std::string> order;  ///< paths, insertion order
    std::map<std::string, Prim> prims;
    std::string upAxis = "Y";
    double metersPerUnit = 0.01;
    std::string text;
};

namespace {

bool validName(const std::string& n) {
    if (n.empty() || !(std::isalpha(static_cast<unsigned char>(n[0])) || n[0] == '_')) return false;
    for (char c : n)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
    return true;
}

/// Checks an absolute prim path; returns "" or why it is invalid.
std::string checkPath(const char* path) {
    if (!path) return "path is NULL";
    std::string p = path;
    if (p.size() < 2 || p[0] != '/' || p.back() == '/')
        return "prim path '" + p + "' must be absolute, like /World/Mesh";
    size_t start = 1;
    while (start <= p.size()) {
        size_t end = p.find('/', start);
        if (end == std::string::npos) end = p.size();
        if (!validName(p.substr(start, end - start)))
            return "prim path '" + p + "' has an invalid name '" + p.substr(start, end - start) +
                   "'";
        start = end + 1;
    }
    return "";
}

std::string number(double v, bool integer) {
    char buf[40];
    if (integer)
        std::snprintf(buf, sizeof buf, "%lld", static_cast<long long>(std::llround(v)));
    else
        std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

/// Values per element of a USD value type: "float" 1, "color3f" 3, "quatf" 4, "matrix4d" 16.
int tupleSize(const std::string& base) {
    if (base == "matrix4d") return 16;
    if (base == "matrix3d") return 9;
    if (base == "matrix2d") return 4;
    if (base.rfind("quat", 0) == 0) return 4;
    for (char c : base)
        if (c >= '2' && c <= '4') return c - '0';
    return 1;
}

bool isIntegral(const std::string& base) {
    return base == "int" || base == "int64" || base == "uint" || base == "uint64" ||
           base == "uchar" || base == "bool" || base.rfind("int", 0) == 0;
}

std::string element(const double* v, int n, bool integer, bool matrix = false) {
    if (n == 1) return number(v[0], integer);
    std::string out = "(";
    if (matrix) {
        int rows = n == 16 ? 4 : n == 9 ? 3 : 2;
        for (int r = 0; r < rows; ++r) {
            out += r ? ", (" : "(";
            for (int c = 0; c < rows; ++c)
                out += (c ? ", " : "") + number(v[r * rows + c], integer);
            out += ")";
        }
        return out + ")";
    }
    for (int i = 0; i < n; ++i) out += (i ? ", " : "") + number(v[i], integer);
    return out + ")";
}

std::string quoted(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        if (c == '\n') {
            out += "\\n";
            continue;
        }
        out += c;
    }
    return out + "\"";
}

PrdSceneBuilder::Prim& ensurePrim(PrdSceneBuilder* b, const std::string& path,
                                  const std::string& type) {
    // Ancestors first, as Xforms.
    for (size_t slash = path.find('/', 1); slash != std::string::npos;
         slash = path.find('/', slash + 1)) {
        std::string parent = path.substr(0, slash);
        if (!b->prims.count(parent)) {
            b->prims[parent].type = "Xform";
            b->order.push_back(parent);
        }
    }
    if (!b->prims.count(path)) b->order.push_back(path);
    auto& p = b->prims[path];
    p.type = type;
    return p;
}

void setLine(PrdSceneBuilder::Prim& p, const std::string& name, const std::string& line) {
    // Re-authoring an attribute replaces its line (matched by " name =" or " name.connect =").
    for (auto& l : p.lines) {
        if (l.find(" " + name + " =") != std::string::npos) {
            l = line;
            return;
        }
    }
    p.lines.push_back(line);
}

void emit(const PrdSceneBuilder* b, const std::string& path, int depth, std::string* out) {
    const auto& p = b->prims.at(path);
    std::string indent(4 * depth, ' ');
    std::string name = path.substr(path.rfind('/') + 1);
    *out += indent + "def " + p.type + " \"" + name + "\"";
    if (!p.schemas.empty()) {
        *out += " (prepend apiSchemas = [";
        for (size_t i = 0; i < p.schemas.size(); ++i)
            *out += (i ? ", \"" : "\"") + p.schemas[i] + "\"";
        *out += "])";
    }
    *out += "\n" + indent + "{\n";
    for (const auto& l : p.lines) *out += indent + "    " + l + "\n";
    for (const std::string& child : b->order)
        if (child.size() > path.size() && child.compare(0, path.size(), path) == 0 &&
            child[path.size()] == '/' && child.find('/', path.size() + 1) == std::string::npos)
            emit(b, child, depth + 1, out);
    *out += indent + "}\n";
}

}  // namespace

// Defined in hostApi.cpp: makes prdLastError(NULL) return `message`.
void prdSetThreadError(const std::string& message);

#define PRD_BUILDER_CHECK(call)                                     \
    if (!b) {                                                       \
        prdSetThreadError(std::string(call) + ": builder is NULL"); \
        return PRD_ERROR_NULL_HANDLE;                               \
    }

#define PRD_FAIL(status, call, message)                          \
    do {                                                         \
        prdSetThreadError(std::string(call) + ": " + (message)); \
        return status;                                           \
    } while (0)

#define PRD_PATH(call, path)                             \
    if (std::string why = checkPath(path); !why.empty()) \
    PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, call, why)

extern "C" {

PrdStatus prdSceneBuilderCreate(PrdSceneBuilder** out) {
    if (!out) PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, "prdSceneBuilderCreate", "out is NULL");
    *out = new (std::nothrow) PrdSceneBuilder;
    return *out ? PRD_OK : PRD_ERROR_INTERNAL;
}

void prdSceneBuilderDestroy(PrdSceneBuilder* b) {
    delete b;
}

PrdStatus prdSceneSetStageMetadata(PrdSceneBuilder* b, const char* upAxis, double metersPerUnit) {
    PRD_BUILDER_CHECK("prdSceneSetStageMetadata");
    std::string up = upAxis ? upAxis : "Y";
    if (up != "Y" && up != "Z")
        PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, "prdSceneSetStageMetadata",
                 "upAxis must be \"Y\" or \"Z\", not '" + up + "'");
    if (!(metersPerUnit > 0.0) || !std::isfinite(metersPerUnit))
        PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, "prdSceneSetStageMetadata",
                 "metersPerUnit must be positive");
    b->upAxis = up;
    b->metersPerUnit = metersPerUnit;
    return PRD_OK;
}

PrdStatus prdSceneAddPrim(PrdSceneBuilder* b, const char* path, const char* typeName) {
    PRD_BUILDER_CHECK("prdSceneAddPrim");
    PRD_PATH("prdSceneAddPrim", path);
    if (!typeName || !validName(typeName))
        PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, "prdSceneAddPrim",
                 "typeName must be a USD type name like Xform or Camera");
    auto it = b->prims.find(path);
    if (it != b->prims.end() && !(it->second.type == "Xform" && it->second.lines.empty()))
        PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, "prdSceneAddPrim",
                 std::string("prim '") + path + "' already exists");
    ensurePrim(b, path, typeName);
    return PRD_OK;
}

PrdStatus prdSceneAddMesh(PrdSceneBuilder* b, const char* path, const float* points,
                          size_t pointCount, const int* counts, size_t faceCount,
                          const int* indices, size_t indexCount) {
    const char* call = "prdSceneAddMesh";
    PRD_BUILDER_CHECK(call);
    PRD_PATH(call, path);
    if (!points || !counts || !indices)
        PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, call, "points, counts and indices must not be NULL");
    size_t sum = 0;
    for (size_t f = 0; f < faceCount; ++f) {
        if (counts[f] < 3)
            PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, call,
                     "face " + std::to_string(f) + " has " + std::to_string(counts[f]) +
                         " vertices (at least 3)");
        sum += size_t(counts[f]);
    }
    if (sum != indexCount)
        PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, call,
                 "face vertex counts add up to " + std::to_string(sum) + " but " +
                     std::to_string(indexCount) + " indices were given");
    for (size_t i = 0; i < indexCount; ++i)
        if (indices[i] < 0 || size_t(indices[i]) >= pointCount)
            PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, call,
                     "index " + std::to_string(indices[i]) + " at " + std::to_string(i) +
                         " is out of range (" + std::to_string(pointCount) + " points)");
    if (prdSceneAddPrim(b, path, "Mesh") != PRD_OK) return PRD_ERROR_INVALID_ARGUMENT;
    auto& p = b->prims[path];
    std::string c = "int[] faceVertexCounts = [", ix = "int[] faceVertexIndices = [",
                pts = "point3f[] points = [";
    for (size_t f = 0; f < faceCount; ++f) c += (f ? ", " : "") + std::to_string(counts[f]);
    for (size_t i = 0; i < indexCount; ++i) ix += (i ? ", " : "") + std::to_string(indices[i]);
    for (size_t i = 0; i < pointCount; ++i) {
        double v[3] = {points[3 * i], points[3 * i + 1], points[3 * i + 2]};
        pts += (i ? ", " : "") + element(v, 3, false);
    }
    p.lines.push_back("uniform token subdivisionScheme = \"none\"");
    p.lines.push_back(c + "]");
    p.lines.push_back(ix + "]");
    p.lines.push_back(pts + "]");
    return PRD_OK;
}

PrdStatus prdSceneSetAttribute(PrdSceneBuilder* b, const char* path, const char* typeName,
                               const char* name, const double* values, size_t count,
                               const char* interpolation) {
    const char* call = "prdSceneSetAttribute";
    PRD_BUILDER_CHECK(call);
    PRD_PATH(call, path);
    if (!b->prims.count(path))
        PRD_FAIL(PRD_ERROR_NOT_FOUND, call, std::string("no prim at '") + path + "': add it first");
    if (!typeName || !name || !*name)
        PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, call, "typeName and name must not be NULL");
    if (!values && count) PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, call, "values is NULL");
    std::string type = typeName;
    bool array = type.size() > 2 && type.compare(type.size() - 2, 2, "[]") == 0;
    std::string base = array ? type.substr(0, type.size() - 2) : type;
    int n = tupleSize(base);
    bool integer = isIntegral(base);
    bool matrix = base.rfind("matrix", 0) == 0;
    if ((!array && count != size_t(n)) || (array && count % size_t(n) != 0))
        PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, call,
                 std::string("'") + name + "' of type " + type + " needs " +
                     (array ? "a multiple of " : "") + std::to_string(n) + " numbers, got " +
                     std::to_string(count));
    for (size_t i = 0; i < count; ++i)
        if (!std::isfinite(values[i]))
            PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, call,
                     std::string("'") + name + "' has a non-finite value");
    std::string value;
    if (array) {
        value = "[";
        for (size_t i = 0; i < count; i += n)
            value += (i ? ", " : "") + element(values + i, n, integer, matrix);
        value += "]";
    } else {
        value = element(values, n, integer, matrix);
    }
    if (base == "bool") value = values[0] != 0.0 ? "true" : "false";
    std::string line = type + " " + name + " = " + value;
    if (interpolation && *interpolation) line += " (interpolation = " + quoted(interpolation) + ")";
    setLine(b->prims[path], name, line);
    return PRD_OK;
}

PrdStatus prdSceneSetAttributeString(PrdSceneBuilder* b, const char* path, const char* typeName,
                                     const char* name, const char* value) {
    const char* call = "prdSceneSetAttributeString";
    PRD_BUILDER_CHECK(call);
    PRD_PATH(call, path);
    if (!b->prims.count(path))
        PRD_FAIL(PRD_ERROR_NOT_FOUND, call, std::string("no prim at '") + path + "': add it first");
    if (!typeName || !name || !value)
        PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, call, "typeName, name and value must not be NULL");
    std::string type = typeName;
    std::string v;
    if (type == "token" || type == "string")
        v = quoted(value);
    else if (type == "asset") {
        if (std::string(value).find('@') != std::string::npos)
            PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, call, "asset paths cannot contain '@'");
        v = std::string("@") + value + "@";
    } else
        PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, call,
                 "typeName must be token, string or asset, not '" + type + "'");
    setLine(b->prims[path], name, type + " " + name + " = " + v);
    return PRD_OK;
}

PrdStatus prdSceneSetTransform(PrdSceneBuilder* b, const char* path, const double matrix[16]) {
    PRD_BUILDER_CHECK("prdSceneSetTransform");
    if (!matrix) PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, "prdSceneSetTransform", "matrix is NULL");
    PrdStatus s =
        prdSceneSetAttribute(b, path, "matrix4d", "xformOp:transform", matrix, 16, nullptr);
    if (s != PRD_OK) return s;
    setLine(b->prims[path], "xformOpOrder",
            "uniform token[] xformOpOrder = [\"xformOp:transform\"]");
    return PRD_OK;
}

PrdStatus prdSceneAddMaterial(PrdSceneBuilder* b, const char* path) {
    const char* call = "prdSceneAddMaterial";
    PRD_BUILDER_CHECK(call);
    if (PrdStatus s = prdSceneAddPrim(b, path, "Material"); s != PRD_OK) return s;
    std::string shader = std::string(path) + "/Surface";
    b->prims[path].lines.push_back("token outputs:surface.connect = <" + shader +
                                   ".outputs:surface>");
    ensurePrim(b, shader, "Shader");
    b->prims[shader].lines.push_back("uniform token info:id = \"UsdPreviewSurface\"");
    b->prims[shader].lines.push_back("token outputs:surface");
    return PRD_OK;
}

PrdStatus prdSceneSetMaterialInput(PrdSceneBuilder* b, const char* materialPath, const char* input,
                                   const double* values, size_t count) {
    const char* call = "prdSceneSetMaterialInput";
    PRD_BUILDER_CHECK(call);
    PRD_PATH(call, materialPath);
    auto it = b->prims.find(materialPath);
    if (it == b->prims.end() || it->second.type != "Material")
        PRD_FAIL(
            PRD_ERROR_NOT_FOUND, call,
            std::string("no material at '") + materialPath + "': call prdSceneAddMaterial first");
    if (!input || !validName(input))
        PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, call, "input must be a name like diffuseColor");
    std::string in = input;
    const char* type = in == "useSpecularWorkflow" ? "int"
                       : in == "normal"            ? "normal3f"
                       : count == 3                ? "color3f"
                                                   : "float";
    return prdSceneSetAttribute(b, (std::string(materialPath) + "/Surface").c_str(), type,
                                ("inputs:" + in).c_str(), values, count, nullptr);
}

PrdStatus prdSceneSetMaterialTexture(PrdSceneBuilder* b, const char* materialPath,
                                     const char* input, const char* file, const char* channel) {
    const char* call = "prdSceneSetMaterialTexture";
    PRD_BUILDER_CHECK(call);
    PRD_PATH(call, materialPath);
    auto it = b->prims.find(materialPath);
    if (it == b->prims.end() || it->second.type != "Material")
        PRD_FAIL(
            PRD_ERROR_NOT_FOUND, call,
            std::string("no material at '") + materialPath + "': call prdSceneAddMaterial first");
    if (!input || !validName(input) || !file)
        PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, call, "input and file must be given");
    std::string ch = channel ? channel : "rgb";
    if (ch != "rgb" && ch != "r" && ch != "g" && ch != "b" && ch != "a")
        PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, call, "channel must be rgb, r, g, b or a");
    std::string m = materialPath, tex = m + "/" + input + "Texture", reader = m + "/stReader";
    ensurePrim(b, tex, "Shader");
    auto& t = b->prims[tex];
    t.lines.clear();
    t.lines.push_back("uniform token info:id = \"UsdUVTexture\"");
    t.lines.push_back("asset inputs:file = @" + std::string(file) + "@");
    t.lines.push_back("float2 inputs:st.connect = <" + reader + ".outputs:result>");
    t.lines.push_back(ch == "rgb" ? "float3 outputs:rgb" : "float outputs:" + ch);
    if (!b->prims.count(reader)) {
        ensurePrim(b, reader, "Shader");
        b->prims[reader].lines = {"uniform token info:id = \"UsdPrimvarReader_float2\"",
                                  "string inputs:varname = \"st\"", "float2 outputs:result"};
    }
    std::string type =
        ch == "rgb" ? (std::string(input) == "normal" ? "normal3f" : "color3f") : "float";
    std::string name = std::string("inputs:") + input + ".connect";
    setLine(b->prims[m + "/Surface"], name,
            type + " " + name + " = <" + tex + ".outputs:" + ch + ">");
    return PRD_OK;
}

PrdStatus prdSceneBindMaterial(PrdSceneBuilder* b, const char* primPath, const char* materialPath) {
    const char* call = "prdSceneBindMaterial";
    PRD_BUILDER_CHECK(call);
    PRD_PATH(call, primPath);
    PRD_PATH(call, materialPath);
    if (!b->prims.count(primPath))
        PRD_FAIL(PRD_ERROR_NOT_FOUND, call, std::string("no prim at '") + primPath + "'");
    auto it = b->prims.find(materialPath);
    if (it == b->prims.end() || it->second.type != "Material")
        PRD_FAIL(PRD_ERROR_NOT_FOUND, call, std::string("no material at '") + materialPath + "'");
    auto& p = b->prims[primPath];
    bool has = false;
    for (const auto& s : p.schemas) has |= s == "MaterialBindingAPI";
    if (!has) p.schemas.push_back("MaterialBindingAPI");
    setLine(p, "material:binding", std::string("rel material:binding = <") + materialPath + ">");
    return PRD_OK;
}

PrdStatus prdSceneToUsda(PrdSceneBuilder* b, const char** text) {
    PRD_BUILDER_CHECK("prdSceneToUsda");
    if (!text) PRD_FAIL(PRD_ERROR_INVALID_ARGUMENT, "prdSceneToUsda", "text is NULL");
    b->text = "#usda 1.0\n(\n    upAxis = " + quoted(b->upAxis) +
              "\n    metersPerUnit = " + number(b->metersPerUnit, false) + "\n)\n\n";
    for (const std::string& path : b->order)
        if (path.find('/', 1) == std::string::npos) emit(b, path, 0, &b->text);
    *text = b->text.c_str();
    return PRD_OK;
}

PrdStatus prdOpenStageFromBuilder(PrdDelegate* d, PrdSceneBuilder* b) {
    if (!d) PRD_FAIL(PRD_ERROR_NULL_HANDLE, "prdOpenStageFromBuilder", "delegate is NULL");
    PRD_BUILDER_CHECK("prdOpenStageFromBuilder");
    const char* text = nullptr;
    if (PrdStatus s = prdSceneToUsda(b, &text); s != PRD_OK) return s;
    return prdOpenStageString(d, text, "<host scene>");
}

}  // extern "C"
