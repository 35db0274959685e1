#pragma once
// Images every module may exchange: the renderer produces them, detectors
// (vision/), the overlay writer and the frame cache read them. Plain data.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hcpf {

// 8-bit RGB, row-major, top row first, 3 bytes per pixel.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> pixels;
  uint8_t* at(int x, int y) { return pixels.data() + 3 * (static_cast<size_t>(y) * width + x); }
  const uint8_t* at(int x, int y) const {
    return pixels.data() + 3 * (static_cast<size_t>(y) * width + x);
  }
  friend bool operator==(const RgbImage&, const RgbImage&) = default;
};

// A read-only view of 8-bit RGB pixels whose rows are `stride` bytes apart
// (a crop of a larger image, or a buffer owned elsewhere). Does not own the
// pixels: the viewed image must outlive the view.
struct ImageView {
  const uint8_t* data = nullptr;
  int width = 0;
  int height = 0;
  size_t stride = 0;  // bytes from one row to the next, >= 3 * width

  ImageView() = default;
  ImageView(const uint8_t* pixels, int w, int h, size_t row_stride)
      : data(pixels), width(w), height(h), stride(row_stride) {}
  // The whole image, tightly packed.
  ImageView(const RgbImage& image)  // NOLINT(google-explicit-constructor): a view of it
      : data(image.pixels.data()),
        width(image.width),
        height(image.height),
        stride(3 * static_cast<size_t>(image.width)) {}

  const uint8_t* at(int x, int y) const {
    return data + static_cast<size_t>(y) * stride + 3 * static_cast<size_t>(x);
  }
  // The w x h sub-rectangle whose top-left pixel is (x, y); the caller keeps
  // it inside this view.
  ImageView Crop(int x, int y, int w, int h) const { return {at(x, y), w, h, stride}; }
  bool empty() const { return width <= 0 || height <= 0; }
};

}  // namespace hcpf
