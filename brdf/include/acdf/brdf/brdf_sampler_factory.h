#pragma once
// The one place a BRDF sampler is chosen by name: the scene file, the command line, bench-error
// and the Python module all go through makeBrdfSampler, so a new sampler is an enum value, a name
// and a case here.

#include <memory>
#include <optional>
#include <string_view>

#include "acdf/brdf/brdf_model.h"
#include "acdf/brdf/brdf_sampler.h"
#include "acdf/brdf/tabulated_brdf_sampler.h"
#include "acdf/sampling/table_cache.h"

namespace acdf {

// Cosine: cosine-weighted (no table). Uniform, Adaptive: the half-vector tables
// (TabulatedBrdfSampler) with that method. Native: the model's own sampler
// (BrdfModel::nativeSampler: an RGL file's warps, GGX's distribution of normals); named "rgl",
// as users of the RGL format know it.
enum class BrdfSampling { Cosine, Uniform, Adaptive, Native };

// "cosine", "uniform", "adaptive", "rgl"; parse throws std::invalid_argument naming them.
std::string_view toString(BrdfSampling sampling);
BrdfSampling parseBrdfSampling(std::string_view name);

// The method of the half-vector tables `sampling` names (Uniform, Adaptive); none for the others.
std::optional<DimensionMethod> tableMethod(BrdfSampling sampling);

// A sampler and whether its table came from the cache (false when it has none).
struct MadeBrdfSampler {
  std::shared_ptr<const BrdfSampler> sampler;
  bool fromCache = false;
};

// The sampler `sampling` names for `model`. The table strategies use `table` with their method
// (table.method is set to tableMethod(sampling)), read from `cache` when it holds the table and stored there
// once built; `what` names the table in the cache's warnings, or the model in Native's error. Throws std::invalid_argument for Native
// with a model that has no sampler of its own, OptionError or std::invalid_argument for table
// options the model does not suit.
MadeBrdfSampler makeBrdfSampler(const std::shared_ptr<const BrdfModel>& model, BrdfSampling sampling,
                                TabulatedBrdfOptions table, TableCache& cache, std::string_view what);
// The same without a cache: every table is built.
std::shared_ptr<const BrdfSampler> makeBrdfSampler(const std::shared_ptr<const BrdfModel>& model,
                                                   BrdfSampling sampling, const TabulatedBrdfOptions& table = {});

}  // namespace acdf
