#include "acdf/integrator/scene_assets.h"

#include <stdexcept>

#include <fmt/format.h>

#include "acdf/brdf/analytic.h"
#include "acdf/brdf/measured_file.h"
#include "acdf/brdf/rgl.h"
#include "acdf/brdf/rgl_sampler.h"
#include "acdf/sampling/enum_names.h"

namespace acdf {

namespace {
constexpr EnumName<BrdfSampling> kBrdfSamplingNames[] = {
    {BrdfSampling::Cosine, "cosine"},
    {BrdfSampling::Uniform, "uniform"},
    {BrdfSampling::Adaptive, "adaptive"},
    {BrdfSampling::Rgl, "rgl"},
};
}  // namespace

std::string_view toString(BrdfSampling sampling) { return nameOf(kBrdfSamplingNames, sampling); }

BrdfSampling parseBrdfSampling(std::string_view name) { return valueNamed(kBrdfSamplingNames, name, "BRDF sampling"); }

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
  if (sampling == BrdfSampling::Cosine) return std::make_shared<const CosineBrdfSampler>(model);
  if (sampling == BrdfSampling::Rgl) {
    auto rgl = std::dynamic_pointer_cast<const RglBrdf>(model);
    if (!rgl) throw std::invalid_argument("rgl sampling needs an RGL .bsdf file, and " + modelName + " is not one");
    auto& slot = brdfSamplers_["rgl " + modelName];
    if (!slot) slot = std::make_shared<const RglBrdfSampler>(std::move(rgl));
    return slot;
  }
  table.method = sampling == BrdfSampling::Uniform ? DimensionMethod::Uniform : DimensionMethod::Adaptive;
  // The cache key covers the model's values and every option that shapes the table; the defensive
  // mixture weight is applied at sample time, so it only tells samplers apart.
  const CacheKey tableKey = TabulatedBrdfSampler::tableKey(*model, table);
  auto& slot = brdfSamplers_[fmt::format("{} w={:a}", tableKey.hex(), table.cosineWeight)];
  if (!slot) {
    const std::string what = fmt::format("brdf {} {}", table.name(), modelName);
    Cached<Cascade> cascade =
        cache_.getOrBuild(tableKey, what, [&] { return TabulatedBrdfSampler::buildCascade(*model, table); });
    try {
      slot = std::make_shared<const TabulatedBrdfSampler>(model, table, std::move(cascade.value));
    } catch (const SerializationError&) {
      // A cached table of another shape under this key (a hash collision): never trusted.
      slot = std::make_shared<const TabulatedBrdfSampler>(model, table);
      cascade.fromCache = false;
    }
    record(what, cascade.fromCache);
  }
  return slot;
}

std::shared_ptr<const EnvironmentTable> SceneAssets::environmentTable(
    const std::shared_ptr<const EnvironmentMap>& map, const std::string& mapKey, EnvironmentSampling strategy,
    const SimplifyOptions& simplify) {
  if (strategy == EnvironmentSampling::UniformSphere || map->isBlack())
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

}  // namespace acdf
