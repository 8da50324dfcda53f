#pragma once
// Rendering a scene into a film: tiles of the crop window in parallel (oneTBB), one path per
// sample. Sample s of full-frame pixel p takes its random values from the scene's Sampler
// (sampler.h: independent or Sobol) started on (p, s) with the scene seed, one clone per tile, so the image is the same
// for any thread count, tile order, and split into passes: --spp N and a time-limited render that
// reached N samples produce the same pixels.

#include <cstdint>
#include <functional>
#include <optional>

#include "acdf/integrator/film.h"
#include "acdf/integrator/scene.h"

namespace acdf {

struct RenderOptions {
  // Render progressive passes of one sample per pixel until this many seconds have passed
  // (at least one pass); otherwise scene.settings.spp samples per pixel.
  std::optional<double> seconds;
  // Called with the fraction done (of the samples, or of the time) after each tile, by the
  // worker thread that finished it, one call at a time; may be empty.
  std::function<void(double fraction)> progress;
  uint32_t tileSize = 16;
};

struct RenderStats {
  uint32_t spp = 0;    // samples per pixel rendered
  uint64_t paths = 0;  // camera paths traced
  uint64_t rays = 0;   // rays cast (closest hit and shadow)
  double seconds = 0;  // wall-clock render time
};

// The film has the crop window's size.
Film makeFilm(const Scene& scene);
RenderStats render(const Scene& scene, Film& film, const RenderOptions& options = {});

}  // namespace acdf
