#include "hcpf/core/rng.h"

#include <string>

#include "hcpf/core/check.h"

namespace hcpf {

uint64_t Mix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

uint64_t HashName(std::string_view name) {
  uint64_t h = 0xCBF29CE484222325ULL;
  for (const unsigned char c : name) {
    h ^= c;
    h *= 0x100000001B3ULL;
  }
  return h;
}

void Rng::Reseed(uint64_t identity) {
  identity_ = identity;
  uint64_t x = identity;
  for (auto& word : s_) {
    x = Mix64(x);
    word = x;
  }
  // xoshiro must not start from the all-zero state; Mix64 of four successive
  // values cannot all be zero, but keep the guard explicit.
  if ((s_[0] | s_[1] | s_[2] | s_[3]) == 0) s_[0] = 1;
  has_spare_ = false;
}

Rng Rng::Fork(std::string_view name) const {
  Rng child;
  child.Reseed(Mix64(identity_ ^ Mix64(HashName(name))));
  return child;
}

Rng Rng::Fork(std::string_view name, int64_t index) const {
  std::string full(name);
  full += '/';
  full += std::to_string(index);
  return Fork(full);
}

uint64_t Rng::UniformInt(uint64_t n) {
  HCPF_CHECK(n > 0);
  // Lemire (2019), "Fast random integer generation in an interval".
  __extension__ using U128 = unsigned __int128;
  U128 m = static_cast<U128>(NextU64()) * n;
  uint64_t low = static_cast<uint64_t>(m);
  if (low < n) {
    const uint64_t threshold = (0 - n) % n;
    while (low < threshold) {
      m = static_cast<U128>(NextU64()) * n;
      low = static_cast<uint64_t>(m);
    }
  }
  return static_cast<uint64_t>(m >> 64);
}

int64_t Rng::Poisson(double lambda) {
  HCPF_CHECK(lambda >= 0.0 && std::isfinite(lambda)) << "lambda=" << lambda;
  // A Poisson(λ) is the sum of Poisson(λ_i) with Σλ_i = λ; chunks of mean <= 16
  // keep exp(-λ_i) far from underflow and the product loop short.
  int64_t total = 0;
  double remaining = lambda;
  while (remaining > 0.0) {
    const double chunk = remaining > 16.0 ? 16.0 : remaining;
    remaining -= chunk;
    const double limit = std::exp(-chunk);
    double product = Uniform();
    while (product > limit) {
      ++total;
      product *= Uniform();
    }
  }
  return total;
}

}  // namespace hcpf
