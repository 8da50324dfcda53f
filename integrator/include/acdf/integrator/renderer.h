#pragma once
// Rendering a scene into a film: tiles of the crop window in parallel (oneTBB), one path per
// sample. Sample s of full-frame pixel p takes its random values from the scene's Sampler
// (sampler.h: independent or Sobol) started on (p, s) with the scene seed, one clone per tile, so the image is the same
// for any thread count, tile order, and split into passes: --spp N and a time-limited render that
// reached N samples produce the same pixels (without guiding, whose passes the budget decides).
//
// Guiding (RenderSettings::guiding, path_integrator.h). The samples go in passes: the first, of
// one sample per pixel, unguided; every pass's paths record what they learn, and the next pass is
// guided by the fields built from those records alone (guiding_field.h: the light's, and under
// `paths` the paths' too). Passes double (1, 2, 4, …)
// while the samples left after the next one are at least as many as it has and the last fields
// learned from fewer than about a million records; the last pass takes the rest with the last
// fields and records nothing. Every sample counts in the image, each an unbiased estimate. Under
// `auto` the second pass (2 samples per pixel) guides the light of the pixels with x + y even and not the
// others, and compares the two halves: relative variance per sample (the mean of the pixels'
// luminance variance over the squared mean luminance) times rays per sample. Guiding goes on only
// if the unguided half's figure is kAutoGuidingGain times the guided one's or more; otherwise the
// rest renders unguided and nothing more is learned. With a time budget the passes double while
// the next would end within half of it, and one-sample passes with the last field fill the rest.
// Deterministic for a sample count: records are kept per tile and joined in tile order.
//
// Light paths (RenderSettings::lightPaths, light_paths.h). Where the light has portals, each sample
// index has its own pool of light paths, traced before the samples of that index from the seed and
// the index alone (so passes of any size give the same image), and the paths connect to it. Under
// auto the first 8 samples (fewer if the render has fewer) connect the pixels with x + y even and
// not the others, as guiding's comparing pass does, and the rest connect only if the connected
// half's figure was 1.1 times lower. A time-limited render renders those first samples in one pass.
//
// Branching (RenderSettings::branches). Under auto, before the first pass, a probe of 13,824
// camera samples spread over the full frame, each with two branches and none of them in the
// image, measures what a branch costs and what it lowers: the rays cast before and after the
// first vertex's light sample, the spread of the two branches' estimates (the variance after the
// first vertex) and that of neighbouring pixels' samples (the whole). Every sample then branches
// as branchesThatPay says. The probe's seed is fixed and it ignores the crop, so the choice is the
// scene's: the same for every seed, crop and time budget.

#include <cstddef>
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

struct GuidingStats {
  bool guided = false;          // whether the last samples were guided
  uint32_t trainingPasses = 0;  // passes whose records built a field
  // Under auto, the second pass's unguided over guided relative variance × rays per sample.
  std::optional<double> measuredGain;
  std::size_t spatialLeaves = 0, fieldBytes = 0;  // the last field's
  double fieldSeconds = 0;                        // building fields
};

// The gain `auto` needs to guide: the field's lookups cost time the ray count does not show.
inline constexpr double kAutoGuidingGain = 1.2;

// The most branches auto chooses, and what their figure must promise: rays are its cost, and a
// branch's BSDF evaluations and light sample cost more than its rays say on measured materials
// (the demo: 2 branches promised 1.065x and lose 4 %; the RGL scene, 1.107x and gain 6 %).
inline constexpr uint32_t kMaxAutoBranches = 8;
inline constexpr double kBranchingMargin = 1.1;

// The branch count K in [1, kMaxAutoBranches] that makes variance times cost per camera sample,
// (V0 + V1 / K)(c0 + K c1), least (about sqrt(V1 c0 / (V0 c1))), if that is kBranchingMargin
// times less than with one branch (else 1), for rays per camera sample
// c0 = `raysBefore` (the camera ray, the first vertex's shadow ray) and per branch c1 =
// `raysAfter`, and the variance of the light before the first vertex's continuation
// V0 = `varianceBefore` (negative counts as 0) and after it, per branch, V1 = `varianceAfter`.
uint32_t branchesThatPay(double raysBefore, double raysAfter, double varianceBefore, double varianceAfter);

struct BranchingStats {
  uint32_t branches = 1;  // of the last samples
  // Under auto, what the probe measured: rays per camera sample before the first vertex's light
  // sample and per branch after it, and the relative variances (over the squared mean luminance)
  // before and after the first vertex's continuation, per sample of a pixel's first
  // 8 samples (none where the probe saw only black: one branch then).
  std::optional<double> raysBefore, raysAfter, varianceBefore, varianceAfter;
};

struct RenderStats {
  uint32_t spp = 0;    // samples per pixel rendered
  uint64_t paths = 0;  // camera paths traced
  uint64_t rays = 0;   // rays cast (closest hit and shadow)
  double seconds = 0;  // wall-clock render time
  GuidingStats guiding;
  BranchingStats branching;
  bool connectsLightPaths = false;  // whether the paths connected to light paths (light_paths.h)
  // Where the scene could, the probe's variance times rays per sample without connections over
  // with them.
  std::optional<double> lightPathGain;
};

// The film has the crop window's size.
Film makeFilm(const Scene& scene);
RenderStats render(const Scene& scene, Film& film, const RenderOptions& options = {});

}  // namespace acdf
