#include "acdf/brdf/brdf_sampler_factory.h"

#include <stdexcept>
#include <string>

#include "acdf/sampling/enum_names.h"

namespace acdf {

namespace {
constexpr EnumName<BrdfSampling> kBrdfSamplingNames[] = {
    {BrdfSampling::Cosine, "cosine"},
    {BrdfSampling::Uniform, "uniform"},
    {BrdfSampling::Adaptive, "adaptive"},
    {BrdfSampling::Native, "rgl"},
};
}  // namespace

std::string_view toString(BrdfSampling sampling) { return nameOf(kBrdfSamplingNames, sampling); }

BrdfSampling parseBrdfSampling(std::string_view name) { return valueNamed(kBrdfSamplingNames, name, "BRDF sampling"); }

std::optional<DimensionMethod> tableMethod(BrdfSampling sampling) {
  switch (sampling) {
    case BrdfSampling::Uniform: return DimensionMethod::Uniform;
    case BrdfSampling::Adaptive: return DimensionMethod::Adaptive;
    case BrdfSampling::Cosine:
    case BrdfSampling::Native: break;
  }
  return std::nullopt;
}

MadeBrdfSampler makeBrdfSampler(const std::shared_ptr<const BrdfModel>& model, BrdfSampling sampling,
                                TabulatedBrdfOptions table, TableCache& cache, std::string_view what) {
  if (!model) throw std::invalid_argument("makeBrdfSampler: no model");
  if (sampling == BrdfSampling::Cosine) return {std::make_shared<const CosineBrdfSampler>(model), false};
  if (sampling == BrdfSampling::Native) {
    auto native = model->nativeSampler(model);
    if (!native)
      throw std::invalid_argument("rgl sampling needs an RGL .bsdf file (a model with a sampler of its own), and " +
                                  std::string(what) + " is not one");
    return {std::move(native), false};
  }
  table.method = *tableMethod(sampling);
  validate(table);
  Cached<Cascade> cascade = cache.getOrBuild(TabulatedBrdfSampler::tableKey(*model, table), what,
                                             [&] { return TabulatedBrdfSampler::buildCascade(*model, table); });
  try {
    return {std::make_shared<const TabulatedBrdfSampler>(model, table, std::move(cascade.value)), cascade.fromCache};
  } catch (const SerializationError&) {
    // A cached table of another shape under this key (a hash collision): never trusted.
    return {std::make_shared<const TabulatedBrdfSampler>(model, table), false};
  }
}

std::shared_ptr<const BrdfSampler> makeBrdfSampler(const std::shared_ptr<const BrdfModel>& model,
                                                   BrdfSampling sampling, const TabulatedBrdfOptions& table) {
  TableCache none = TableCache::disabled();
  return makeBrdfSampler(model, sampling, table, none, "the model").sampler;
}

}  // namespace acdf
