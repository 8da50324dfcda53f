#pragma once
// Where a path's random values come from (pbrt-v4's Sampler, Nori's Sampler): for sample
// `sampleIndex` of a pixel, startPixelSample(), then values in [0, 1) one dimension at a time.
// The values of a pixel sample depend on the pixel, the sample index and the seed alone — not on
// the thread, nor on what was asked before — so an image is the same for any thread count, tile
// order and split into passes. Each thread renders with its own clone().
//
// Dimensions, in the order PathIntegrator asks for them:
//   getPixel2D()               the position in the pixel (the camera ray);
//   per surface vertex:  get2D()   the light sample (next-event estimation; not under bsdf-only),
//                        get2D()   the BSDF sample,
//                        get1D()   Russian roulette (from RenderSettings::rouletteDepth on).
// Which dimensions a vertex gets depends on the path before it (no light sample under bsdf-only,
// roulette from rouletteDepth on): harmless for independent values, while a low-discrepancy
// sampler needs a fixed allotment per bounce.

#include <array>
#include <cstdint>
#include <memory>

#include "acdf/sampling/rng.h"

namespace acdf {

class Sampler {
 public:
  virtual ~Sampler() = default;

  // Starts sample `sampleIndex` of full-frame pixel (x, y).
  virtual void startPixelSample(uint32_t x, uint32_t y, uint32_t sampleIndex) = 0;
  virtual float get1D() = 0;
  virtual std::array<float, 2> get2D() = 0;
  // The position in the pixel, [0, 1)².
  virtual std::array<float, 2> getPixel2D() = 0;

  // A sampler of the same kind and seed, with its own state (one per thread or tile).
  virtual std::unique_ptr<Sampler> clone() const = 0;
};

// Independent uniform values: pixel sample (x, y, s) reads PCG32 stream y · frameWidth + x from
// the seed SplitMix(seed ⊕ SplitMix(s)), every dimension the next value of that stream.
class IndependentSampler final : public Sampler {
 public:
  // `frameWidth`: the full frame's width in pixels, which numbers the streams.
  IndependentSampler(uint64_t seed, uint32_t frameWidth) : seed_(seed), frameWidth_(frameWidth) {}

  void startPixelSample(uint32_t x, uint32_t y, uint32_t sampleIndex) override;
  float get1D() override { return rng_.nextFloat(); }
  std::array<float, 2> get2D() override { return {rng_.nextFloat(), rng_.nextFloat()}; }
  std::array<float, 2> getPixel2D() override { return get2D(); }
  std::unique_ptr<Sampler> clone() const override { return std::make_unique<IndependentSampler>(*this); }

 private:
  uint64_t seed_;
  uint32_t frameWidth_;
  Pcg32 rng_;
};

}  // namespace acdf
