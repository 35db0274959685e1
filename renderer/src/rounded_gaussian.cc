#include "rounded_gaussian.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "hcpf/core/check.h"
#include "hcpf/core/instruction_set.h"

namespace hcpf::renderer::internal {
namespace {

constexpr uint64_t kUnits = uint64_t{1} << 32;  // the weights' unit is 2^-32

}  // namespace

int RoundedGaussianKmax(double sigma) {
  return static_cast<int>(std::clamp(std::ceil(8.0 * sigma), 1.0, 255.0));
}

std::vector<uint64_t> RoundedGaussianWeights(double sigma, int kmax) {
  // P(K = k) = Phi((k + 1/2) / s) - Phi((k - 1/2) / s) for 0 < k < kmax, as
  // a difference of upper tails (both small far out, so no cancellation
  // against 1): Phi-bar(t) = erfc(t / sqrt 2) / 2. P(K >= kmax) is one tail.
  const double scale = 1.0 / (sigma * std::sqrt(2.0));
  const auto upper = [&](double t) { return 0.5 * std::erfc(t * scale); };
  std::vector<uint64_t> w(2 * static_cast<size_t>(kmax) + 1, 0);
  for (int k = 1; k <= kmax; ++k) {
    const double p = k < kmax ? upper(k - 0.5) - upper(k + 0.5) : upper(k - 0.5);
    const auto units = static_cast<uint64_t>(std::llround(p * static_cast<double>(kUnits)));
    w[static_cast<size_t>(kmax + k)] = units;
    w[static_cast<size_t>(kmax - k)] = units;
  }
  // K = 0 takes the rest, which is its own probability erf(1 / (2 sqrt 2 s))
  // rounded, give or take the other values' rounding (under one unit each).
  const uint64_t others = std::accumulate(w.begin(), w.end(), uint64_t{0});
  HCPF_CHECK(others <= kUnits) << "the tails of sigma " << sigma << " exceed one";
  w[static_cast<size_t>(kmax)] = kUnits - others;
  return w;
}

RoundedGaussianTable::RoundedGaussianTable(double sigma) {
  HCPF_CHECK(sigma > 0.0 && sigma <= 1e6) << "sigma " << sigma;
  kmax_ = RoundedGaussianKmax(sigma);
  const std::vector<uint64_t> weights = RoundedGaussianWeights(sigma, kmax_);
  const size_t m = weights.size();
  size_t n = 2;
  int bits = 1;
  while (n < m) {
    n *= 2;
    ++bits;
  }
  shift_ = 32 - bits;
  const uint64_t capacity = uint64_t{1} << shift_;  // 2^32 / n
  mask_ = static_cast<uint32_t>(capacity - 1);
  bins_.assign(n, Bin{});
  // Vose's alias construction on whole units: a bin under capacity is
  // topped up from one over it, which becomes its alias. Integer arithmetic,
  // so the table realises the weights exactly and the same way everywhere.
  std::vector<uint64_t> rest(n, 0);
  std::vector<size_t> small, large;
  for (size_t j = 0; j < n; ++j) {
    rest[j] = j < m ? weights[j] : 0;
    bins_[j].value = static_cast<int16_t>(j < m ? static_cast<int>(j) - kmax_ : 0);
    bins_[j].alias = bins_[j].value;
    (rest[j] < capacity ? small : large).push_back(j);
  }
  while (!small.empty() && !large.empty()) {
    const size_t s = small.back();
    small.pop_back();
    const size_t l = large.back();
    bins_[s].threshold = static_cast<uint32_t>(rest[s]);
    bins_[s].alias = bins_[l].value;
    rest[l] -= capacity - rest[s];
    if (rest[l] < capacity) {
      large.pop_back();
      small.push_back(l);
    }
  }
  // The weights sum to n * capacity, so what is left is exactly full.
  for (const size_t j : large) {
    HCPF_CHECK(rest[j] == capacity) << "weights do not sum to 2^32";
    bins_[j].threshold = static_cast<uint32_t>(capacity);
  }
  HCPF_CHECK(small.empty()) << "weights do not sum to 2^32";
  if (bins_.size() <= kVectorBins) {
    for (size_t j = 0; j < bins_.size(); ++j) {
      thresholds_[j] = bins_[j].threshold;
      values_[j] = static_cast<uint16_t>(bins_[j].value) |
                   (static_cast<uint32_t>(static_cast<uint16_t>(bins_[j].alias)) << 16);
    }
  }
}

namespace {

// AVX-512 (F and BW) in the CPU and the active instruction set AVX-512 (a
// test may choose a narrower one: hcpf/core/instruction_set.h).
bool VectorLookupsAllowed() {
  static const bool has = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw");
  return has && ActiveInstructionSet() == InstructionSet::kAvx512;
}

// GCC 12's AVX-512 intrinsics start some results from an "undefined"
// register, which -Wmaybe-uninitialized reports at every use (GCC bug
// 105593); nothing here reads an undefined value.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
// Sixteen 32-bit inputs at a time (eight words): the bin index u >> shift
// picks a threshold and a value-alias pair from the 64-entry arrays by two
// two-register permutes each (bit 5 of the index chooses between them), the
// low bits compared with the threshold choose value or alias.
__attribute__((target("avx512f,avx512bw"))) void SampleWordsAvx512(const uint32_t* thresholds,
                                                                   const uint32_t* values,
                                                                   int shift, uint32_t mask,
                                                                   const uint64_t* words,
                                                                   size_t count, int16_t* out) {
  const __m512i t0 = _mm512_load_si512(thresholds);
  const __m512i t1 = _mm512_load_si512(thresholds + 16);
  const __m512i t2 = _mm512_load_si512(thresholds + 32);
  const __m512i t3 = _mm512_load_si512(thresholds + 48);
  const __m512i v0 = _mm512_load_si512(values);
  const __m512i v1 = _mm512_load_si512(values + 16);
  const __m512i v2 = _mm512_load_si512(values + 32);
  const __m512i v3 = _mm512_load_si512(values + 48);
  const __m512i low_bits = _mm512_set1_epi32(static_cast<int>(mask));
  const __m512i bit5 = _mm512_set1_epi32(32);
  const __m128i shift_count = _mm_cvtsi32_si128(shift);
  for (size_t i = 0; i < count; i += 8) {
    const __m512i u = _mm512_loadu_si512(words + i);  // little-endian: low half first
    const __m512i bin = _mm512_srl_epi32(u, shift_count);
    const __mmask16 upper = _mm512_test_epi32_mask(bin, bit5);
    const __m512i threshold = _mm512_mask_blend_epi32(upper, _mm512_permutex2var_epi32(t0, bin, t1),
                                                      _mm512_permutex2var_epi32(t2, bin, t3));
    const __m512i pair = _mm512_mask_blend_epi32(upper, _mm512_permutex2var_epi32(v0, bin, v1),
                                                 _mm512_permutex2var_epi32(v2, bin, v3));
    const __mmask16 below = _mm512_cmplt_epu32_mask(_mm512_and_si512(u, low_bits), threshold);
    const __m512i value = _mm512_srai_epi32(_mm512_slli_epi32(pair, 16), 16);
    const __m512i alias = _mm512_srai_epi32(pair, 16);
    const __m512i k = _mm512_mask_blend_epi32(below, alias, value);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + 2 * i), _mm512_cvtepi32_epi16(k));
  }
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

}  // namespace

bool RoundedGaussianTable::HasVectorPath() const {
  return bins_.size() <= kVectorBins && VectorLookupsAllowed();
}

void RoundedGaussianTable::SampleWords(const uint64_t* words, size_t count, int16_t* out,
                                       bool scalar) const {
  size_t i = 0;
  if (!scalar && HasVectorPath()) {
    i = count - count % 8;
    SampleWordsAvx512(thresholds_.data(), values_.data(), shift_, mask_, words, i, out);
  }
  for (; i < count; ++i) {
    out[2 * i] = static_cast<int16_t>(Sample(static_cast<uint32_t>(words[i])));
    out[2 * i + 1] = static_cast<int16_t>(Sample(static_cast<uint32_t>(words[i] >> 32)));
  }
}

uint64_t RoundedGaussianTable::Count(int k) const {
  const uint64_t capacity = uint64_t{mask_} + 1;
  uint64_t count = 0;
  for (const Bin& b : bins_) {
    if (b.value == k) count += b.threshold;
    if (b.alias == k) count += capacity - b.threshold;
  }
  return count;
}

}  // namespace hcpf::renderer::internal
