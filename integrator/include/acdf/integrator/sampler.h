#pragma once
// Where a path's random values come from (pbrt-v4's Sampler, Nori's Sampler): for sample
// `sampleIndex` of a pixel, startPixelSample(), then values in [0, 1) one dimension at a time.
// The values of a pixel sample depend on the pixel, the sample index and the seed alone — not on
// the thread, nor on what was asked before — so an image is the same for any thread count, tile
// order and split into passes. Each thread renders with its own clone().
//
// Dimensions, in the order PathIntegrator asks for them:
//   getPixel2D()                  the position in the pixel (the camera ray);
//   per surface vertex, depth d:  startVertex(d), then
//                        get2D()   the light sample (next-event estimation; not under bsdf-only),
//                                  whose second value also picks the light path vertex the
//                                  vertex connects to (light_paths.h),
//                                  or getCandidates() under product direct lighting: the values of
//                                  its candidates (their number is an option),
//                        get2D()   the BSDF sample,
//                        get1D()   Russian roulette (from RenderSettings::rouletteDepth on).
// With RenderSettings::branches > 1 the path branches at vertex 0 after its light sample:
// startBranch(b, branches) for b = 0, 1, …, each followed by the BSDF sample (and roulette) of
// vertex 0 and the whole branch.
// Which values a vertex asks for depends on the MIS mode, the direct lighting and the depth;
// startVertex() lets a low-discrepancy sampler give every vertex the same fixed block of
// dimensions whatever the vertices before it asked for.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>

#include "acdf/sampling/rng.h"
#include "acdf/sampling/sobol.h"

namespace acdf {

// The values of the candidates product sampling draws at one call site: candidate i's 2D point,
// and one value for the resampling choice. Either every value comes from a PCG32 stream, or they
// are stratified over the pixel's samples: in pixel sample s, candidate i of `count` takes point
// count·s + i of a padded Sobol component (indices modulo 2^32), so the candidates of a pixel's
// samples together stratify it (and each sample's own when `count` is a power of 2), and the
// resampling value is point s of the component + 2^31, below 2^-24 filled in from the stream.
class CandidateValues {
 public:
  // Every value from `random`.
  explicit CandidateValues(Pcg32 random) : random_(random) {}
  // Stratified, with padded Sobol components seeded by `seed`.
  CandidateValues(Pcg32 random, uint64_t seed, uint32_t sampleIndex, uint32_t count, uint32_t component)
      : random_(random), sobol_(SobolComponent{seed, sampleIndex, count, component}) {}

  // Candidate i's point in [0, 1)²; called for i = 0, 1, … in order.
  std::array<float, 2> point(uint32_t i);
  // Uniform in [0, 1), with 53 bits.
  double resamplingValue();

 private:
  struct SobolComponent {
    uint64_t seed;
    uint32_t sampleIndex, count, component;
  };
  Pcg32 random_;
  std::optional<SobolComponent> sobol_;
};

class Sampler {
 public:
  virtual ~Sampler() = default;

  // Starts sample `sampleIndex` of full-frame pixel (x, y).
  virtual void startPixelSample(uint32_t x, uint32_t y, uint32_t sampleIndex) = 0;
  // Starts the values of the surface vertex at `depth` (0: where the camera ray ends); at most
  // kValuesPerVertex calls (get1D, get2D) follow before the next vertex.
  virtual void startVertex(uint32_t depth) = 0;
  virtual float get1D() = 0;
  virtual std::array<float, 2> get2D() = 0;
  // The values of `count` candidates (product sampling), from the pixel, the sample index, the
  // seed and the call's place in the order above, like every other value. Counts as one call of
  // the vertex.
  virtual CandidateValues getCandidates(uint32_t count) = 0;
  // The position in the pixel, [0, 1)².
  virtual std::array<float, 2> getPixel2D() = 0;
  // Starts branch `branch` of `branches` (called for 0, 1, … in order) of the path at the vertex
  // whose light sample was just taken: from that vertex's next call on, the values are branch
  // `branch`'s, as different from the other branches' as two pixel samples'.
  virtual void startBranch(uint32_t branch, uint32_t branches) = 0;

  // A sampler of the same kind and seed, with its own state (one per thread or tile).
  virtual std::unique_ptr<Sampler> clone() const = 0;

  // The get1D/get2D/getCandidates calls a vertex may make: light, BSDF, roulette.
  static constexpr uint32_t kValuesPerVertex = 3;
};

// Independent uniform values: pixel sample (x, y, s) reads PCG32 stream y · frameWidth + x from
// the seed SplitMix(seed ⊕ SplitMix(s)), every dimension the next value of that stream (vertices
// need no allotment: every value is independent of every other).
class IndependentSampler final : public Sampler {
 public:
  // `frameWidth`: the full frame's width in pixels, which numbers the streams.
  IndependentSampler(uint64_t seed, uint32_t frameWidth) : seed_(seed), frameWidth_(frameWidth) {}

  void startPixelSample(uint32_t x, uint32_t y, uint32_t sampleIndex) override;
  void startVertex(uint32_t) override {}
  float get1D() override { return rng_.nextFloat(); }
  std::array<float, 2> get2D() override { return {rng_.nextFloat(), rng_.nextFloat()}; }
  // From a stream seeded by the next two values of the pixel sample's.
  CandidateValues getCandidates(uint32_t count) override;
  std::array<float, 2> getPixel2D() override { return get2D(); }
  void startBranch(uint32_t, uint32_t) override {}
  std::unique_ptr<Sampler> clone() const override { return std::make_unique<IndependentSampler>(*this); }

 private:
  uint64_t seed_;
  uint32_t frameWidth_;
  Pcg32 rng_;
};

// Owen-scrambled Sobol values: the padded sequence of acdf/sampling/sobol.h (pbrt-v4's
// PaddedSobolSampler, Burley 2020), indexed by the pixel's sample number, seeded per pixel by
// SplitMix(SplitMix(seed) ⊕ (y · frameWidth + x)). Each call site has its own component of the
// sequence, a fixed allotment per bounce:
//   component 0                   the pixel position,
//   components 1 + 3d … 3 + 3d    vertex d's calls in order (light 2D, BSDF 2D, roulette 1D
//                                 under power/balance MIS; BSDF 2D, roulette 1D under bsdf-only),
// so vertex d's light sample always reads component 1 + 3d, however the path got there. Every
// component is a (0,2)-sequence over the pixel's samples (the first 2^m samples a (0,m,2)-net,
// for every m); components are independent of each other, pixels independent of each other.
// Branch b of B (startBranch) reads point B·s + b of the components from its first call on
// (indices modulo 2^32), so a pixel's branches together are one stratified sequence, as the
// pixel's samples are.
// getCandidates(M) takes a component's place too, for stratified CandidateValues (their stream
// seeded by a hash of the pixel's seed, the sample index and the component).
class SobolSampler final : public Sampler {
 public:
  SobolSampler(uint64_t seed, uint32_t frameWidth) : seed_(seed), frameWidth_(frameWidth) {}

  void startPixelSample(uint32_t x, uint32_t y, uint32_t sampleIndex) override;
  void startVertex(uint32_t depth) override { component_ = 1 + kValuesPerVertex * depth; }
  float get1D() override;
  std::array<float, 2> get2D() override;
  CandidateValues getCandidates(uint32_t count) override;
  std::array<float, 2> getPixel2D() override;
  void startBranch(uint32_t branch, uint32_t branches) override;
  std::unique_ptr<Sampler> clone() const override { return std::make_unique<SobolSampler>(*this); }

 private:
  uint64_t seed_;
  uint32_t frameWidth_;
  uint64_t pixelSeed_ = 0;
  uint32_t pixelSampleIndex_ = 0;
  uint32_t sampleIndex_ = 0;         // the pixel sample's, or its branch's
  PaddedSobolIndex paddedIndex_{0};  // sampleIndex_, prepared once for all its components
  uint32_t component_ = 0;
  uint32_t branchComponent_ = 0;     // where the branches' values start
};

enum class SamplerKind { Independent, Sobol };
// "independent", "sobol"; parse throws std::invalid_argument.
std::string_view toString(SamplerKind kind);
SamplerKind parseSamplerKind(std::string_view name);
std::unique_ptr<Sampler> makeSampler(SamplerKind kind, uint64_t seed, uint32_t frameWidth);

}  // namespace acdf
