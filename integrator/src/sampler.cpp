#include "acdf/integrator/sampler.h"

#include <stdexcept>
#include <string>

#include "acdf/sampling/enum_names.h"
#include "acdf/sampling/sobol.h"

namespace acdf {

void IndependentSampler::startPixelSample(uint32_t x, uint32_t y, uint32_t sampleIndex) {
  rng_ = Pcg32(mixSeed(seed_ ^ mixSeed(sampleIndex)), uint64_t{y} * frameWidth_ + x);
}

std::array<float, 2> CandidateValues::point(uint32_t i) {
  if (sobol_) return paddedSobol2D(sobol_->sampleIndex * sobol_->count + i, sobol_->component, sobol_->seed);
  return {random_.nextFloat(), random_.nextFloat()};
}

double CandidateValues::resamplingValue() {
  if (!sobol_) return random_.nextDouble();
  const float stratified = paddedSobol1D(sobol_->sampleIndex, sobol_->component + 0x80000000u, sobol_->seed);
  return stratified + random_.nextDouble() * 0x1p-24;  // a float on the 2^-24 lattice, then its cell
}

CandidateValues IndependentSampler::getCandidates(uint32_t) {
  const uint64_t seed = uint64_t{rng_.nextUint()} << 32 | rng_.nextUint();
  return CandidateValues(Pcg32(mixSeed(seed), seed));
}

void SobolSampler::startPixelSample(uint32_t x, uint32_t y, uint32_t sampleIndex) {
  pixelSeed_ = mixSeed(mixSeed(seed_) ^ (uint64_t{y} * frameWidth_ + x));
  pixelSampleIndex_ = sampleIndex;
  sampleIndex_ = sampleIndex;
  paddedIndex_ = PaddedSobolIndex(sampleIndex);
  component_ = 0;
}

void SobolSampler::startBranch(uint32_t branch, uint32_t branches) {
  if (branch == 0) branchComponent_ = component_;
  component_ = branchComponent_;
  sampleIndex_ = pixelSampleIndex_ * branches + branch;
  paddedIndex_ = PaddedSobolIndex(sampleIndex_);
}

float SobolSampler::get1D() { return paddedSobol1D(paddedIndex_, component_++, pixelSeed_); }

std::array<float, 2> SobolSampler::get2D() { return paddedSobol2D(paddedIndex_, component_++, pixelSeed_); }

CandidateValues SobolSampler::getCandidates(uint32_t count) {
  const uint32_t component = component_++;
  return CandidateValues(Pcg32(mixSeed(pixelSeed_ ^ mixSeed(uint64_t{sampleIndex_} << 32 | component)), pixelSeed_),
                         pixelSeed_, sampleIndex_, count, component);
}

std::array<float, 2> SobolSampler::getPixel2D() { return paddedSobol2D(paddedIndex_, 0, pixelSeed_); }

namespace {
constexpr EnumName<SamplerKind> kSamplerNames[] = {{SamplerKind::Independent, "independent"},
                                                   {SamplerKind::Sobol, "sobol"}};
}  // namespace

std::string_view toString(SamplerKind kind) { return nameOf(kSamplerNames, kind); }

SamplerKind parseSamplerKind(std::string_view name) { return valueNamed(kSamplerNames, name, "sampler"); }

std::unique_ptr<Sampler> makeSampler(SamplerKind kind, uint64_t seed, uint32_t frameWidth) {
  if (kind == SamplerKind::Sobol) return std::make_unique<SobolSampler>(seed, frameWidth);
  return std::make_unique<IndependentSampler>(seed, frameWidth);
}

}  // namespace acdf
