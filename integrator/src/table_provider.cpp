#include "acdf/integrator/table_provider.h"

#include <chrono>
#include <stdexcept>

#include <fmt/format.h>

#include "acdf/brdf/analytic.h"

namespace acdf {

namespace {

// Adds the wall-clock time of its scope to a counter.
class ScopedTimer {
 public:
  explicit ScopedTimer(double& total) : total_(total), start_(std::chrono::steady_clock::now()) {}
  ~ScopedTimer() { total_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count(); }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  double& total_;
  std::chrono::steady_clock::time_point start_;
};

// Every option that changes a table, so equal keys mean equal tables.
std::string simplifyKey(const SimplifyOptions& o) {
  return fmt::format("simplify{}/{}/{}/{}/{}", static_cast<int>(o.method), static_cast<int>(o.metric), o.epsilon,
                     o.maxPoints, o.weightBound);
}

std::string tableKey(const TabulatedBrdfOptions& o) {
  return fmt::format("{} {}x{}x{}x{} ss{} w{} mirror{} {} tol{}", o.name(), o.thetaOutCells, o.phiOutCells,
                     o.thetaHalfCells, o.phiHalfCells, o.supersampling, o.cosineWeight, o.mirror, simplifyKey(o.simplify),
                     static_cast<int>(o.tolerance));
}

}  // namespace

std::string_view toString(BrdfSampling sampling) {
  switch (sampling) {
    case BrdfSampling::Cosine: return "cosine";
    case BrdfSampling::Uniform: return "uniform";
    case BrdfSampling::Adaptive: return "adaptive";
  }
  return "?";
}

BrdfSampling parseBrdfSampling(std::string_view name) {
  for (auto s : {BrdfSampling::Cosine, BrdfSampling::Uniform, BrdfSampling::Adaptive})
    if (toString(s) == name) return s;
  throw std::invalid_argument("unknown BRDF sampling '" + std::string(name) + "' (cosine, uniform or adaptive)");
}

std::shared_ptr<const MerlBrdf> TableProvider::merlFile(const std::filesystem::path& path) {
  auto& slot = merls_["file:" + path.string()];
  if (!slot) {
    ScopedTimer timer(milliseconds_);
    slot = std::make_shared<const MerlBrdf>(MerlBrdf::load(path));
  }
  return slot;
}

std::shared_ptr<const MerlBrdf> TableProvider::merlPreset(const std::string& name) {
  auto& slot = merls_["preset:" + name];
  if (!slot) {
    ScopedTimer timer(milliseconds_);
    const std::vector<double> raw = AnalyticBrdf::preset(name).merlTable();
    const std::span<const double> all(raw);
    slot = std::make_shared<const MerlBrdf>(all.subspan(0, MerlBrdf::kCells), all.subspan(MerlBrdf::kCells, MerlBrdf::kCells),
                                            all.subspan(2 * MerlBrdf::kCells, MerlBrdf::kCells));
  }
  return slot;
}

std::shared_ptr<const EnvironmentMap> TableProvider::environmentMap(const std::filesystem::path& path) {
  auto& slot = maps_[path.string()];
  if (!slot) {
    ScopedTimer timer(milliseconds_);
    slot = std::make_shared<const EnvironmentMap>(EnvironmentMap::load(path.string()));
  }
  return slot;
}

std::shared_ptr<const BrdfSampler> TableProvider::brdfSampler(const std::shared_ptr<const MerlBrdf>& brdf,
                                                              const std::string& brdfKey,
                                                              MerlBrdf::Interpolation interpolation,
                                                              BrdfSampling sampling, TabulatedBrdfOptions table) {
  if (sampling == BrdfSampling::Cosine) return std::make_shared<const CosineBrdfSampler>(*brdf, interpolation);
  table.method = sampling == BrdfSampling::Uniform ? DimensionMethod::Uniform : DimensionMethod::Adaptive;
  const std::string key = fmt::format("{} [{}] interp{}", brdfKey, tableKey(table), static_cast<int>(interpolation));
  auto& slot = brdfSamplers_[key];
  if (!slot) {
    ScopedTimer timer(milliseconds_);
    slot = std::make_shared<const TabulatedBrdfSampler>(*brdf, interpolation, table);
    built_.push_back(fmt::format("brdf {} {}", table.name(), brdfKey));
  }
  return slot;
}

std::shared_ptr<const EnvironmentLight> TableProvider::environmentLight(const std::shared_ptr<const EnvironmentMap>& map,
                                                                        const std::string& mapKey,
                                                                        const EnvironmentLightOptions& options) {
  // The light also carries the rotation and scale, which the table does not depend on, but a
  // light is one object: key them too.
  const Vec3d x = options.worldFromMap.apply({1, 0, 0}), y = options.worldFromMap.apply({0, 1, 0});
  const std::string key = fmt::format("{} {} {} scale{} rot{},{},{},{},{},{}", mapKey, toString(options.strategy),
                                      simplifyKey(options.simplify), options.scale, x.x, x.y, x.z, y.x, y.y, y.z);
  auto& slot = lights_[key];
  if (!slot) {
    ScopedTimer timer(milliseconds_);
    slot = std::make_shared<const EnvironmentLight>(map, options);
    built_.push_back(fmt::format("envmap {} {}", toString(options.strategy), mapKey));
  }
  return slot;
}

}  // namespace acdf
