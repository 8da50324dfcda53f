// Irradiance from an environment map, E(n) = ∫ L(ω) max(0, n·ω) dω, estimated in your own Monte
// Carlo loop twice with the same sample count: with acdf's adaptive light table (directions drawn
// ∝ the map's luminance), and with cosine-weighted hemisphere sampling (∝ max(0, n·ω)).
//
//   sample_environment MAP.exr [SAMPLES]
//
// The map is lat-long with +y up (OpenEXR's LatLong layout); n is the up direction.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <numbers>
#include <random>

#include "acdf/envmap/environment_light.h"
#include "acdf/sampling/frame.h"
#include "running_estimate.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s MAP.exr [SAMPLES]\n", argv[0]);
    return 2;
  }
  const long samples = argc > 2 ? std::atol(argv[2]) : 100000;
  try {
    const auto map = std::make_shared<const acdf::EnvironmentMap>(acdf::EnvironmentMap::load(argv[1]));
    const acdf::EnvironmentLight light(map);    // the adaptive table, built here
    const acdf::LightSampleContext lightAlone;  // no BSDF samples to combine with: a complete pdf
    const acdf::Frame up(acdf::Vec3d{0, 1, 0});

    std::mt19937 rng(1);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    RunningEstimate withLight, withCosine;
    for (long i = 0; i < samples; ++i) {
      const acdf::LightSample s = light.sample(lightAlone, uniform(rng), uniform(rng));
      const double cosine = acdf::dot(up.normal(), s.direction);
      withLight.add(cosine > 0 ? s.radiance.luminance() * cosine / s.pdf : 0.0);

      // pdf = cosθ / π, so L cosθ / pdf = π L.
      const acdf::Vec3d w = up.toWorld(acdf::sampleCosineHemisphere(uniform(rng), uniform(rng)));
      withCosine.add(std::numbers::pi * light.eval(w).luminance());
    }
    std::printf("%s: %u x %u, adaptive table of %zu bytes\n", argv[1], map->width(), map->height(), light.tableBytes());
    std::printf("irradiance at +y, %ld samples each:\n", samples);
    std::printf("  light table       %.6g +- %.2g\n", withLight.mean(), withLight.standardError());
    std::printf("  cosine hemisphere %.6g +- %.2g\n", withCosine.mean(), withCosine.standardError());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  return 0;
}
