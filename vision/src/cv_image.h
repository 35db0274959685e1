#pragma once
// Private: OpenCV views of the project's images, and the pooling of a dense
// response into a LikelihoodMap.

#include <opencv2/core.hpp>
#include <optional>
#include <span>

#include "hcpf/core/image.h"
#include "hcpf/core/types.h"
#include "hcpf/vision/detector.h"

namespace hcpf::vision::internal {

// A CV_8UC3 (RGB order) header over the view's pixels: no copy; valid while
// the viewed pixels are.
inline cv::Mat RgbMat(const ImageView& view) {
  return cv::Mat(view.height, view.width, CV_8UC3, const_cast<uint8_t*>(view.data), view.stride);
}

// A point of a cv::pyrDown image in its source image's coordinates, in
// OpenCV's pixel coordinates (pixel i's centre at i, as cv::warpAffine reads
// a matrix): pyrDown centres its pixel i on source pixel 2 i. (2 i + 0.5, a
// centre convention that warpAffine does not share, put the diff detector's
// fitted warp half a pixel off: any rotation or scale A moved every pixel by
// (A - I)(0.5, 0.5), 0.026 px at 2 degrees and x1.01; a review.)
inline cv::Point2f FullResolutionOfHalf(cv::Point2f half) {
  return cv::Point2f(2.0f * half.x, 2.0f * half.y);
}

// Grey levels (OpenCV's RGB2GRAY: 0.299 R + 0.587 G + 0.114 B, rounded).
cv::Mat GreyMat(const ImageView& view);

// A response over an image of `width` x `height`, max-pooled into cells of
// `cell_px`; negative values become 0. Its value (x, y) stands for the point
// (x0 + x, y0 + y) of the image, in continuous coordinates (pixel i spans
// [i, i + 1)), and goes to the cell holding that point: a template of odd
// width centres its match in the middle of a pixel, x0 = left + w / 2.0
// (pooled by the pixel's index, such a match went to the cell before its
// centre's wherever a cell edge fell inside its pixel, with cells of a
// fractional size).
LikelihoodMap PoolToMap(const cv::Mat& response, double x0, double y0, int width, int height,
                        double cell_px);

// The box clipped to [0, width) x [0, height), or nullopt when less than a
// pixel remains.
std::optional<BoxPx> ClipToImage(const BoxPx& box, int width, int height);

// The window given for `target`, or nullptr.
const SearchWindow* WindowOf(std::span<const SearchWindow> windows, ObjectId target);

// The pixels within `scale` times the box's size around its centre, clipped
// to the image (possibly empty).
cv::Rect AroundBox(const BoxPx& box, double scale, int width, int height);

// v clamped to [lo, hi], then truncated to an int (NaN gives lo): a cast of a
// value beyond int is undefined, so the clamp comes first.
int ClampToInt(double v, int lo, int hi);

}  // namespace hcpf::vision::internal
