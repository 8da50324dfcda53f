#pragma once
// The sampling-strategy combinations (BRDF sampling × environment sampling × direct lighting and
// its MIS mode × sample source) a comparison renders, with the rules for which of them render the
// same image by construction, so a comparison renders each image once and says why it left the
// others out.

#include <string>
#include <vector>

#include "acdf/envmap/environment_table.h"
#include "acdf/integrator/scene.h"
#include "acdf/integrator/scene_assets.h"

namespace acdf {

struct Strategy {
  BrdfSampling bsdf;
  EnvironmentSampling env;
  MisMode mis;
  SamplerKind sampler = SamplerKind::Independent;
  DirectLighting direct = DirectLighting::Mis;

  // How direct light is gathered: the MIS mode's name, or "product" (which uses no MIS mode).
  std::string_view lighting() const { return direct == DirectLighting::Product ? toString(direct) : toString(mis); }
  // "adaptive × hierarchical × power × sobol" (the third: lighting()).
  std::string label() const;
  // File-name form, "adaptive_hierarchical_power_sobol".
  std::string id() const;
};

struct SkippedStrategy {
  Strategy strategy;
  std::string reason;  // which image it would repeat
};

struct StrategyPlan {
  std::vector<Strategy> render;  // in the order sample source, direct lighting, MIS mode, BRDF sampling,
                                 // environment sampling
  std::vector<SkippedStrategy> skipped;
};

// Every combination of the lists (each non-empty), less those identical to one rendered: without
// a measured material every BRDF strategy samples as the first one does; bsdf-only never samples
// the environment, so only the first environment strategy is rendered with it; product direct
// lighting uses no MIS mode, so only the first MIS mode is rendered with it.
StrategyPlan planStrategies(const std::vector<BrdfSampling>& bsdfs, const std::vector<EnvironmentSampling>& envs,
                            const std::vector<MisMode>& mises, const std::vector<SamplerKind>& samplers,
                            bool sceneHasMeasured,
                            const std::vector<DirectLighting>& directs = {DirectLighting::Mis});

}  // namespace acdf
