// SPDX-License-Identifier: Apache-2.0
// The output encoders over OpenEXRCore (OpenEXR's C library) and libpng: both are small C
// libraries (zlib and libc/libm only), so the executable links them directly and writing the
// output loads neither OpenImageIO nor OpenEXR's C++ libraries (docs/performance.md, section 0).
#include "delegate/imageio/nativeWriter.h"

#include <cmath>
#include <openexr.h>
#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>

namespace principled::imageio {

namespace {

// OpenEXRCore reports the detailed message through a callback (default: printed to stderr).
thread_local std::string exrMessage;

void exrError(exr_const_context_t, exr_result_t code, const char* msg) {
    exrMessage = msg && *msg ? msg : exr_get_default_error_message(code);
}

}  // namespace

bool writeExrFloat(const std::string& path, int width, int height,
                   const std::vector<std::string>& names, const float* pixels,
                   std::string* error, float pixelAspectRatio) {
    const size_t nch = names.size();
    if (width <= 0 || height <= 0 || nch == 0) {
        *error = "nothing to write";
        return false;
    }
    exrMessage.clear();
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = &exrError;
    exr_context_t f = nullptr;
    exr_result_t rv = exr_start_write(&f, path.c_str(), EXR_WRITE_FILE_DIRECTLY, &init);
    // AOV layers make names longer than 31 characters ("layer.channel"): OpenEXR 2 files allow
    // up to 255 with the long-names flag, which only such files get (as Imf does).
    bool longNames = false;
    for (const auto& n : names) longNames |= n.size() > 31;
    if (rv == EXR_ERR_SUCCESS && longNames) rv = exr_set_longname_support(f, 1);
    int part = 0;
    if (rv == EXR_ERR_SUCCESS) rv = exr_add_part(f, nullptr, EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr_simple(f, part, width, height, EXR_COMPRESSION_ZIP);
    if (rv == EXR_ERR_SUCCESS && pixelAspectRatio != 1.0f && std::isfinite(pixelAspectRatio) && pixelAspectRatio > 0.0f)
        rv = exr_set_pixel_aspect_ratio(f, part, pixelAspectRatio);
    // OpenEXRCore keeps the channel list sorted by name, as the format requires.
    for (size_t c = 0; c < nch && rv == EXR_ERR_SUCCESS; ++c)
        rv = exr_add_channel(f, part, names[c].c_str(), EXR_PIXEL_FLOAT,
                             EXR_PERCEPTUALLY_LINEAR, 1, 1);
    if (rv == EXR_ERR_SUCCESS) rv = exr_write_header(f);
    int32_t lines = 1;
    if (rv == EXR_ERR_SUCCESS) rv = exr_get_scanlines_per_chunk(f, part, &lines);
    exr_encode_pipeline_t encoder{};
    bool encoderInitialized = false, encoderReady = false;
    for (int y = 0; y < height && rv == EXR_ERR_SUCCESS; y += lines) {
        exr_chunk_info_t chunk{};
        rv = exr_write_scanline_chunk_info(f, part, y, &chunk);
        if (rv != EXR_ERR_SUCCESS) break;
        rv = encoderInitialized ? exr_encoding_update(f, part, &chunk, &encoder)
                                : exr_encoding_initialize(f, part, &chunk, &encoder);
        if (rv != EXR_ERR_SUCCESS) break;
        encoderInitialized = true;
        // Each channel of the file reads its values from the interleaved pixels.
        for (int16_t c = 0; c < encoder.channel_count; ++c) {
            exr_coding_channel_info_t& ch = encoder.channels[c];
            size_t k = 0;
            while (k < nch && names[k] != ch.channel_name) ++k;
            ch.user_bytes_per_element = 4;
            ch.user_data_type = EXR_PIXEL_FLOAT;
            ch.user_pixel_stride = int32_t(nch * sizeof(float));
            ch.user_line_stride = int32_t(size_t(width) * nch * sizeof(float));
            ch.encode_from_ptr =
                reinterpret_cast<const uint8_t*>(pixels + (size_t(chunk.start_y) * width) * nch + k);
        }
        if (!encoderReady) {
            rv = exr_encoding_choose_default_routines(f, part, &encoder);
            encoderReady = rv == EXR_ERR_SUCCESS;
            if (!encoderReady) break;
        }
        rv = exr_encoding_run(f, part, &encoder);
    }
    if (encoderInitialized) exr_encoding_destroy(f, &encoder);
    exr_result_t done = f ? exr_finish(&f) : EXR_ERR_SUCCESS;
    if (rv == EXR_ERR_SUCCESS) rv = done;
    if (rv != EXR_ERR_SUCCESS) {
        *error = "OpenEXR: " + (exrMessage.empty()
                                    ? std::string(exr_get_default_error_message(rv))
                                    : exrMessage);
        return false;
    }
    return true;
}

bool writePng8(const std::string& path, int width, int height, int channels,
               const uint8_t* pixels, std::string* error) {
    if (width <= 0 || height <= 0 || (channels != 3 && channels != 4)) {
        *error = "PNG needs 3 or 4 channels";
        return false;
    }
    png_image image;
    std::memset(&image, 0, sizeof(image));
    image.version = PNG_IMAGE_VERSION;
    image.width = png_uint_32(width);
    image.height = png_uint_32(height);
    image.format = channels == 4 ? PNG_FORMAT_RGBA : PNG_FORMAT_RGB;
    // libpng's simplified API: 8-bit sRGB samples, rows top first, stride = width * channels.
    if (!png_image_write_to_file(&image, path.c_str(), 0, pixels, 0, nullptr)) {
        *error = std::string("libpng: ") + image.message;
        png_image_free(&image);
        return false;
    }
    return true;
}

}  // namespace principled::imageio
