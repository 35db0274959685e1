#pragma once
// Deterministic random numbers for everything stochastic in HCPF Bench.
//
// One scenario seed drives every component through *named sub-streams*:
//   Rng root(seed);
//   Rng filter_rng = root.Fork("tracker/filter/3");
// A fork depends only on its parent's identity (seed + fork path) and the name,
// never on how many numbers the parent has drawn, so adding a component never
// shifts the numbers another component sees, and results do not depend on the
// order in which (or the thread on which) components run.
//
// The generator is xoshiro256** (Blackman & Vigna, 2018) seeded through
// splitmix64. Uniform and normal variates come from this file's own functions
// (not std::*_distribution, whose algorithms differ between standard libraries),
// so a seed gives the same numbers with every compiler and library.

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>
#include <string_view>

namespace hcpf {

// One xoshiro256** step: returns the output of state (s0, s1, s2, s3) and
// advances it. Rng::NextU64 is this on its own state; code that steps
// several streams in lockstep calls it per stream (the renderer's noise
// lanes, renderer/src/sensor.cc), so the compiler can vectorise across them.
inline uint64_t Xoshiro256StarStar(uint64_t& s0, uint64_t& s1, uint64_t& s2, uint64_t& s3) {
  const uint64_t result = std::rotl(s1 * 5, 7) * 9;
  const uint64_t t = s1 << 17;
  s2 ^= s0;
  s3 ^= s1;
  s1 ^= s2;
  s0 ^= s3;
  s2 ^= t;
  s3 = std::rotl(s3, 45);
  return result;
}

class Rng {
 public:
  explicit Rng(uint64_t seed = 0) { Reseed(seed); }

  // A new independent stream named `name` below this one.
  Rng Fork(std::string_view name) const;
  // Convenience for indexed streams: Fork(name + "/" + index).
  Rng Fork(std::string_view name, int64_t index) const;

  // The identity this stream was created from (seed mixed with its fork path).
  uint64_t identity() const { return identity_; }

  uint64_t NextU64() { return Xoshiro256StarStar(s_[0], s_[1], s_[2], s_[3]); }
  // The generator's state (s0, s1, s2, s3) for Xoshiro256StarStar: stepping
  // a copy gives the numbers NextU64 would.
  std::array<uint64_t, 4> state() const { return {s_[0], s_[1], s_[2], s_[3]}; }

  // Uniform in [0, 1) with 53 random bits.
  double Uniform() { return static_cast<double>(NextU64() >> 11) * 0x1.0p-53; }
  // Uniform in (0, 1]: safe to take the logarithm of.
  double UniformOpenZero() { return static_cast<double>((NextU64() >> 11) + 1) * 0x1.0p-53; }
  // Uniform in [lo, hi).
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  // Uniform integer in [0, n), n > 0 (Lemire's nearly-divisionless method).
  uint64_t UniformInt(uint64_t n);

  // Standard normal (Box–Muller; the second variate of each pair is kept).
  double Normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = UniformOpenZero();
    const double u2 = Uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double theta = 6.283185307179586 * u2;
    spare_ = r * std::sin(theta);
    has_spare_ = true;
    return r * std::cos(theta);
  }
  double Normal(double mean, double sigma) { return mean + sigma * Normal(); }

  // Poisson with mean lambda >= 0 (Knuth's product method on chunks of mean <= 16).
  int64_t Poisson(double lambda);
  // True with probability p.
  bool Bernoulli(double p) { return Uniform() < p; }

 private:
  void Reseed(uint64_t identity);

  uint64_t identity_ = 0;
  uint64_t s_[4] = {};
  double spare_ = 0.0;
  bool has_spare_ = false;
};

// 64-bit FNV-1a hash of a string; stable across platforms (used for fork names).
uint64_t HashName(std::string_view name);
// splitmix64 finaliser: a bijective 64-bit mixer.
uint64_t Mix64(uint64_t x);

}  // namespace hcpf
