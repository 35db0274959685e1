#pragma once
// PNG and JPEG through libpng and libjpeg(-turbo) directly. OpenCV's
// imgcodecs would do the same, but loading it (and the GDAL, HDF5, ... it
// links) costs every `hcpf` process ~20 ms before main(); these two libraries
// cost nothing measurable.

#include <cstdint>
#include <string>
#include <vector>

namespace hcpf::renderer::codecs {

// 8-bit RGB, rows top to bottom. Throws RunError naming the path.
void WritePngRgb8(const std::string& path, int width, int height, const uint8_t* rgb);
// 16-bit grey (network byte order is handled inside). Throws RunError.
void WritePngGray16(const std::string& path, int width, int height, const uint16_t* values);
// Reads any PNG as 8-bit RGB (palette, grey, alpha and 16-bit are converted).
// Throws InputError naming the path when it cannot be read.
std::vector<uint8_t> ReadPngRgb8(const std::string& path, int* width, int* height);
// Encodes 8-bit RGB as JPEG at `quality` (1..100, 4:2:0) and decodes it back
// in place: the sensor effect of a JPEG round trip.
void JpegRoundTrip(int width, int height, int quality, uint8_t* rgb);

}  // namespace hcpf::renderer::codecs
