#pragma once
// The interface between acdf's image reader (image_file.cpp) and its OpenImageIO module
// (openimageio_module.cpp), a shared object loaded on the first image that is not OpenEXR: a
// program that reads OpenEXR only then never loads the about 250 shared libraries OpenImageIO
// links, which cost a quarter of a second of dynamic linking at every start. Plain C types, so that
// no exception and no library object crosses it.

#include <cstddef>
#include <cstdint>

extern "C" {

// What an image's header claims, which acdf checks before any pixel is decoded.
struct AcdfImageClaims {
  int64_t width, height, depth, fileChannels;
  uint32_t channelsRead;  // 3 (RGB) or 1 (gray)
  double bytesPerRow;     // in the file's own pixel types
  int bufferedRows;       // rows OpenImageIO converts at once: a tile's height, else kScanlinesPerConversion
};

// One read: acdf's image and its sizing callback in, the format's name or the failure out.
struct AcdfImageRead {
  void* image;
  // Sizes the image as `claims` say and returns its pixels (channelsRead floats per pixel, rows
  // top down), or null with the reason in `problem` (NUL-terminated, at most problemSize bytes).
  float* (*prepare)(void* image, const AcdfImageClaims* claims, char* problem, std::size_t problemSize);
  char format[64];    // on success: OpenImageIO's name of the file's format
  char what[512];     // on failure: what could not be done
  char detail[1024];  // and OpenImageIO's message, if any
};

// The module's one entry point: reads `path` into read->image; true on success.
using AcdfReadWithOpenImageIO = bool (*)(const char* path, AcdfImageRead* read);
inline constexpr const char* kAcdfReadWithOpenImageIO = "acdf_read_with_openimageio";

}  // extern "C"

// OpenImageIO 2.4 converts pixels to float through a buffer of whole scanlines in the file's own
// format, at least 256 of them even for a shorter image (ImageInput::read_scanlines), or one row
// of tiles.
inline constexpr int kScanlinesPerConversion = 256;
