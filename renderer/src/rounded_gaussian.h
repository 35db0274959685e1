#pragma once
// Private: the sensor noise's integer sampler.
//
// The sensor adds N(0, sigma^2) noise to 8-bit values and rounds to the
// nearest level: out = clamp(round(p + sigma z), 0, 255). For an integer p,
// round(p + sigma z) = p + round(sigma z), so the noise is the integer
// K = round(sigma z), whose probabilities are known in closed form:
//   P(K = k) = Phi((k + 1/2) / sigma) - Phi((k - 1/2) / sigma).
// Drawing K directly gives the same output distribution as drawing z,
// without a normal variate per value. This table draws K with Walker's alias
// method from 32 random bits: the top bits pick one of n bins (n a power of
// two), the rest are compared with the bin's threshold, which picks the bin's
// own value or its alias.
//
// Exact to 2^-32: every value's probability is its closed-form one rounded to
// a whole number of 2^-32 units (the units sum to exactly 2^32), and the
// table reproduces those units exactly. Values beyond kmax = min(255,
// ceil(8 sigma)) are folded into +-kmax: beyond 255 the clamp makes them the
// same; beyond 8 sigma their mass (< 1.3e-15) is below one unit.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace hcpf::renderer::internal {

class RoundedGaussianTable {
 public:
  // sigma > 0.
  explicit RoundedGaussianTable(double sigma);

  // K for 32 uniformly random bits u.
  int32_t Sample(uint32_t u) const {
    const Bin& b = bins_[u >> shift_];
    // Branch-free (the comparison is a coin toss in most bins, so a branch
    // would mispredict often): alias + (value - alias) if below threshold.
    const int32_t below = -static_cast<int32_t>((u & mask_) < b.threshold);
    return b.alias + ((b.value - b.alias) & below);
  }

  // Two values per 64-bit word, the low half first: out[2i] = Sample(low
  // half of words[i]), out[2i + 1] = Sample(high half); `out` holds 2 x
  // `count` values. With AVX-512 and at most 64 bins (sigma <= 3.875, where
  // kmax <= 31) the bins are looked up sixteen at a time by register
  // permutes; otherwise, or when `scalar`, one at a time with Sample. Both
  // give the same values (RoundedGaussian.VectorLookupsEqualSample).
  void SampleWords(const uint64_t* words, size_t count, int16_t* out, bool scalar = false) const;
  // Whether SampleWords has its vector path on this machine and table (and
  // the active instruction set is AVX-512: hcpf/core/instruction_set.h; a
  // narrower one takes Sample, SensorEffects.EveryInstructionSetGivesTheSameBytes).
  bool HasVectorPath() const;

  int kmax() const { return kmax_; }
  // The number of 32-bit inputs u for which Sample(u) == k (0 outside
  // [-kmax, kmax]); these sum to 2^32.
  uint64_t Count(int k) const;

 private:
  struct Bin {
    uint32_t threshold = 0;  // in [0, 2^32 / n]
    int16_t value = 0;
    int16_t alias = 0;
  };
  int kmax_ = 0;
  int shift_ = 0;
  uint32_t mask_ = 0;
  std::vector<Bin> bins_;
  // The bins again as two arrays of 64, for the vector path (filled when
  // there are at most 64 bins; unused entries zero): thresholds, and value
  // (low 16 bits) with alias (high 16 bits).
  static constexpr size_t kVectorBins = 64;
  alignas(64) std::array<uint32_t, kVectorBins> thresholds_{};
  alignas(64) std::array<uint32_t, kVectorBins> values_{};
};

// The weights the table realises: P(K = k) for k = -kmax..kmax (index
// k + kmax) in units of 2^-32, rounded to nearest, summing to exactly 2^32
// (the remainder of the rounding goes to k = 0, the largest).
std::vector<uint64_t> RoundedGaussianWeights(double sigma, int kmax);

// kmax for sigma (see the header comment).
int RoundedGaussianKmax(double sigma);

}  // namespace hcpf::renderer::internal
