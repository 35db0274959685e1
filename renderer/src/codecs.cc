#include "codecs.h"

#include <fmt/format.h>
#include <jpeglib.h>
#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <memory>

#include "hcpf/core/error.h"

namespace hcpf::renderer::codecs {
namespace {

struct FileCloser {
  void operator()(FILE* f) const {
    if (f != nullptr) std::fclose(f);
  }
};
using File = std::unique_ptr<FILE, FileCloser>;

// libpng reports errors by longjmp; these PNG calls hold no C++ objects with
// destructors between setjmp and the calls that may jump.
void WritePng(const std::string& path, int width, int height, int bit_depth, int color_type,
              const std::vector<const uint8_t*>& rows) {
  File file(std::fopen(path.c_str(), "wb"));
  if (!file) throw RunError(fmt::format("cannot write PNG {}: {}", path, std::strerror(errno)));
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  if (png == nullptr || info == nullptr) {
    png_destroy_write_struct(&png, &info);
    throw RunError("cannot write PNG " + path + ": out of memory");
  }
  if (setjmp(png_jmpbuf(png))) {
    // A failed write of the file (a full disk) is the usual cause, and fwrite
    // left its reason in errno; it was reported as "libpng error" alone.
    const int error = errno;
    const bool write_failed = std::ferror(file.get()) != 0;
    png_destroy_write_struct(&png, &info);
    throw RunError(fmt::format("cannot write PNG {}: {}", path,
                               write_failed ? std::strerror(error) : "libpng error"));
  }
  png_init_io(png, file.get());
  // Rendered frames (textures, sensor noise) compress poorly whatever the
  // effort: zlib level 6 with libpng's adaptive per-row filter choice took
  // ~125 ms a 640x480 frame, most of `hcpf render`'s time. Level 2 with the
  // UP filter writes the same pixels in ~18 ms, 8 % larger (crossing, 240
  // frames: 30.6 s -> 4.8 s, 81 -> 87 MB). Frames stay byte-identical run to
  // run.
  png_set_compression_level(png, 2);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height),
               bit_depth, color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (bit_depth == 16) png_set_swap(png);  // our uint16 are little-endian; PNG is big-endian
  for (const uint8_t* row : rows) png_write_row(png, row);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  // The reason when the disk is full (a buffered write fails at the flush or
  // the close; it was reported with none, and the close went unchecked).
  if (std::fflush(file.get()) != 0 || std::fclose(file.release()) != 0) {
    throw RunError(fmt::format("cannot write PNG {}: {}", path, std::strerror(errno)));
  }
}

}  // namespace

void WritePngRgb8(const std::string& path, int width, int height, const uint8_t* rgb) {
  std::vector<const uint8_t*> rows(height);
  for (int y = 0; y < height; ++y) rows[y] = rgb + static_cast<size_t>(y) * width * 3;
  WritePng(path, width, height, 8, PNG_COLOR_TYPE_RGB, rows);
}

void WritePngGray16(const std::string& path, int width, int height, const uint16_t* values) {
  std::vector<const uint8_t*> rows(height);
  for (int y = 0; y < height; ++y) {
    rows[y] = reinterpret_cast<const uint8_t*>(values + static_cast<size_t>(y) * width);
  }
  WritePng(path, width, height, 16, PNG_COLOR_TYPE_GRAY, rows);
}

std::vector<uint8_t> ReadPngRgb8(const std::string& path, int* width, int* height) {
  png_image image;
  std::memset(&image, 0, sizeof(image));
  image.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_file(&image, path.c_str()) == 0) {
    throw InputError(fmt::format("{}: cannot read PNG: {}", path, image.message));
  }
  image.format = PNG_FORMAT_RGB;
  std::vector<uint8_t> pixels(PNG_IMAGE_SIZE(image));
  if (png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr) == 0) {
    const std::string message = image.message;
    png_image_free(&image);
    throw InputError(fmt::format("{}: cannot read PNG: {}", path, message));
  }
  *width = static_cast<int>(image.width);
  *height = static_cast<int>(image.height);
  return pixels;
}

namespace {

struct JpegError {
  jpeg_error_mgr manager;
  std::jmp_buf jump;
};

void OnJpegError(j_common_ptr info) {
  auto* error = reinterpret_cast<JpegError*>(info->err);
  std::longjmp(error->jump, 1);
}

}  // namespace

void JpegRoundTrip(int width, int height, int quality, uint8_t* rgb) {
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  {
    jpeg_compress_struct c;
    JpegError error;
    c.err = jpeg_std_error(&error.manager);
    error.manager.error_exit = OnJpegError;
    if (setjmp(error.jump)) {
      jpeg_destroy_compress(&c);
      std::free(buffer);
      throw RunError("JPEG encoding failed");
    }
    jpeg_create_compress(&c);
    jpeg_mem_dest(&c, &buffer, &size);
    c.image_width = static_cast<JDIMENSION>(width);
    c.image_height = static_cast<JDIMENSION>(height);
    c.input_components = 3;
    c.in_color_space = JCS_RGB;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, quality, TRUE);
    jpeg_start_compress(&c, TRUE);
    while (c.next_scanline < c.image_height) {
      JSAMPROW row = rgb + static_cast<size_t>(c.next_scanline) * width * 3;
      jpeg_write_scanlines(&c, &row, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
  }
  jpeg_decompress_struct d;
  JpegError error;
  d.err = jpeg_std_error(&error.manager);
  error.manager.error_exit = OnJpegError;
  if (setjmp(error.jump)) {
    jpeg_destroy_decompress(&d);
    std::free(buffer);
    throw RunError("JPEG decoding failed");
  }
  jpeg_create_decompress(&d);
  jpeg_mem_src(&d, buffer, size);
  jpeg_read_header(&d, TRUE);
  d.out_color_space = JCS_RGB;
  jpeg_start_decompress(&d);
  while (d.output_scanline < d.output_height) {
    JSAMPROW row = rgb + static_cast<size_t>(d.output_scanline) * width * 3;
    jpeg_read_scanlines(&d, &row, 1);
  }
  jpeg_finish_decompress(&d);
  jpeg_destroy_decompress(&d);
  std::free(buffer);
}

}  // namespace hcpf::renderer::codecs
