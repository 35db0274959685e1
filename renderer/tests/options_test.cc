// Options validation, sensor effects and the frame cache (no GL).

#include <gtest/gtest.h>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "hcpf/core/error.h"
#include "hcpf/core/instruction_set.h"
#include "hcpf/core/text_file.h"
#include "hcpf/renderer/image_io.h"
#include "hcpf/renderer/renderer.h"
#include "support/process.h"

namespace hcpf::renderer {
namespace {

TEST(RendererOptions, DefaultsValidate) { EXPECT_NO_THROW(RendererOptions().Validate()); }

// The depth PNG holds 65535 units: at 1 mm, 100 m is past it and written
// 65535, and counted (every library camera is 90-400 m away, so every pixel
// was 65535 and nothing said so: a review); at 10 mm it fits. Read back
// (libpng's 8-bit reading, monotone in the value): 100 m is the brightest
// grey only where it saturated.
TEST(WriteDepthPng, CountsWhatItsUnitCannotHold) {
  const DepthImage depth{
      .width = 3, .height = 1, .depth_m = {50.0f, 100.0f, std::numeric_limits<float>::infinity()}};
  const std::string path =
      (std::filesystem::temp_directory_path() / "hcpf-depth-unit-test.png").string();
  EXPECT_EQ(WriteDepthPng(depth, path, 1.0), 1);
  RgbImage mm = ReadPng(path);
  EXPECT_EQ(mm.at(1, 0)[0], 255);  // 100,000 mm: written 65535
  EXPECT_LT(mm.at(0, 0)[0], 255);  // 50,000 mm
  EXPECT_EQ(mm.at(2, 0)[0], 0);    // nothing drawn
  EXPECT_EQ(WriteDepthPng(depth, path, 10.0), 0);
  RgbImage cm = ReadPng(path);
  EXPECT_LT(cm.at(1, 0)[0], 255);  // 10,000 cm
  EXPECT_LT(cm.at(0, 0)[0], cm.at(1, 0)[0]);
  std::filesystem::remove(path);
}

TEST(RendererOptions, BadFieldsAreNamed) {
  const auto message = [](const RendererOptions& o) {
    try {
      o.Validate();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  RendererOptions o;
  o.shadow_map_size = 10;
  EXPECT_NE(message(o).find("renderer.shadow_map_size"), std::string::npos);
  o = {};
  o.pcf_radius = -1;
  EXPECT_NE(message(o).find("renderer.pcf_radius"), std::string::npos);
  o = {};
  o.texture_size = 100;  // not a power of two
  EXPECT_NE(message(o).find("renderer.texture_size"), std::string::npos);
  o = {};
  o.sensor.jpeg_quality = 101;
  EXPECT_NE(message(o).find("sensor.jpeg_quality"), std::string::npos);
  o = {};
  o.sensor.exposure = 0.0;
  EXPECT_NE(message(o).find("sensor.exposure"), std::string::npos);
}

TEST(GlBackend, ParsesNamesAndRejectsOthers) {
  EXPECT_EQ(ParseGlBackend("auto"), GlBackend::kAuto);
  EXPECT_EQ(ParseGlBackend("osmesa"), GlBackend::kOsMesa);
  EXPECT_EQ(ParseGlBackend("egl"), GlBackend::kEgl);
  EXPECT_THROW(ParseGlBackend("vulkan"), InputError);
}

RgbImage Flat(int w, int h, uint8_t v) {
  RgbImage img;
  img.width = w;
  img.height = h;
  img.pixels.assign(static_cast<size_t>(w) * h * 3, v);
  return img;
}

// Per-channel sample mean and variance of (value - level) over an image.
struct ChannelMoments {
  double mean[3] = {};
  double variance[3] = {};  // unbiased (n - 1)
};

ChannelMoments MomentsAround(const RgbImage& image, double level) {
  ChannelMoments m;
  const double n = static_cast<double>(image.width) * image.height;
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0;
    for (size_t i = c; i < image.pixels.size(); i += 3) sum += image.pixels[i] - level;
    const double mean = sum / n;
    double ss = 0.0;
    for (size_t i = c; i < image.pixels.size(); i += 3) {
      const double d = image.pixels[i] - level - mean;
      ss += d * d;
    }
    m.mean[c] = mean;
    m.variance[c] = ss / (n - 1.0);
  }
  return m;
}

TEST(SensorEffects, NoiseHasZeroMeanAndTheRequestedVariancePerChannel) {
  // Mid-grey 128 with sigma 5: clipping needs a 25-sigma draw, so the output
  // is round(128 + 5 z). Rounding a continuous variable whose density is
  // smooth on the scale of one grey level adds independent uniform error on
  // [-1/2, 1/2] (Sheppard's correction): expected variance 25 + 1/12, mean 0.
  //
  // Tolerances, n = 400 * 300 = 120,000 values per channel, 5 standard errors:
  //  - mean: SE = sqrt(25 + 1/12) / sqrt(n) = 5.008 / 346.4 = 0.0145 -> 0.072;
  //  - variance: for normal data SE(s^2) = sigma^2 sqrt(2 / (n - 1)) =
  //    25.08 * 0.00408 = 0.102 -> 0.51. (The rounded values' excess kurtosis
  //    is -(1/120) / 25.08^2 ~ -1e-5: the normal formula holds.)
  // A wrong scale (sigma 4.9 or 5.1 gives variance 24.1 or 26.1) or a
  // missing channel fails by several times the tolerance.
  SensorOptions s;
  s.noise_sigma = 5.0;
  for (const uint64_t seed : {uint64_t{1}, uint64_t{2}}) {
    RgbImage a = Flat(400, 300, 128);
    ApplySensorEffects(s, Rng(seed).Fork("renderer/sensor", 0), a);
    const ChannelMoments m = MomentsAround(a, 128.0);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(m.mean[c], 0.0, 0.072) << "seed " << seed << " channel " << c;
      EXPECT_NEAR(m.variance[c], 25.0 + 1.0 / 12.0, 0.51) << "seed " << seed << " channel " << c;
    }
  }
}

TEST(SensorEffects, NoiseOfNeighboursIsUncorrelated) {
  // Every byte gets its own draw: the correlation of horizontally adjacent
  // values of one channel, and of two channels of one pixel, is 0. For
  // independent values the sample correlation of n pairs has SE 1/sqrt(n);
  // n ~ 120,000 -> 0.0029, tolerance 5 SE = 0.0145.
  SensorOptions s;
  s.noise_sigma = 5.0;
  RgbImage a = Flat(400, 300, 128);
  ApplySensorEffects(s, Rng(3).Fork("renderer/sensor", 0), a);
  const auto correlation = [&](auto first, auto second) {
    double sxy = 0.0, sxx = 0.0, syy = 0.0;
    int64_t n = 0;
    for (int y = 0; y < a.height; ++y) {
      for (int x = 0; x + 1 < a.width; ++x) {
        const double u = first(x, y) - 128.0;
        const double v = second(x, y) - 128.0;
        sxy += u * v;
        sxx += u * u;
        syy += v * v;
        ++n;
      }
    }
    return sxy / std::sqrt(sxx * syy);
  };
  EXPECT_NEAR(correlation([&](int x, int y) { return a.at(x, y)[0]; },
                          [&](int x, int y) { return a.at(x + 1, y)[0]; }),
              0.0, 0.0145);
  EXPECT_NEAR(correlation([&](int x, int y) { return a.at(x, y)[0]; },
                          [&](int x, int y) { return a.at(x, y)[1]; }),
              0.0, 0.0145);
}

TEST(SensorEffects, NoiseIsUncorrelatedAtEveryLagOfItsGeneratorLanes) {
  // The noise words come from eight generator lanes, interleaved (word 8k +
  // l from lane l, two values a word): values 2 apart come from neighbouring
  // lanes, 16 apart from the same lane's next draw. The sample correlation of
  // values `lag` apart in memory, for every lag up to 40 (two rounds of the
  // lanes and more), is 0 within 5 SE: n ~ 360,000 pairs, SE 1/sqrt(n) =
  // 0.00167, tolerance 0.0083. Lanes seeded alike would give lag 2 a
  // correlation of 1.
  SensorOptions s;
  s.noise_sigma = 5.0;
  RgbImage a = Flat(400, 300, 128);
  ApplySensorEffects(s, Rng(6).Fork("renderer/sensor", 0), a);
  const size_t n = a.pixels.size();
  for (size_t lag = 1; lag <= 40; ++lag) {
    double sxy = 0.0, sxx = 0.0, syy = 0.0;
    for (size_t i = 0; i + lag < n; ++i) {
      const double u = a.pixels[i] - 128.0;
      const double v = a.pixels[i + lag] - 128.0;
      sxy += u * v;
      sxx += u * u;
      syy += v * v;
    }
    EXPECT_NEAR(sxy / std::sqrt(sxx * syy), 0.0, 0.0083) << "lag " << lag;
  }
}

TEST(SensorEffects, NoiseClipsAtBlackAndWhiteWithoutWrapping) {
  // At level L the output is clamp(round(L + sigma z), 0, 255), so
  //   P(0)   = P(L + sigma z < 0.5)    = Phi((0.5 - L) / sigma),
  //   P(255) = P(L + sigma z >= 254.5) = 1 - Phi((254.5 - L) / sigma).
  // A value that wrapped (e.g. -1 -> 255) would move mass between the two.
  // Tolerance: 5 binomial standard errors sqrt(p (1 - p) / n), n = 3 * 200 * 150.
  const auto phi = [](double t) { return 0.5 * std::erfc(-t / std::sqrt(2.0)); };
  struct Case {
    uint8_t level;
    double sigma;
  };
  for (const Case c : {Case{0, 5.0}, Case{255, 5.0}, Case{250, 100.0}, Case{3, 100.0}}) {
    SensorOptions s;
    s.noise_sigma = c.sigma;
    RgbImage a = Flat(200, 150, c.level);
    ApplySensorEffects(s, Rng(4).Fork("renderer/sensor", 0), a);
    const double n = static_cast<double>(a.pixels.size());
    double zeros = 0.0, whites = 0.0;
    for (const uint8_t v : a.pixels) {
      zeros += v == 0 ? 1.0 : 0.0;
      whites += v == 255 ? 1.0 : 0.0;
    }
    const double p0 = phi((0.5 - c.level) / c.sigma);
    const double p255 = 1.0 - phi((254.5 - c.level) / c.sigma);
    EXPECT_NEAR(zeros / n, p0, 5.0 * std::sqrt(p0 * (1.0 - p0) / n) + 1e-12)
        << "level " << int{c.level} << " sigma " << c.sigma;
    EXPECT_NEAR(whites / n, p255, 5.0 * std::sqrt(p255 * (1.0 - p255) / n) + 1e-12)
        << "level " << int{c.level} << " sigma " << c.sigma;
  }
}

TEST(SensorEffects, NoiseRoundsToTheNearestLevel) {
  // With sigma 0.1 at level 100 a draw leaves the level only beyond |z| = 5
  // (probability 5.7e-7 per value, so ~0.07 of the 120,000 values): the
  // output is the level itself, not one below (truncation) or above.
  SensorOptions s;
  s.noise_sigma = 0.1;
  RgbImage a = Flat(200, 200, 100);
  ApplySensorEffects(s, Rng(5).Fork("renderer/sensor", 0), a);
  int64_t off = 0;
  for (const uint8_t v : a.pixels) off += v != 100 ? 1 : 0;
  EXPECT_LE(off, 3);  // Poisson(0.07): P(> 3) < 1e-6
}

TEST(SensorEffects, SameStreamGivesTheSameBytesAndAnotherFrameOther) {
  // The renderer forks rng.Fork("renderer/sensor", frame) per frame: the same
  // fork gives byte-identical noise (on images of every size, including
  // ones that are not a whole number of noise blocks or vector chunks), and
  // the next frame's fork different noise.
  SensorOptions s;
  s.noise_sigma = 3.0;
  s.blur_px = 0.7;
  s.jpeg_quality = 85;
  const Rng root(42);
  for (const auto& [w, h] : {std::pair{200, 100}, std::pair{37, 11}, std::pair{1, 1}}) {
    RgbImage a = Flat(w, h, 128);
    RgbImage b = Flat(w, h, 128);
    RgbImage c = Flat(w, h, 128);
    for (int i = 0; i < w * h * 3; ++i) a.pixels[i] = b.pixels[i] = c.pixels[i] = (i * 37) % 251;
    ApplySensorEffects(s, root.Fork("renderer/sensor", 7), a);
    ApplySensorEffects(s, root.Fork("renderer/sensor", 7), b);
    ApplySensorEffects(s, root.Fork("renderer/sensor", 8), c);
    EXPECT_EQ(a, b) << w << "x" << h;
    if (w * h > 1) {
      // (not for one pixel: its three values after JPEG may well coincide)
      EXPECT_NE(a, c) << w << "x" << h;
    }
  }
}

// Every instruction set this CPU has gives the same bytes: the noise words'
// lanes (FillLanes) and, with AVX-512, the table lookups sixteen at a time
// (SampleWordsAvx512; a narrower set takes the scalar lookups), at a sigma
// whose table fits the vector path (3) and one whose does not (10).
TEST(SensorEffects, EveryInstructionSetGivesTheSameBytes) {
  for (const double sigma : {3.0, 10.0}) {
    SensorOptions s;
    s.noise_sigma = sigma;
    const auto noisy = [&] {
      RgbImage a = Flat(203, 61, 128);
      ApplySensorEffects(s, Rng(8).Fork("renderer/sensor", 0), a);
      return a.pixels;
    };
    std::vector<uint8_t> expected;
    {
      const hcpf::testing::ScopedInstructionSet baseline(InstructionSet::kBaseline);
      expected = noisy();
    }
    hcpf::testing::ForEachInstructionSetOfThisCpu([&](InstructionSet set) {
      EXPECT_TRUE(noisy() == expected) << NameOf(set) << ", sigma " << sigma;
    });
  }
}

TEST(SensorEffects, ExposureScalesAndSaturates) {
  SensorOptions s;
  s.exposure = 1.5;
  RgbImage a = Flat(4, 4, 100);
  ApplySensorEffects(s, Rng(1), a);
  EXPECT_EQ(a.pixels[0], 150);  // 100 * 1.5
  RgbImage b = Flat(4, 4, 200);
  ApplySensorEffects(s, Rng(1), b);
  EXPECT_EQ(b.pixels[0], 255);  // 300 saturates
}

TEST(SensorEffects, BlurSpreadsAnEdgeAndKeepsFlatAreas) {
  SensorOptions s;
  s.blur_px = 2.0;
  RgbImage a = Flat(40, 10, 0);
  for (int y = 0; y < 10; ++y) {
    for (int x = 20; x < 40; ++x) a.at(x, y)[0] = a.at(x, y)[1] = a.at(x, y)[2] = 200;
  }
  ApplySensorEffects(s, Rng(1), a);
  EXPECT_EQ(a.at(2, 5)[0], 0);  // 18 px (9 sigma) from the edge
  EXPECT_EQ(a.at(37, 5)[0], 200);
  // At the edge, a Gaussian-blurred step is half way: pixels 19 and 20
  // straddle it, so one is below and one above 100, both strictly between.
  EXPECT_GT(a.at(19, 5)[0], 0);
  EXPECT_LT(a.at(19, 5)[0], 100);
  EXPECT_GT(a.at(20, 5)[0], 100);
  EXPECT_LT(a.at(20, 5)[0], 200);
}

TEST(SensorEffects, JpegRoundTripChangesDetailButKeepsMeanLevel) {
  SensorOptions s;
  s.jpeg_quality = 10;
  RgbImage a = Flat(64, 64, 0);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) a.at(x, y)[1] = ((x / 2 + y / 2) % 2) ? 255 : 0;  // checker
  }
  const RgbImage before = a;
  ApplySensorEffects(s, Rng(1), a);
  EXPECT_NE(a, before);
  double mean = 0.0;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) mean += a.at(x, y)[1];
  }
  // A 2-px checker is half 255: mean 127.5; JPEG keeps block means (the DC
  // coefficient) to within a few levels even at quality 10.
  EXPECT_NEAR(mean / (64.0 * 64.0), 127.5, 12.0);
}

TEST(PixelHash, ChangesWithPixelsNotWithOutputFlags) {
  WorldSpec w;
  w.frames = 10;
  w.camera.path.push_back({0, {0, 0, 100}, {0, 0, 0}});
  RendererOptions o;
  const std::string h = PixelHash(w, o, 7);
  EXPECT_EQ(h.size(), 32u);
  EXPECT_EQ(h, PixelHash(w, o, 7));
  EXPECT_NE(h, PixelHash(w, o, 8));
  RendererOptions o2 = o;
  o2.output_depth = true;
  o2.backend = GlBackend::kEgl;
  EXPECT_EQ(h, PixelHash(w, o2, 7));
  o2.sensor.noise_sigma = 1.0;
  EXPECT_NE(h, PixelHash(w, o2, 7));
  WorldSpec w2 = w;
  w2.sun.azimuth_deg += 1.0;
  EXPECT_NE(h, PixelHash(w2, o, 7));
}

TEST(PixelHash, KnowsAModelByItsNameAndContentNotItsFolder) {
  // The same scene in two clones: model paths are absolute, the hash alike.
  const auto root = hcpf::testing::FreshDir("pixel-hash-model");
  std::filesystem::create_directories(root / "a");
  std::filesystem::create_directories(root / "b");
  WriteTextFile((root / "a" / "car.obj").string(), "v 0 0 0\n");
  WriteTextFile((root / "b" / "car.obj").string(), "v 0 0 0\n");
  WriteTextFile((root / "b" / "van.obj").string(), "v 0 0 0\n");
  WorldSpec w;
  w.frames = 10;
  w.camera.path.push_back({0, {0, 0, 100}, {0, 0, 0}});
  TargetSpec t;
  t.id = ObjectId(1);
  t.model = (root / "a" / "car.obj").string();
  w.targets.push_back(t);
  const RendererOptions o;
  const std::string h = PixelHash(w, o, 7);
  WorldSpec moved = w;
  moved.targets[0].model = (root / "b" / "car.obj").string();
  EXPECT_EQ(PixelHash(moved, o, 7), h);
  // Another name (the extension picks the loader) or content: other pixels.
  moved.targets[0].model = (root / "b" / "van.obj").string();
  EXPECT_NE(PixelHash(moved, o, 7), h);
  WriteTextFile((root / "a" / "car.obj").string(), "v 0 0 1\n");
  EXPECT_NE(PixelHash(w, o, 7), h);
}

// The files a model's loader reads beside it count as the model: a .gltf's
// buffers by URI (a .bin edited in place, its bounds unchanged, had been
// served from the cache as the old geometry) and an .obj's material
// libraries (their colours). Embedded data: URIs are in the model's bytes.
TEST(PixelHash, KnowsAModelByTheFilesItNamesBesideItToo) {
  const auto root = hcpf::testing::FreshDir("pixel-hash-side-files");
  WriteTextFile((root / "box.gltf").string(),
                R"({"asset": {"version": "2.0"}, "buffers": [{"uri": "my%20box.bin", )"
                R"("byteLength": 4}, {"uri": "data:application/octet-stream;base64,AAAAAA==", )"
                R"("byteLength": 4}]})");
  WriteTextFile((root / "my box.bin").string(), "abcd");
  WriteTextFile((root / "car.obj").string(), "# a car\n  mtllib\tcar paint.mtl \r\nv 0 0 0\n");
  WriteTextFile((root / "car paint.mtl").string(), "newmtl red\nKd 1 0 0\n");
  WorldSpec w;
  w.frames = 10;
  w.camera.path.push_back({0, {0, 0, 100}, {0, 0, 0}});
  TargetSpec t;
  t.id = ObjectId(1);
  t.model = (root / "box.gltf").string();
  w.targets.push_back(t);
  OccluderSpec car;
  car.kind = OccluderKind::kMesh;
  car.model = (root / "car.obj").string();
  w.occluders.push_back(car);
  const RendererOptions o;
  const std::string h = PixelHash(w, o, 7);
  EXPECT_EQ(PixelHash(w, o, 7), h);
  WriteTextFile((root / "my box.bin").string(), "abce");
  const std::string bin_edited = PixelHash(w, o, 7);
  EXPECT_NE(bin_edited, h);
  WriteTextFile((root / "car paint.mtl").string(), "newmtl red\nKd 0 1 0\n");
  const std::string mtl_edited = PixelHash(w, o, 7);
  EXPECT_NE(mtl_edited, bin_edited);
  std::filesystem::remove(root / "car paint.mtl");
  EXPECT_NE(PixelHash(w, o, 7), mtl_edited);
}

TEST(FrameCache, StoresAndLoadsFramesExactly) {
  const auto root = hcpf::testing::FreshDir("frame-cache");
  FrameCache cache(root, "abc");
  EXPECT_FALSE(cache.Load(3).has_value());
  RenderedFrame f;
  f.frame = 3;
  f.rgb = Flat(8, 6, 0);
  f.rgb.at(7, 5)[2] = 250;
  f.ground_truth.frame = 3;
  f.ground_truth.camera.intrinsics = CameraIntrinsics::FromHorizontalFov(8, 6, 40.0);
  f.ground_truth.camera.intrinsics.cx_px += 0.1234567890123;
  GroundTruthObject obj;
  obj.id = ObjectId{4};
  obj.amodal_box = {1.5, 2.25, 3.0, 1.0 / 3.0};
  obj.visible_fraction = 2.0 / 3.0;
  obj.pixels_visible = 2;
  obj.pixels_total = 3;
  f.ground_truth.objects.push_back(obj);
  cache.Store(f);
  const auto loaded = cache.Load(3);
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ(loaded->rgb, f.rgb);
  EXPECT_EQ(loaded->ground_truth.camera.intrinsics, f.ground_truth.camera.intrinsics);
  ASSERT_EQ(loaded->ground_truth.objects.size(), 1u);
  EXPECT_EQ(loaded->ground_truth.objects[0].amodal_box, obj.amodal_box);
  EXPECT_EQ(loaded->ground_truth.objects[0].visible_fraction, obj.visible_fraction);
  EXPECT_EQ(loaded->ground_truth.objects[0].pixels_total, 3);
}

RenderedFrame NoisyFrame(int frame, int width, int height, uint64_t seed) {
  RenderedFrame f;
  f.frame = frame;
  f.rgb = Flat(width, height, 0);
  Rng rng(seed);
  for (uint8_t& v : f.rgb.pixels) v = static_cast<uint8_t>(rng.UniformInt(256));
  f.ground_truth.frame = frame;
  return f;
}

std::string ReadBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}
void WriteBytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// The renderers that stored frames in a scene's folder: each noted once, in
// the order first noted; a cache without the file (frames from before they
// were noted) has none.
TEST(FrameCache, NotesEachRendererOnce) {
  const auto root = hcpf::testing::FreshDir("frame-cache-renderers");
  const FrameCache cache(root, "abc");
  EXPECT_TRUE(cache.Renderers().empty());
  GlInfo cpu{.backend = "osmesa",
             .platform = "osmesa",
             .vendor = "Mesa",
             .renderer = "llvmpipe (LLVM 15.0.6, 256 bits)",
             .version = "4.5 (Core Profile) Mesa 22.3.6"};
  GlInfo gpu{.backend = "egl",
             .platform = "egl device 0 (hardware)",
             .vendor = "NVIDIA Corporation",
             .renderer = "NVIDIA H200/PCIe/SSE2",
             .version = "4.6.0 NVIDIA 550.54"};
  EXPECT_EQ(RendererLine(cpu),
            "osmesa; Mesa; llvmpipe (LLVM 15.0.6, 256 bits); 4.5 (Core Profile) Mesa 22.3.6");
  cache.NoteRenderer(cpu);
  cache.NoteRenderer(cpu);
  EXPECT_EQ(cache.Renderers(), std::vector<std::string>{RendererLine(cpu)});
  cache.NoteRenderer(gpu);
  cache.NoteRenderer(cpu);
  EXPECT_EQ(cache.Renderers(), (std::vector<std::string>{RendererLine(cpu), RendererLine(gpu)}));
  std::ifstream in(root / "abc" / "renderers.txt");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), RendererLine(cpu) + "\n" + RendererLine(gpu) + "\n");
  // A line break inside a GL string cannot split a line.
  gpu.renderer = "two\nlines";
  EXPECT_EQ(RendererLine(gpu).find('\n'), std::string::npos);
}

// Issue 13 item 2: every byte value at every position survives the left
// difference and zstd (uniform noise: the filter's wrap-around mod 256 is
// exercised everywhere); a file of another format version, a truncated or a
// flipped payload is a miss (re-rendered), never misread; an old PNG-format
// entry (NNNNNN.png) is not read at all.
TEST(FrameCache, FormatVersionAndDamageAreMissesNeverMisreads) {
  const auto root = hcpf::testing::FreshDir("frame-cache-format");
  const FrameCache cache(root, "abc");
  const RenderedFrame f = NoisyFrame(2, 37, 11, 5);
  cache.Store(f);
  ASSERT_TRUE(cache.Load(2).has_value());
  EXPECT_EQ(cache.Load(2)->rgb, f.rgb);
  const auto path = cache.dir() / "000002.frame";
  const std::string good = ReadBytes(path);
  ASSERT_EQ(good.compare(0, 8, "HCPFRAME"), 0);
  EXPECT_EQ(static_cast<unsigned char>(good[8]), FrameCache::kFormatVersion);

  std::string other_version = good;
  other_version[8] = static_cast<char>(FrameCache::kFormatVersion + 1);
  WriteBytes(path, other_version);
  EXPECT_FALSE(cache.Load(2).has_value());

  WriteBytes(path, good.substr(0, good.size() - 5));  // truncated
  EXPECT_FALSE(cache.Load(2).has_value());

  // One flipped bit in the payload (uniform noise is stored as raw blocks, so
  // the stream still parses): zstd's content checksum makes it a miss.
  for (size_t at : {good.size() / 2, good.size() - 6}) {
    std::string flipped = good;
    flipped[at] = static_cast<char>(flipped[at] ^ 0x01);
    WriteBytes(path, flipped);
    EXPECT_FALSE(cache.Load(2).has_value()) << "byte " << at << " of " << good.size();
  }

  WriteBytes(path, good);
  EXPECT_EQ(cache.Load(2)->rgb, f.rgb);

  // The previous format (PNG + JSON): not this format, so a miss.
  std::filesystem::rename(path, cache.dir() / "000002.png");
  EXPECT_FALSE(cache.Load(2).has_value());
}

// A store that fails part-way (a full disk: RLIMIT_FSIZE under the frame's
// size, in a child process) says why and leaves no temporary file: it said
// "cannot write <name>.tmp" with no reason and kept the partial file in the
// cache for good.
TEST(FrameCache, AStoreThatFailsSaysWhyAndLeavesNothing) {
  const auto root = hcpf::testing::FreshDir("frame-cache-full");
  const FrameCache cache(root, "abc");
  const RenderedFrame f = NoisyFrame(2, 64, 48, 9);  // noise: ~9 KB whatever zstd does
  const int code = hcpf::testing::InChildWithFileSizeLimit(4096, [&] {
    try {
      cache.Store(f);
    } catch (const RunError& e) {
      const std::string text = e.what();
      return text.find("000002.frame failed: " + std::string(std::strerror(EFBIG))) !=
                     std::string::npos
                 ? 0
                 : 3;
    }
    return 4;  // no error
  });
  EXPECT_EQ(code, 0) << "3: another message, 4: no error";
  std::vector<std::string> left;
  for (const auto& e : std::filesystem::directory_iterator(cache.dir()))
    left.push_back(e.path().filename().string());
  EXPECT_TRUE(left.empty()) << left.front();
  EXPECT_FALSE(cache.Load(2).has_value());
  cache.Store(f);  // and without the limit, stored whole
  EXPECT_EQ(cache.Load(2)->rgb, f.rgb);
}

// A PNG that cannot be written whole (a full disk: RLIMIT_FSIZE under its
// size, in a child process) says why: it said "libpng error".
TEST(WritePng, AFailedWriteSaysWhy) {
  const auto dir = hcpf::testing::FreshDir("png-full");
  const RenderedFrame f = NoisyFrame(1, 64, 48, 3);  // noise: ~9 KB of PNG
  const std::string path = (dir / "frame.png").string();
  const int code = hcpf::testing::InChildWithFileSizeLimit(4096, [&] {
    try {
      WritePng(f.rgb, path);
    } catch (const RunError& e) {
      return std::string(e.what()) == "cannot write PNG " + path + ": " + std::strerror(EFBIG) ? 0
                                                                                               : 3;
    }
    return 4;  // no error
  });
  EXPECT_EQ(code, 0) << "3: another message, 4: no error";
}

// The writer stores exactly what Store would, for every frame submitted, and
// Finish reports a store's failure instead of losing it.
TEST(FrameCache, WriterStoresEverySubmittedFrameAndReportsFailures) {
  const auto root = hcpf::testing::FreshDir("frame-cache-writer");
  const FrameCache cache(root, "abc");
  std::vector<RenderedFrame> frames;
  for (int i = 0; i < 12; ++i) frames.push_back(NoisyFrame(i, 16, 9, 100 + i));
  {
    FrameCacheWriter writer(cache, 2);
    for (const RenderedFrame& f : frames) writer.Submit(f);
    writer.Finish();
  }
  for (const RenderedFrame& f : frames) {
    const auto loaded = cache.Load(f.frame);
    ASSERT_TRUE(loaded.has_value()) << f.frame;
    EXPECT_EQ(loaded->rgb, f.rgb) << f.frame;
  }
  // Three workers taking the frames in turn store the same files.
  const FrameCache three(root, "three");
  {
    FrameCacheWriter writer(three, 1, 3);
    for (const RenderedFrame& f : frames) writer.Submit(f);
    writer.Finish();
  }
  for (const RenderedFrame& f : frames) {
    const std::string name = fmt::format("{:06d}.frame", f.frame);
    EXPECT_EQ(ReadBytes(three.dir() / name), ReadBytes(cache.dir() / name)) << f.frame;
  }
  // The same bytes as a synchronous Store.
  const FrameCache direct(root, "direct");
  direct.Store(frames[7]);
  EXPECT_EQ(ReadBytes(cache.dir() / "000007.frame"), ReadBytes(direct.dir() / "000007.frame"));

  // A cache whose directory cannot be created (a file is in the way).
  WriteBytes(root / "blocked", "x");
  FrameCacheWriter blocked(FrameCache(root / "blocked", "abc"));
  blocked.Submit(frames[0]);
  EXPECT_THROW(blocked.Finish(), RunError);
  // With several workers, a failure on any of them reaches Finish.
  FrameCacheWriter blocked_three(FrameCache(root / "blocked", "abc"), 1, 3);
  for (int i = 0; i < 2; ++i) blocked_three.Submit(frames[static_cast<size_t>(i)]);
  EXPECT_THROW(blocked_three.Finish(), RunError);
}

}  // namespace
}  // namespace hcpf::renderer

namespace hcpf::renderer {
namespace {

TEST(ContactSheet, GridOfThumbnailsWithGap) {
  std::vector<RenderedFrame> frames(5);
  for (int i = 0; i < 5; ++i) {
    frames[i].frame = i;
    frames[i].rgb = Flat(64, 48, static_cast<uint8_t>(40 * i));
  }
  ContactSheetOptions o;
  o.columns = 3;
  o.thumb_width_px = 32;
  const RgbImage sheet = MakeContactSheet(frames, o);
  // 3 columns x 2 rows of 32 x 24 thumbnails with 4 px gaps around them:
  // width 3 * (32 + 4) + 4 = 112, height 2 * (24 + 4) + 4 = 60.
  EXPECT_EQ(sheet.width, 112);
  EXPECT_EQ(sheet.height, 60);
  // The fifth frame (value 160) sits in row 1, column 1; probe its centre.
  EXPECT_EQ(sheet.at(4 + 36 + 16, 4 + 28 + 18)[1], 160);
}

// Green boxes on green grass (an audit found them hard to see on the
// contact sheet): every box is a 1 px line over a 3 px black one. On a thumb
// at full size (scale 1), a visible box whose left edge is x = 10 draws green
// at x = 10 and black at x = 9 and 11; the grass at x = 13 is untouched.
TEST(ContactSheet, BoxesAreOutlinedInBlack) {
  std::vector<RenderedFrame> frames(1);
  frames[0].rgb = Flat(64, 48, 0);
  for (size_t p = 1; p < frames[0].rgb.pixels.size(); p += 3) frames[0].rgb.pixels[p] = 150;
  GroundTruthObject o;
  o.id = ObjectId{1};
  o.in_frame = true;
  o.amodal_box = {.left = 10, .top = 20, .width = 30, .height = 16};
  o.visible_box = o.amodal_box;
  o.visible_fraction = 1.0;
  frames[0].ground_truth.objects = {o};
  ContactSheetOptions options;
  options.columns = 1;
  options.thumb_width_px = 64;
  const RgbImage sheet = MakeContactSheet(frames, options);
  constexpr int kGap = 4;   // the sheet's margin
  const int y = kGap + 28;  // halfway down the box's left edge
  const auto rgb = [&](int x) {
    const uint8_t* px = sheet.at(kGap + x, y);
    return std::array<int, 3>{px[0], px[1], px[2]};
  };
  EXPECT_EQ(rgb(10), (std::array<int, 3>{0, 255, 0}));
  EXPECT_EQ(rgb(9), (std::array<int, 3>{0, 0, 0}));
  EXPECT_EQ(rgb(11), (std::array<int, 3>{0, 0, 0}));
  EXPECT_EQ(rgb(13), (std::array<int, 3>{0, 150, 0}));
}

// Labels of targets side by side go apart (an audit: at the end of a
// crossing two labels were printed over each other on the contact sheet).
// On a black frame at scale 1, two boxes 8 x 20 at x = 50 and 54, y = 40:
// the first label goes above its box; the second's place above is taken by
// it, so it goes below (from y = 40 + 20 + 2 = 62, hcpf::PlaceLabels). Its
// white text is there, under both boxes, where nothing was drawn when every
// label went above its box.
TEST(ContactSheet, LabelsOfTargetsSideBySideGoApart) {
  std::vector<RenderedFrame> frames(1);
  frames[0].rgb = Flat(200, 100, 0);
  for (const int id : {1, 2}) {
    GroundTruthObject o;
    o.id = ObjectId{id};
    o.in_frame = true;
    o.amodal_box = {.left = 46.0 + 4 * id, .top = 40, .width = 7, .height = 19};
    o.visible_fraction = 1.0;
    frames[0].ground_truth.objects.push_back(o);
  }
  ContactSheetOptions options;
  options.columns = 1;
  options.thumb_width_px = 200;
  const RgbImage sheet = MakeContactSheet(frames, options);
  constexpr int kGap = 4;
  int white_below = 0, white_above = 0;
  for (int y = 0; y < 100; ++y) {
    for (int x = 40; x < 120; ++x) {
      const uint8_t* px = sheet.at(kGap + x, kGap + y);
      if (px[0] < 200 || px[1] < 200 || px[2] < 200) continue;  // not the labels' white
      (y >= 62 ? white_below : white_above) += 1;
    }
  }
  EXPECT_GT(white_above, 0);
  EXPECT_GT(white_below, 0);
}

// The device selection of issue 13 item 3, on described devices: a GPU's
// EGL device first for auto and egl, OSMesa before the surfaceless platform
// for auto only, Mesa's software device last, OSMesa alone for osmesa.
TEST(GlBackendPlan, HardwareEglDevicesFirstSoftwareLast) {
  using Kind = GlAttempt::Kind;
  const std::vector<EglDeviceDescription> devices = {
      {.index = 0, .extensions = "EGL_EXT_device_drm EGL_MESA_device_software"},
      {.index = 1, .extensions = "EGL_NV_device_cuda EGL_EXT_device_drm"},
      {.index = 2, .extensions = "EGL_EXT_device_drm EGL_EXT_device_drm_render_node"}};
  EXPECT_TRUE(devices[0].software());
  EXPECT_FALSE(devices[1].software());
  const std::vector<GlAttempt> automatic = PlanGlAttempts(GlBackend::kAuto, devices);
  const std::vector<GlAttempt> expected_auto = {{Kind::kEglDevice, 1},
                                                {Kind::kEglDevice, 2},
                                                {Kind::kOsMesa, -1},
                                                {Kind::kEglSurfaceless, -1},
                                                {Kind::kEglDevice, 0}};
  EXPECT_EQ(automatic, expected_auto);
  const std::vector<GlAttempt> egl = PlanGlAttempts(GlBackend::kEgl, devices);
  const std::vector<GlAttempt> expected_egl = {{Kind::kEglDevice, 1},
                                               {Kind::kEglDevice, 2},
                                               {Kind::kEglSurfaceless, -1},
                                               {Kind::kEglDevice, 0}};
  EXPECT_EQ(egl, expected_egl);
  const std::vector<GlAttempt> osmesa = PlanGlAttempts(GlBackend::kOsMesa, devices);
  EXPECT_EQ(osmesa, (std::vector<GlAttempt>{{Kind::kOsMesa, -1}}));
  // No devices (no EGL_EXT_device_enumeration): OSMesa, then surfaceless.
  EXPECT_EQ(PlanGlAttempts(GlBackend::kAuto, {}),
            (std::vector<GlAttempt>{{Kind::kOsMesa, -1}, {Kind::kEglSurfaceless, -1}}));
}

}  // namespace
}  // namespace hcpf::renderer
