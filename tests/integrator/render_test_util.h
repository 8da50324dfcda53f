#pragma once
// Helpers for the renderer tests: load a scene from JSON text, render it, and compare image
// means within their standard errors.

#include <string>

#include <nlohmann/json.hpp>

#include "acdf/integrator/renderer.h"
#include "acdf/integrator/scene.h"

namespace acdf::rendertest {

#ifdef ACDF_SANITIZED_BUILD
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif

struct Rendered {
  Film film{1, 1};
  RenderStats stats;
  std::size_t portals = 0;  // the environment light's, declared or found
};

// Loads `scene` (relative paths against the source tree) with `overrides` and renders it, with
// tables shared by every call (not thread-safe).
Rendered renderScene(const nlohmann::json& scene, const SceneOverrides& overrides = {});

// The mean over the film's pixels, per channel, and its standard error (pixels independent);
// summed in double.
struct ImageMean {
  Rgb mean, standardError;
};
ImageMean imageMean(const Film& film);

// A sphere of radius 1 at the origin filling the whole frame of a camera on +z, lit by a
// constant environment of `radiance`, with `material` (a scene-file material object).
nlohmann::json furnaceScene(const nlohmann::json& material, const Rgb& radiance, uint32_t size, uint32_t spp);

}  // namespace acdf::rendertest
