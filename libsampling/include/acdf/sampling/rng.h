#pragma once
// PCG32 (O'Neill 2014): a small, fast, seedable generator with independent streams, so tests,
// benchmarks and renders are reproducible for a fixed seed.

#include <cstdint>

namespace acdf {

// SplitMix64's finaliser: decorrelates seeds that differ in a few bits (consecutive sample
// indices, pixels, paths) before they seed a generator.
constexpr uint64_t mixSeed(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

class Pcg32 {
 public:
  explicit Pcg32(uint64_t seed = 0x853c49e6748fea9bULL, uint64_t stream = 0xda3e39cb94b95bdbULL) {
    state_ = 0;
    increment_ = (stream << 1u) | 1u;
    nextUint();
    state_ += seed;
    nextUint();
  }

  uint32_t nextUint() {
    uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + increment_;
    auto xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    auto rot = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
  }

  // Uniform in [0, 1) on the 2^-24 lattice: 0 and kOneMinusEpsilon are both reachable.
  float nextFloat() { return static_cast<float>(nextUint() >> 8) * 0x1p-24f; }
  double nextDouble() { return static_cast<double>(((uint64_t)nextUint() << 21) ^ nextUint()) * 0x1p-53; }

 private:
  uint64_t state_;
  uint64_t increment_;
};

}  // namespace acdf
