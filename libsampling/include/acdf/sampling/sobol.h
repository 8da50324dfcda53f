#pragma once
// Owen-scrambled Sobol points in base 2 (Sobol 1967, Owen 1995, hash-based scrambling as in
// Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4)), for a renderer's sample source
// to wrap. Every function is a pure function of (index, dimension, seed): pixels, samples and
// dimensions can be evaluated in any order on any thread, and the same arguments give the same
// value on every run.
//
// Values are floats in [0, 1) on the 2^-24 lattice, like Pcg32::nextFloat: 0 and
// kOneMinusEpsilon are both reachable, 1 never is. Among the first 2^24 indices every lattice
// value occurs exactly once, in every dimension and for every seed.
//
// Two sequences:
//  - sobolSample(index, dimension, seed): dimension `dimension` (< kSobolDimensions) of point
//    `index` of the Sobol sequence, each dimension Owen-scrambled by its own seed derived from
//    `seed`. The first 2^m points of dimensions 0 and 1 are a (0,m,2)-net; other pairs are
//    (t,m,2)-nets with the small t Joe & Kuo's direction numbers were chosen for; all dimensions
//    are stratified jointly.
//  - paddedSobol1D/2D(index, dimension, seed): the shuffled, padded sequence (Burley 2020, §4;
//    pbrt-v4's PaddedSobolSampler). Each `dimension` of the padded sequence is a 1D or 2D
//    component of its own: the Sobol (0,2)-sequence of dimensions 0 and 1, Owen-scrambled, at a
//    shuffled index (the index itself Owen-scrambled), with seeds hashed from (seed, dimension).
//    Every component is stratified on its own: the indices of any aligned block
//    [j·2^m, (j+1)·2^m), the first 2^m in particular, give a (0,m,2)-net of a 2D component, so
//    a pixel's first 2^m samples are a net at every m. Any number of components is allowed;
//    different components are independent, not jointly stratified. (pbrt-v4 shuffles with a
//    random permutation of the pixel's sample count instead, which only makes the whole count,
//    not its power-of-two prefixes, a net.)
//
// For path tracing, use the padded sequence: one `dimension` per call site (camera 2D, then per
// bounce light 2D, BSDF 2D, roulette 1D, ...), a per-pixel seed (a hash of the pixel and the
// render's seed) and the pixel's sample number as the index. Each 2D decision then sees a
// (0,2)-net of the pixel's samples at every power-of-two count, however deep the path, which is
// what importance-sampled integrands profit from; the global sequence's joint stratification over
// many dimensions buys little for them and runs out after kSobolDimensions.
//
// Seeds are hashed before use (SplitMix64), so pixel numbers can serve directly; fold the render's
// seed in with a hash too, not by adding it. Index range: a sequence has 2^32 points (32-bit
// generator matrices).

#include <array>
#include <cstdint>

namespace acdf {

// Dimensions of the Sobol sequence of sobolBits() and sobolSample(): 0 … kSobolDimensions − 1.
// Dimension 0 is the van der Corput sequence, dimension d ≥ 1 uses line d + 1 of Joe & Kuo's
// new-joe-kuo-6.21201 (their dimensions are 1-based; see src/sobol_direction_numbers.h).
inline constexpr uint32_t kSobolDimensions = 64;

// Dimension `dimension` of point `index` of the unscrambled Sobol sequence, as a 32-bit binary
// fraction (the point is bits / 2^32). Points are in natural order: bit k of the index selects
// column k of the dimension's generator matrix. (Joe & Kuo's generator visits the same points in
// Gray-code order: their n-th point is sobolBits(n ^ (n >> 1), d).) Throws std::out_of_range for
// dimension >= kSobolDimensions.
uint32_t sobolBits(uint32_t index, uint32_t dimension);

// Nested uniform (Owen) scrambling of a 32-bit binary fraction: each digit is flipped or kept by
// a hash of the seed and of the digits before it (more significant), so two values that share
// their first k digits still share (other) first k digits afterwards and the scrambling maps
// every elementary interval [j/2^k, (j+1)/2^k) onto one. A bijection of the 32-bit values for
// every seed. The hash is Laine & Karras' construction (bit-reversed multiply/xor steps, each of
// which lets a bit depend only on the bits below it) with Vegdahl's constants (2021, "Building a
// better LK hash", also used by pbrt-v4 and Cycles); the seed should be well mixed.
uint32_t owenScramble(uint32_t bits, uint32_t seed);

// A 32-bit binary fraction as a float in [0, 1): its 24 leading digits (truncated), exactly
// representable, so the largest result is kOneMinusEpsilon.
constexpr float bitsToUnitFloat(uint32_t bits) { return static_cast<float>(bits >> 8) * 0x1p-24f; }

// Dimension `dimension` (< kSobolDimensions, else std::out_of_range) of point `index` of the
// Sobol sequence Owen-scrambled per dimension: owenScramble(sobolBits(index, dimension), s) with
// s hashed from (seed, dimension).
float sobolSample(uint32_t index, uint32_t dimension, uint64_t seed);

// Point `index` of the padded sequence with its bits reversed, as every component's shuffle
// starts: a sampler that draws many components of one point reverses the index once.
// paddedSobol*(PaddedSobolIndex(i), d, s) equals paddedSobol*(i, d, s).
struct PaddedSobolIndex {
  explicit PaddedSobolIndex(uint32_t index);
  uint32_t reversed;
};

// Component `dimension` (any value) of point `index` of the padded sequence, 2D: Sobol
// dimensions 0 and 1 at the shuffled index, each scrambled by its own seed; all three seeds are
// hashed from (seed, dimension).
std::array<float, 2> paddedSobol2D(uint32_t index, uint32_t dimension, uint64_t seed);
std::array<float, 2> paddedSobol2D(PaddedSobolIndex index, uint32_t dimension, uint64_t seed);

// The 1D component `dimension` of the padded sequence: the first coordinate of
// paddedSobol2D(index, dimension, seed), at half the cost. 1D and 2D components share one
// numbering; give each call site its own `dimension`.
float paddedSobol1D(uint32_t index, uint32_t dimension, uint64_t seed);
float paddedSobol1D(PaddedSobolIndex index, uint32_t dimension, uint64_t seed);

}  // namespace acdf
