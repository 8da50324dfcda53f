#pragma once
// Helpers for the envmap tests: small maps built in memory and the project's shared real maps
// (../shared/data/envmaps, outside the repository). Temporary directories: tests/apps'
// acdf::apptest::TempDirTest.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "acdf/envmap/environment_light.h"
#include "acdf/envmap/environment_map.h"

namespace acdf::envmaptest {

// A map whose pixel (row, column) has radiance rgb(row, column).
std::shared_ptr<const EnvironmentMap> makeMap(uint32_t width, uint32_t height,
                                              const std::function<Rgb(uint32_t row, uint32_t column)>& rgb);
// Black except pixel (row, column), which is `value` in every channel.
std::shared_ptr<const EnvironmentMap> onePixelMap(uint32_t width, uint32_t height, uint32_t row, uint32_t column,
                                                  float value = 1.0f);
std::shared_ptr<const EnvironmentMap> constantMap(uint32_t width, uint32_t height, float value = 1.0f);
// Smooth, strictly positive and different in every channel and pixel.
std::shared_ptr<const EnvironmentMap> smoothMap(uint32_t width, uint32_t height);

// Every strategy but uniform-sphere sampling (which has no table).
inline constexpr EnvironmentSampling kTableStrategies[] = {
    EnvironmentSampling::Uniform, EnvironmentSampling::Alias, EnvironmentSampling::Adaptive,
    EnvironmentSampling::Compensated, EnvironmentSampling::Hierarchical};
// Both kinds of light call: a compensated light answers them from different tables.
inline constexpr LightSampleContext kLightContexts[] = {{.allowIncompletePdf = false}, {.allowIncompletePdf = true}};
inline std::string describe(const LightSampleContext& context) {
  return context.allowIncompletePdf ? "incomplete pdf allowed" : "complete pdf";
}

// Light `a` with context `contextA` draws the same samples as light `b` with `contextB` (`count`
// variate pairs from Pcg32(seed)): the same directions and pdfs, the same pdf() of each, and b's
// pdf() of its sample is the sample's. For two lights, or one light's stale and fresh contexts.
void expectSameSamples(const EnvironmentLight& a, const LightSampleContext& contextA, const EnvironmentLight& b,
                       const LightSampleContext& contextB, uint64_t seed, int count);

// Path of a shared real map ("sunset_1024x512.exr", ...), or "" when the shared data are absent.
std::string sharedEnvmap(const std::string& name);
inline constexpr const char* kSharedEnvmaps[] = {"sunset_1024x512.exr", "forest_1024x512.exr", "stage_1000x500.exr"};

}  // namespace acdf::envmaptest

// Skips the current test when the shared real maps are absent.
#define ACDF_SKIP_WITHOUT_SHARED_ENVMAPS()                                                    \
  do {                                                                                        \
    if (::acdf::envmaptest::sharedEnvmap(::acdf::envmaptest::kSharedEnvmaps[0]).empty())      \
      GTEST_SKIP() << "shared maps not found in " ACDF_SHARED_ENVMAPS " (project test data)"; \
  } while (0)
