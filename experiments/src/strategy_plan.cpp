#include "acdf/experiments/strategy_plan.h"

#include <fmt/format.h>

namespace acdf {

std::string Strategy::label() const {
  return fmt::format("{} × {} × {} × {}", toString(bsdf), toString(env), toString(mis), toString(sampler));
}

std::string Strategy::id() const {
  return fmt::format("{}_{}_{}_{}", toString(bsdf), toString(env), toString(mis), toString(sampler));
}

StrategyPlan planStrategies(const std::vector<BrdfSampling>& bsdfs, const std::vector<EnvironmentSampling>& envs,
                            const std::vector<MisMode>& mises, const std::vector<SamplerKind>& samplers,
                            bool sceneHasMeasured) {
  StrategyPlan plan;
  for (SamplerKind sampler : samplers)
    for (MisMode mis : mises)
      for (BrdfSampling bsdf : bsdfs)
        for (EnvironmentSampling env : envs) {
          const Strategy s{bsdf, env, mis, sampler};
          if (!sceneHasMeasured && bsdf != bsdfs.front())
            plan.skipped.push_back(
                {s, fmt::format("no measured material: the same image as {} BRDF sampling", toString(bsdfs.front()))});
          else if (mis == MisMode::BsdfOnly && env != envs.front())
            plan.skipped.push_back({s, fmt::format("bsdf-only never samples the environment: the same image as {}",
                                                   toString(envs.front()))});
          else
            plan.render.push_back(s);
        }
  return plan;
}

}  // namespace acdf
