/* SPDX-License-Identifier: Apache-2.0 */
/* principled_types.h: the C types shared by the host ABI (principled_c.h) and the plugin table
 * (principled_plugin.h): version, status codes, pixel formats and plain structs. */
#ifndef PRINCIPLED_TYPES_H
#define PRINCIPLED_TYPES_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Major version of the ABI: a host only talks to plugins with the same major version. */
#define PRD_ABI_VERSION 1u
/** Minor version: calls appended to PrdRendererApi; a host accepts plugins whose table is at
 *  least as large as the one it was compiled against (structSize). */
#define PRD_ABI_MINOR 2u

typedef enum PrdStatus {
    PRD_OK = 0,
    PRD_ERROR_NULL_HANDLE = 1,      /**< the delegate handle is NULL */
    PRD_ERROR_INVALID_ARGUMENT = 2, /**< a NULL pointer, a bad size, a value of the wrong type */
    PRD_ERROR_NOT_FOUND = 3,        /**< unknown renderer, setting, AOV, prim, attribute, camera */
    PRD_ERROR_IO = 4,               /**< a file cannot be read or parsed */
    PRD_ERROR_NO_STAGE = 5,         /**< the call needs an open stage */
    PRD_ERROR_NOT_BOUND = 6,        /**< the AOV is not bound */
    PRD_ERROR_UNSUPPORTED = 7,      /**< valid request the renderer cannot do (yet) */
    PRD_ERROR_PLUGIN = 8,  /**< plugin library missing, entry point missing, ABI mismatch */
    PRD_ERROR_INTERNAL = 9 /**< a bug: an unexpected exception inside the library */
} PrdStatus;

/** Pixel formats of AOV buffers (a subset of Hydra's HdFormat). */
typedef enum PrdFormat {
    PRD_FORMAT_INVALID = 0,
    PRD_FORMAT_FLOAT32 = 1,
    PRD_FORMAT_FLOAT32_VEC2 = 2,
    PRD_FORMAT_FLOAT32_VEC3 = 3,
    PRD_FORMAT_FLOAT32_VEC4 = 4,
    PRD_FORMAT_INT32 = 5
} PrdFormat;

/** Type of a render setting's value. */
typedef enum PrdValueType {
    PRD_TYPE_NONE = 0,
    PRD_TYPE_INT = 1,   /**< set with prdSetSettingInt (bool settings too: 0/1) */
    PRD_TYPE_FLOAT = 2, /**< set with prdSetSettingFloat (an int is accepted) */
    PRD_TYPE_STRING = 3 /**< set with prdSetSettingString (tokens too) */
} PrdValueType;

/** A renderer the registry found. */
typedef struct PrdRendererInfo {
    const char* typeName;    /**< "PrincipledEmbreeRenderer" */
    const char* displayName; /**< "Embree" */
    const char* pluginName;  /**< plugInfo.json "Name" */
    const char* libraryPath; /**< absolute path of the plugin library */
    int priority;            /**< higher first */
    int loaded;              /**< 1 once the library was loaded successfully */
} PrdRendererInfo;

typedef struct PrdSettingDescriptor {
    const char* key;         /**< "convergedSamplesPerPixel" */
    const char* displayName; /**< "Samples per pixel" */
    const char* help;        /**< one line */
    PrdValueType type;
    const char* defaultText; /**< the default value as text ("64") */
} PrdSettingDescriptor;

typedef struct PrdAovInfo {
    const char* name; /**< "color" */
    PrdFormat format;
    int channels;     /**< values per pixel */
    int multiSampled; /**< 1: samples averaged; 0: first sample wins (IDs, depth) */
} PrdAovInfo;

typedef struct PrdBufferView {
    const void* data; /**< float or int32 values by format, top row first */
    int width;
    int height;
    int channels;
    PrdFormat format;
    int converged; /**< 1 when the pass that wrote it reached its target */
} PrdBufferView;

#ifdef __cplusplus
}
#endif

#endif /* PRINCIPLED_TYPES_H */
