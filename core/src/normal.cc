#include "hcpf/core/normal.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

namespace hcpf {
namespace {

// Marsaglia & Tsang (2000), 256 layers of equal area v under f(x) = exp(-x^2/2)
// (unnormalised density); r is the start of the tail.
constexpr double kR = 3.6541528853610088;
constexpr double kV = 4.92867323399e-3;
constexpr int kLayers = 256;

struct Tables {
  // x[i]: right edge of layer i (x[0] = v / f(r) is the pseudo-width of the base
  // strip, x[1] = r, x[256] = 0); f[i] = f(x[i]); k[i] = x[i+1] / x[i]: a
  // uniform u < k[i] lands in the part of layer i that lies wholly under f.
  std::array<double, kLayers + 1> x{};
  std::array<double, kLayers + 1> f{};
  std::array<double, kLayers> k{};

  Tables() {
    auto density = [](double t) { return std::exp(-0.5 * t * t); };
    x[0] = kV / density(kR);
    x[1] = kR;
    // Layer i spans y in [f(x_i), f(x_{i+1})] with area x_i * (f(x_{i+1}) - f(x_i)) = v.
    for (int i = 1; i < kLayers - 1; ++i) {
      x[i + 1] = std::sqrt(-2.0 * std::log(kV / x[i] + density(x[i])));
    }
    x[kLayers] = 0.0;
    for (int i = 0; i <= kLayers; ++i) f[i] = density(x[i]);
    for (int i = 0; i < kLayers; ++i) k[i] = x[i + 1] / x[i];
  }
};

const Tables kTables;

// Bit 8 of a raw draw is the sign, applied by XOR into the IEEE sign bit: a
// `negative ? -v : v` select compiles to a branch that mispredicts half the
// time and costs more than the rest of the generator.
inline uint64_t SignBit(uint64_t bits) { return (bits & 0x100) << 55; }

// The top 53 bits as a uniform in [0, 1). Through int64: the value is < 2^53,
// and the signed conversion is one instruction where the unsigned one is a
// branchy sequence without AVX-512.
inline double Uniform53(uint64_t bits) {
  return static_cast<double>(static_cast<int64_t>(bits >> 11)) * 0x1.0p-53;
}

// Rejection part of the ziggurat for a raw draw whose fast path (FastPath
// below) failed: its layer i and uniform u >= k[i]. Returns true and sets
// *value (with the draw's sign) when the point is accepted; may advance rng.
bool SlowPath(Rng& rng, uint64_t bits, double* value) {
  const int i = static_cast<int>(bits & 0xFF);
  const auto accept = [&](double magnitude) {
    *value = std::bit_cast<double>(std::bit_cast<uint64_t>(magnitude) ^ SignBit(bits));
    return true;
  };
  if (i == 0) {
    // Tail beyond r: Marsaglia (1964). a ~ Exp(r)/r accepted with prob exp(-a^2/2).
    double a = 0.0;
    double b = 0.0;
    do {
      a = -std::log(rng.UniformOpenZero()) / kR;
      b = -std::log(rng.UniformOpenZero());
    } while (b + b < a * a);
    return accept(kR + a);
  }
  const double xv = Uniform53(bits) * kTables.x[i];
  const double y = kTables.f[i] + rng.Uniform() * (kTables.f[i + 1] - kTables.f[i]);
  return y < std::exp(-0.5 * xv * xv) && accept(xv);
}

struct Fast {
  bool accepted;
  double value;
};

// The ziggurat's fast path for one raw draw: 8 bits pick the layer, bit 8 the
// sign, the top 53 bits the uniform; accepted when the point lies in the part
// of the layer wholly under the density.
inline Fast FastPath(uint64_t bits) {
  const int i = static_cast<int>(bits & 0xFF);
  const double u = Uniform53(bits);
  return {u < kTables.k[i],
          std::bit_cast<double>(std::bit_cast<uint64_t>(u * kTables.x[i]) ^ SignBit(bits))};
}

// Draws one variate. `local` is a private copy of the caller's stream, never
// address-taken on the fast path, so its state stays in registers; the rare
// slow path syncs it through `home` (which SlowPath may advance).
inline double Draw(Rng& local, Rng& home) {
  for (;;) {
    const uint64_t bits = local.NextU64();
    const Fast f = FastPath(bits);
    if (f.accepted) return f.value;
    home = local;
    double value = 0.0;
    const bool accepted = SlowPath(home, bits, &value);
    local = home;
    if (accepted) return value;
  }
}

}  // namespace

double ZigguratNormal(Rng& rng) {
  Rng local = rng;
  const double v = Draw(local, rng);
  rng = local;
  return v;
}

void FillStandardNormal(Rng& rng, std::span<double> out) {
  // Same numbers and the same final stream state as calling ZigguratNormal
  // out.size() times, but faster: the generator's recurrence runs alone over
  // a batch of raw draws (its latency chain is then the only dependency), and
  // the table lookups follow in a second loop. When a draw needs the slow path
  // (about 1 in 100), the stream is rewound to just after that draw, which is
  // where the one-at-a-time code would be, and the batch is restarted there.
  // A batch never holds more draws than outputs still owed, so the stream is
  // never advanced past the last draw the sequential code would make.
  constexpr size_t kBatch = 16;
  std::array<uint64_t, kBatch> bits;
  Rng local = rng;
  size_t done = 0;
  const size_t n = out.size();
  while (done < n) {
    const size_t b = std::min(kBatch, n - done);
    const Rng start = local;
    for (size_t j = 0; j < b; ++j) bits[j] = local.NextU64();
    size_t j = 0;
    for (; j < b; ++j) {
      const Fast f = FastPath(bits[j]);
      if (!f.accepted) break;
      out[done + j] = f.value;
    }
    done += j;
    if (j == b) continue;
    local = start;
    for (size_t t = 0; t <= j; ++t) local.NextU64();
    if (SlowPath(local, bits[j], &out[done])) ++done;
  }
  rng = local;
}

}  // namespace hcpf
