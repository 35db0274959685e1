#include "rounded_gaussian.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "hcpf/core/check.h"

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
