#include "hcpf/tracker/normal.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

namespace hcpf::tracker {
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

// Rejection part of the ziggurat for layer i and uniform u (u >= k[i]).
// Returns true and sets *value when the point is accepted.
bool SlowPath(Rng& rng, int i, double u, double* value) {
  if (i == 0) {
    // Tail beyond r: Marsaglia (1964). a ~ Exp(r)/r accepted with prob exp(-a^2/2).
    double a = 0.0;
    double b = 0.0;
    do {
      a = -std::log(rng.UniformOpenZero()) / kR;
      b = -std::log(rng.UniformOpenZero());
    } while (b + b < a * a);
    *value = kR + a;
    return true;
  }
  const double xv = u * kTables.x[i];
  const double y = kTables.f[i] + rng.Uniform() * (kTables.f[i + 1] - kTables.f[i]);
  if (y < std::exp(-0.5 * xv * xv)) {
    *value = xv;
    return true;
  }
  return false;
}

// Draws one variate. `local` is a private copy of the caller's stream, never
// address-taken on the fast path, so its state stays in registers; the rare
// slow path syncs it through `home` (which SlowPath may advance).
inline double Draw(Rng& local, Rng& home) {
  for (;;) {
    const uint64_t bits = local.NextU64();
    const int i = static_cast<int>(bits & 0xFF);
    // Bit 8 is the sign, applied by XOR into the IEEE sign bit: a `negative ?
    // -v : v` select compiles to a branch that mispredicts half the time and
    // costs more than the rest of the generator.
    const uint64_t sign = (bits & 0x100) << 55;
    // Through int64: the value is < 2^53, and the signed conversion is one
    // instruction where the unsigned one is a branchy sequence without AVX-512.
    const double u = static_cast<double>(static_cast<int64_t>(bits >> 11)) * 0x1.0p-53;
    if (u < kTables.k[i]) {
      return std::bit_cast<double>(std::bit_cast<uint64_t>(u * kTables.x[i]) ^ sign);
    }
    home = local;
    double value = 0.0;
    const bool accepted = SlowPath(home, i, u, &value);
    local = home;
    if (accepted) return std::bit_cast<double>(std::bit_cast<uint64_t>(value) ^ sign);
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
  Rng local = rng;
  for (double& v : out) v = Draw(local, rng);
  rng = local;
}

}  // namespace hcpf::tracker
