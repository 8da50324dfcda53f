#include "acdf/sampling/sobol.h"

#include <bit>
#include <stdexcept>
#include <string>

#include "sobol_direction_numbers.h"

namespace acdf {
namespace {

using sobol_detail::JoeKuoEntry;
using sobol_detail::kJoeKuo;
using sobol_detail::kMaxDegree;

using GeneratorMatrix = std::array<uint32_t, 32>;  // column k: the point of index 2^k, bit-reversed

// Polynomials over GF(2) as bit masks (bit i: the coefficient of x^i). The full polynomial of an
// entry: x^s + a's coefficients + 1.
constexpr uint32_t polynomial(const JoeKuoEntry& e) { return (1u << e.s) | (e.a << 1) | 1u; }

// A polynomial of degree s is primitive iff x has multiplicative order 2^s − 1 modulo it
// (which also makes it irreducible): x^(2^s−1) = 1 and no smaller power is 1.
constexpr bool isPrimitive(uint32_t p, uint32_t s) {
  const uint32_t order = (1u << s) - 1;
  uint32_t power = 1;  // x^n mod p
  for (uint32_t n = 1; n <= order; ++n) {
    power <<= 1;
    if (power & (1u << s)) power ^= p;
    if (power == 1) return n == order;
  }
  return false;
}

// The table's own consistency: consecutive dimensions, distinct primitive polynomials in Joe &
// Kuo's order (by degree, then coefficients), odd m_k < 2^k. A typo in s or a fails here; the
// tests compare the resulting points with the published sequence.
constexpr bool directionNumbersAreValid() {
  if (std::size(kJoeKuo) != kSobolDimensions - 1) return false;
  uint32_t previous = 0;
  for (uint32_t j = 0; j < std::size(kJoeKuo); ++j) {
    const JoeKuoEntry& e = kJoeKuo[j];
    if (e.d != j + 2 || e.s < 1 || e.s > kMaxDegree || e.a >= (1u << (e.s - 1))) return false;
    if (polynomial(e) <= previous || !isPrimitive(polynomial(e), e.s)) return false;
    previous = polynomial(e);
    for (uint32_t k = 0; k < kMaxDegree; ++k) {
      const uint32_t m = e.m[k];
      if (k < e.s ? (m % 2 == 0 || m >= (2u << k)) : m != 0) return false;
    }
  }
  return true;
}
static_assert(directionNumbersAreValid(), "src/sobol_direction_numbers.h is inconsistent");

constexpr uint32_t reverseBits(uint32_t v) {
  v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
  v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
  v = ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
  return (v >> 24) | ((v >> 8) & 0xff00u) | ((v << 8) & 0xff0000u) | (v << 24);  // byte swap
}

// The computations below work on bit-reversed fractions, where digit k + 1 (from the most
// significant) is bit k: the scrambling's carries then run in the right direction, and the
// reversal after the generator matrix cancels the one before the scrambling.

// Column k of a generator matrix is the direction number v_(k+1) = m_(k+1) / 2^(k+1). The first
// s come from the table; beyond them (Bratley & Fox 1988)
//   v_k = a_1 v_(k−1) ⊕ … ⊕ a_(s−1) v_(k−s+1) ⊕ v_(k−s) ⊕ v_(k−s) / 2^s,
// a_1 being the coefficient of x^(s−1). Column k has digit k + 1 set and none after it (m odd,
// m < 2^(k+1)): the matrix is upper triangular with a unit diagonal, so every dimension alone is
// a (0,1)-sequence.
constexpr std::array<GeneratorMatrix, kSobolDimensions> makeReversedGeneratorMatrices() {
  std::array<GeneratorMatrix, kSobolDimensions> matrices{};
  for (uint32_t k = 0; k < 32; ++k) matrices[0][k] = 1u << k;  // van der Corput
  for (uint32_t j = 1; j < kSobolDimensions; ++j) {
    const JoeKuoEntry& e = kJoeKuo[j - 1];
    std::array<uint32_t, 32> v{};  // in the usual order, as the recurrence is written
    for (uint32_t k = 0; k < e.s; ++k) v[k] = e.m[k] << (31 - k);
    for (uint32_t k = e.s; k < 32; ++k) {
      uint32_t x = v[k - e.s] ^ (v[k - e.s] >> e.s);
      for (uint32_t i = 1; i < e.s; ++i)
        if ((e.a >> (e.s - 1 - i)) & 1u) x ^= v[k - i];
      v[k] = x;
    }
    for (uint32_t k = 0; k < 32; ++k) matrices[j][k] = reverseBits(v[k]);
  }
  return matrices;
}

constexpr std::array<GeneratorMatrix, kSobolDimensions> kReversedMatrices = makeReversedGeneratorMatrices();

// Σ_k bit_k(index) · column_k over GF(2), one xor per set bit of the index.
constexpr uint32_t multiply(const GeneratorMatrix& matrix, uint32_t index) {
  uint32_t v = 0;
  for (; index != 0; index &= index - 1) v ^= matrix[std::countr_zero(index)];
  return v;
}

// Dimension 1 (polynomial x + 1) has the Pascal matrix mod 2: digit j + 1 of point i is the
// parity of Σ_k binom(k, j) i_k, and binom(k, j) is odd iff the bits of j are a subset of those
// of k (Lucas). So reversed bit j = ⊕ of i_k over the supersets k of j: five bit-parallel
// superset-sum steps instead of a loop over the index bits.
constexpr uint32_t reversedDimension1(uint32_t index) {
  index ^= (index >> 1) & 0x55555555u;
  index ^= (index >> 2) & 0x33333333u;
  index ^= (index >> 4) & 0x0f0f0f0fu;
  index ^= (index >> 8) & 0x00ff00ffu;
  index ^= (index >> 16) & 0x0000ffffu;
  return index;
}

// The matrix is linear, so agreeing on every column means agreeing everywhere.
constexpr bool dimension1MatchesItsMatrix() {
  for (uint32_t k = 0; k < 32; ++k)
    if (reversedDimension1(1u << k) != kReversedMatrices[1][k]) return false;
  return true;
}
static_assert(dimension1MatchesItsMatrix());

// Laine & Karras' permutation of a reversed fraction. An even factor's product has no term in
// bit i from bit i itself, and carries run upwards, so each step is a bijection that changes bit
// i by a function of the seed and the bits below it (the digits before it): together a nested
// uniform scramble. Constants: Vegdahl 2021.
constexpr uint32_t nestedPermutation(uint32_t r, uint32_t seed) {
  r ^= r * 0x3d20adeau;
  r += seed;
  r *= (seed >> 16) | 1u;
  r ^= r * 0x05526c56u;
  r ^= r * 0x53a22864u;
  return r;
}

// Output n of SplitMix64 (Steele, Lea & Flood 2014) started at `seed`: consecutive n give
// uncorrelated 64-bit values, so every (seed, dimension) gets its own scrambling seeds.
constexpr uint64_t splitMix64(uint64_t seed, uint64_t n) {
  uint64_t z = seed + (n + 1) * 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

constexpr uint32_t low32(uint64_t h) { return static_cast<uint32_t>(h); }
constexpr uint32_t high32(uint64_t h) { return static_cast<uint32_t>(h >> 32); }

// A reversed fraction's leading 24 digits as a float.
constexpr float reversedToUnitFloat(uint32_t r) { return bitsToUnitFloat(reverseBits(r)); }

[[noreturn]] void throwBadDimension(uint32_t dimension) {
  throw std::out_of_range("Sobol dimension " + std::to_string(dimension) + " is not below " +
                          std::to_string(kSobolDimensions));
}

inline void checkDimension(uint32_t dimension) {
  if (dimension >= kSobolDimensions) [[unlikely]]
    throwBadDimension(dimension);
}

}  // namespace

uint32_t sobolBits(uint32_t index, uint32_t dimension) {
  checkDimension(dimension);
  return reverseBits(multiply(kReversedMatrices[dimension], index));
}

uint32_t owenScramble(uint32_t bits, uint32_t seed) { return reverseBits(nestedPermutation(reverseBits(bits), seed)); }

float sobolSample(uint32_t index, uint32_t dimension, uint64_t seed) {
  checkDimension(dimension);
  const uint32_t scramble = high32(splitMix64(seed, dimension));
  return reversedToUnitFloat(nestedPermutation(multiply(kReversedMatrices[dimension], index), scramble));
}

// Seeds of component `dimension`: the index shuffle and the first coordinate's scramble from
// output 2·dimension of the seed's SplitMix64 stream, the second coordinate's from the next.
// Shuffling by Owen-scrambling the index maps every aligned block of 2^m indices onto an aligned
// block of 2^m Sobol points, which in dimensions 0 and 1 is a (0,m,2)-net. Dimension 0 reversed
// is the index itself.
PaddedSobolIndex::PaddedSobolIndex(uint32_t index) : reversed(reverseBits(index)) {}

float paddedSobol1D(PaddedSobolIndex index, uint32_t dimension, uint64_t seed) {
  const uint64_t h = splitMix64(seed, uint64_t{2} * dimension);
  const uint32_t shuffled = reverseBits(nestedPermutation(index.reversed, low32(h)));  // owenScramble(index)
  return reversedToUnitFloat(nestedPermutation(shuffled, high32(h)));
}

float paddedSobol1D(uint32_t index, uint32_t dimension, uint64_t seed) {
  return paddedSobol1D(PaddedSobolIndex(index), dimension, seed);
}

std::array<float, 2> paddedSobol2D(PaddedSobolIndex index, uint32_t dimension, uint64_t seed) {
  const uint64_t h = splitMix64(seed, uint64_t{2} * dimension);
  const uint32_t yScramble = high32(splitMix64(seed, uint64_t{2} * dimension + 1));
  const uint32_t shuffled = reverseBits(nestedPermutation(index.reversed, low32(h)));  // owenScramble(index)
  return {reversedToUnitFloat(nestedPermutation(shuffled, high32(h))),
          reversedToUnitFloat(nestedPermutation(reversedDimension1(shuffled), yScramble))};
}

std::array<float, 2> paddedSobol2D(uint32_t index, uint32_t dimension, uint64_t seed) {
  return paddedSobol2D(PaddedSobolIndex(index), dimension, seed);
}

}  // namespace acdf
