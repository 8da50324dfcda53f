#include "acdf/integrator/scene_assets.h"

#include <stdexcept>

#include <fmt/format.h>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/measured_file.h"
#include "acdf/brdf/rgl.h"

namespace acdf {

std::shared_ptr<const BrdfModel> SceneAssets::measuredFile(const std::filesystem::path& path,
                                                             MerlBrdf::Interpolation interpolation) {
  auto& slot = measuredFiles_[path.string()];
  if (!slot) slot = loadMeasuredBrdf(path);
  if (const auto merl = std::dynamic_pointer_cast<const MerlBrdf>(slot))
    return std::make_shared<const MerlBrdf>(merl->withInterpolation(interpolation));
  return slot;
}

std::shared_ptr<const MerlBrdf> SceneAssets::merlPreset(const std::string& name,
                                                          MerlBrdf::Interpolation interpolation) {
  auto& slot = merlPresets_[name];
  if (!slot) {
    const std::vector<double> raw = AnalyticBrdf::preset(name).merlTable();
    const std::span<const double> all(raw);
    slot = std::make_shared<const MerlBrdf>(all.subspan(0, MerlBrdf::kCells),
                                            all.subspan(MerlBrdf::kCells, MerlBrdf::kCells),
                                            all.subspan(2 * MerlBrdf::kCells, MerlBrdf::kCells));
  }
  return std::make_shared<const MerlBrdf>(slot->withInterpolation(interpolation));
}

std::shared_ptr<const EnvironmentMap> SceneAssets::environmentMap(const std::filesystem::path& path) {
  auto& slot = maps_[path.string()];
  if (!slot) {
    slot = std::make_shared<const EnvironmentMap>(EnvironmentMap::load(path.string()));
  }
  return slot;
}

std::shared_ptr<const BrdfSampler> SceneAssets::brdfSampler(const std::shared_ptr<const BrdfModel>& model,
                                                              const std::string& modelName, BrdfSampling sampling,
                                                              TabulatedBrdfOptions table) {
  if (sampling == BrdfSampling::Cosine) return makeBrdfSampler(model, sampling);
  // A native sampler is shared by every request for the model; `what` names the model in errors.
  std::string key = fmt::format("{} {}", toString(sampling), modelName), what = modelName;
  const std::optional<DimensionMethod> method = tableMethod(sampling);
  if (method) {
    table.method = *method;
    // The cache key covers the model's values and every option that shapes the table; the
    // defensive mixture weight is applied at sample time, so it only tells samplers apart.
    key = fmt::format("{} w={:a}", TabulatedBrdfSampler::tableKey(*model, table).hex(), table.cosineWeight);
    what = fmt::format("brdf {} {}", table.name(), modelName);  // in the tables' list and the cache's warnings
  }
  auto& slot = brdfSamplers_[key];
  if (!slot) {
    MadeBrdfSampler made = makeBrdfSampler(model, sampling, table, cache_, what);
    slot = std::move(made.sampler);
    if (method) record(what, made.fromCache);
  }
  return slot;
}

std::shared_ptr<const EnvironmentTable> SceneAssets::environmentTable(
    const std::shared_ptr<const EnvironmentMap>& map, const std::string& mapKey, EnvironmentTableStrategy strategy,
    const SimplifyOptions& simplify) {
  if (strategy == EnvironmentTableStrategy::UniformSphere || map->isBlack())
    return std::make_shared<const EnvironmentTable>(map, strategy, simplify);
  auto& slot = environmentTables_[EnvironmentTable::key(*map, strategy, simplify).hex()];
  if (!slot) {
    const std::string what = fmt::format("envmap {} {}", toString(strategy), mapKey);
    Cached<EnvironmentTable> table = EnvironmentTable::cached(cache_, map, strategy, simplify, what);
    slot = std::make_shared<const EnvironmentTable>(std::move(table.value));
    record(what, table.fromCache);
  }
  return slot;
}

void SceneAssets::recordPortalTables(const EnvironmentLight& light, const std::string& mapKey) {
  for (std::size_t i = 0; i < light.options().portals.size(); ++i) {
    const WindowedTable2D& table = light.portalTable(i).table();
    record(fmt::format("envmap portal {} {} ({} x {} cells, {:.0f} kB)", i, mapKey, table.coarseColumns(),
                       table.coarseRows(), table.bytes() / 1024.0),
           false);
  }
}

}  // namespace acdf
