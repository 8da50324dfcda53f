#include "acdf/integrator/sampler.h"

namespace acdf {

namespace {

// SplitMix64's finaliser: decorrelates the seeds of consecutive sample indices.
uint64_t mix(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

}  // namespace

void IndependentSampler::startPixelSample(uint32_t x, uint32_t y, uint32_t sampleIndex) {
  rng_ = Pcg32(mix(seed_ ^ mix(sampleIndex)), uint64_t{y} * frameWidth_ + x);
}

}  // namespace acdf
