#include "acdf/experiments/strategy_plan.h"

#include <fmt/format.h>

namespace acdf {

std::string Strategy::label() const {
  return fmt::format("{} × {} × {} × {}", toString(bsdf), toString(env), lighting(), toString(sampler));
}

std::string Strategy::id() const {
  return fmt::format("{}_{}_{}_{}", toString(bsdf), toString(env), lighting(), toString(sampler));
}

StrategyPlan planStrategies(const std::vector<BrdfSampling>& bsdfs, const std::vector<EnvironmentSampling>& envs,
                            const std::vector<MisMode>& mises, const std::vector<SamplerKind>& samplers,
                            bool sceneHasMeasured, const std::vector<DirectLighting>& directs) {
  StrategyPlan plan;
  for (SamplerKind sampler : samplers)
    for (DirectLighting direct : directs)
      for (MisMode mis : mises)
        for (BrdfSampling bsdf : bsdfs)
          for (EnvironmentSampling env : envs) {
            const Strategy s{bsdf, env, mis, sampler, direct};
            const bool product = direct == DirectLighting::Product;
            if (!sceneHasMeasured && bsdf != bsdfs.front())
              plan.skipped.push_back({s, fmt::format("no measured material: the same image as {} BRDF sampling",
                                                     toString(bsdfs.front()))});
            else if (product && mis != mises.front())
              plan.skipped.push_back({s, fmt::format("product lighting uses no MIS mode: the same image as with {}",
                                                     toString(mises.front()))});
            else if (!product && mis == MisMode::BsdfOnly && env != envs.front())
              plan.skipped.push_back({s, fmt::format("bsdf-only never samples the environment: the same image as {}",
                                                     toString(envs.front()))});
            else
              plan.render.push_back(s);
          }
  return plan;
}

}  // namespace acdf
