#pragma once
// The one place the renderer gets its inputs and sampling tables from: MERL files, environment
// maps, BRDF sampling tables and environment tables. Each is made on first request and
// shared by later ones (two spheres of one material get one table). Tables come from the on-disk
// TableCache when it holds them (docs/table-cache.md; a corrupt or stale file is rebuilt with a
// warning) and are stored there once built; each is recorded as built or read from the cache,
// so a render can say which and how long its set-up took. The scene loader asks only for what
// its shapes and chosen strategies use.

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "acdf/brdf/brdf_sampler.h"
#include "acdf/brdf/brdf_sampler_factory.h"
#include "acdf/brdf/merl.h"
#include "acdf/brdf/tabulated_brdf_sampler.h"
#include "acdf/envmap/environment_light.h"
#include "acdf/envmap/environment_map.h"
#include "acdf/envmap/environment_table.h"
#include "acdf/sampling/table_cache.h"

namespace acdf {

class SceneAssets {
 public:
  // TableCache::disabled() builds everything (--no-cache).
  explicit SceneAssets(TableCache cache) : cache_(std::move(cache)) {}

  // A measured file of either format (loadMeasuredBrdf: RGL or MERL by content), loaded once per
  // path; MERL tables of any interpolation share the values. Throws FileError.
  std::shared_ptr<const BrdfModel> measuredFile(const std::filesystem::path& path,
                                                MerlBrdf::Interpolation interpolation);
  std::shared_ptr<const EnvironmentMap> environmentMap(const std::filesystem::path& path);
  // AnalyticBrdf::preset(name) tabulated in the MERL layout (no file needed), once per name.
  // Throws std::invalid_argument for an unknown preset.
  std::shared_ptr<const MerlBrdf> merlPreset(const std::string& name, MerlBrdf::Interpolation interpolation);

  // makeBrdfSampler's sampler of `model`, whose name in the tables' list is `modelName` (its file
  // or preset), through this cache: table samplers are shared by every request with the same table
  // key (the model's content and the options), native ones by every request for the model.
  std::shared_ptr<const BrdfSampler> brdfSampler(const std::shared_ptr<const BrdfModel>& model,
                                                 const std::string& modelName, BrdfSampling sampling,
                                                 TabulatedBrdfOptions table);
  // The sampling table of `map` (identity `mapKey`) under `strategy`, shared by every light of the
  // map whatever its rotation and scale. Uniform-sphere sampling and a black map have no table to
  // build or record.
  std::shared_ptr<const EnvironmentTable> environmentTable(const std::shared_ptr<const EnvironmentMap>& map,
                                                           const std::string& mapKey, EnvironmentTableStrategy strategy,
                                                           const SimplifyOptions& simplify);

  // Records the portals' tables a light built with itself (PortalTable: not cached, 80 ms each for
  // a 1024 × 512 map), named by the map's identity `mapKey`, with their cells and bytes.
  void recordPortalTables(const EnvironmentLight& light, const std::string& mapKey);

  // Names of the tables built, and read from the cache, so far, in order.
  const std::vector<std::string>& tablesBuilt() const { return built_; }
  const std::vector<std::string>& tablesFromCache() const { return fromCache_; }

 private:
  void record(const std::string& table, bool fromCache) { (fromCache ? fromCache_ : built_).push_back(table); }

  TableCache cache_;
  std::map<std::string, std::shared_ptr<const BrdfModel>> measuredFiles_;
  std::map<std::string, std::shared_ptr<const MerlBrdf>> merlPresets_;
  std::map<std::string, std::shared_ptr<const EnvironmentMap>> maps_;
  std::map<std::string, std::shared_ptr<const BrdfSampler>> brdfSamplers_;
  std::map<std::string, std::shared_ptr<const EnvironmentTable>> environmentTables_;
  std::vector<std::string> built_, fromCache_;
};

}  // namespace acdf
