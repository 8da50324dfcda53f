#include "acdf/envmap/environment_light.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "acdf/sampling/sample.h"
#include "acdf/sampling/spherical_rectangle.h"

namespace acdf {

namespace {
// Whether `position` is on the side light passes a portal towards.
bool facing(const Portal& portal, const Vec3d& position) {
  return dot(position - portal.corner, cross(portal.edgeU, portal.edgeV)) > 0;
}
}  // namespace

std::optional<std::string> portalProblem(const Portal& portal) {
  const double u = length(portal.edgeU), v = length(portal.edgeV);
  if (!std::isfinite(dot(portal.corner, portal.corner)) || !std::isfinite(u * v))
    return "its corner and edges must be finite";
  if (!(u > 0) || !(v > 0)) return "its edges must not be zero";
  if (std::abs(dot(portal.edgeU, portal.edgeV)) > 1e-6 * u * v) return "edge_u and edge_v must be perpendicular";
  return std::nullopt;
}

void validate(const EnvironmentLightOptions& o) {
  if (!(o.scale > 0.0f) || !std::isfinite(o.scale))
    throw OptionError("environment light", "scale", "must be finite and > 0, got " + OptionError::number(o.scale));
  validate(o.simplify);
  validate(o.local);
  for (std::size_t i = 0; i < o.portals.size(); ++i)
    if (const std::optional<std::string> problem = portalProblem(o.portals[i]))
      throw OptionError("environment light", "portals", "[" + std::to_string(i) + "]: " + *problem);
}

EnvironmentLight::EnvironmentLight(std::shared_ptr<const EnvironmentMap> map, EnvironmentLightOptions options)
    : EnvironmentLight(map, std::move(options), LightPdfs::Either,
                       [&map](EnvironmentTableStrategy strategy, const SimplifyOptions& simplify) {
                         return std::make_shared<const EnvironmentTable>(map, strategy, simplify);
                       }) {}

EnvironmentLight::EnvironmentLight(std::shared_ptr<const EnvironmentMap> map, EnvironmentLightOptions options,
                                   LightPdfs pdfs, const EnvironmentTableSource& tables)
    : map_(std::move(map)), options_(std::move(options)) {
  if (!map_) throw std::invalid_argument("EnvironmentLight: no map");
  validate(options_);
  auto get = [&](EnvironmentTableStrategy strategy) {
    std::shared_ptr<const EnvironmentTable> table = tables(strategy, options_.simplify);
    if (!table || table->strategy() != strategy || table->map().width() != map_->width() ||
        table->map().height() != map_->height())
      throw std::invalid_argument("EnvironmentLight: the table source gave no table of this map and strategy");
    return table;
  };
  const std::optional<EnvironmentTableStrategy> strategy = tableStrategyOf(options_.strategy);
  if (!strategy) {  // Local, LocalCompensated
    // Calls without a normal get the Adaptive table, whatever `pdfs` (it is complete); so do the
    // calls with one that need a complete pdf from a compensated local light.
    complete_ = get(EnvironmentTableStrategy::Adaptive);
    local_ = std::make_shared<const LocalEnvironmentTable>(
        map_, options_.local, options_.simplify, options_.strategy == EnvironmentSampling::LocalCompensated);
    return;
  }
  if (*strategy != EnvironmentTableStrategy::Compensated) {
    complete_ = get(*strategy);
    return;
  }
  // The compensated table for calls that allow an incomplete pdf, the Adaptive table of the same
  // map (the function before compensation) for the others.
  if (pdfs != LightPdfs::Complete) {
    incomplete_ = get(EnvironmentTableStrategy::Compensated);
    if (incomplete_->complete()) {  // fell back to the uncompensated function: serves both
      complete_ = std::move(incomplete_);
      return;
    }
  }
  if (pdfs != LightPdfs::Incomplete) complete_ = get(EnvironmentTableStrategy::Adaptive);
}

const EnvironmentTable& EnvironmentLight::table(const LightSampleContext& context) const {
  if (context.allowIncompletePdf && incomplete_) return *incomplete_;
  if (!complete_) throw std::logic_error("EnvironmentLight: asked for a complete pdf, made for incomplete ones only");
  return *complete_;
}

LightSample EnvironmentLight::sample(const LightSampleContext& context, float u0, float u1) const {
  const double portals = portalSolidAngle(context);
  if (portals > 0) {
    if (emitsNothing()) return {};
    const double u = clampUnit(u0);
    if (u < kPortalShare) {
      // The facing portal whose share of Σ Ω_i holds u, and u rescaled into that share (the last
      // facing one takes what rounding leaves over).
      double at = u / kPortalShare * portals;
      std::optional<SphericalRectangle> chosen;
      for (const Portal& portal : options_.portals) {
        if (!facing(portal, *context.position)) continue;
        SphericalRectangle seen(*context.position, portal.corner, portal.edgeU, portal.edgeV);
        if (seen.empty()) continue;
        const bool holds = at < seen.solidAngle();
        if (!holds) at -= seen.solidAngle();
        chosen = seen;
        if (holds) break;
      }
      const Vec3d w = chosen->sample(std::clamp(at / chosen->solidAngle(), 0.0, 1.0), clampUnit(u1)).direction;
      const PixelIndex p = map_->mapping().pixelOf(options_.worldFromMap.applyInverse(w));
      return {w, scaled(map_->radiance(p)), mixturePdf(context, w, p)};
    }
    u0 = static_cast<float>(std::min((u - kPortalShare) / (1.0 - kPortalShare), double{kOneMinusEpsilon}));
  }
  const EnvironmentTable::Sample s =
      usesLocal(context) ? local_->sampleInCell(localCell(context), u0, u1) : table(context).sample(u0, u1);
  if (!(s.pdf > 0)) return {};
  const Vec3d w = options_.worldFromMap.apply(s.direction);
  return {w, scaled(map_->radiance(s.pixel)), portals > 0 ? mixturePdf(context, w, s.pixel) : s.pdf};
}

double EnvironmentLight::portalSolidAngle(const Vec3d& position) const {
  double total = 0;
  for (const Portal& portal : options_.portals)
    if (facing(portal, position))
      total += SphericalRectangle(position, portal.corner, portal.edgeU, portal.edgeV).solidAngle();
  return total;
}

double EnvironmentLight::portalSolidAngle(const LightSampleContext& context) const {
  if (!context.position || options_.portals.empty()) return 0.0;
  return context.portalSolidAngle ? *context.portalSolidAngle : portalSolidAngle(*context.position);
}

double EnvironmentLight::portalPdf(const Vec3d& position, double solidAngle, const Vec3d& w) const {
  int through = 0;
  for (const Portal& portal : options_.portals)
    through += facing(portal, position) &&
               SphericalRectangle::passesThrough(position, portal.corner, portal.edgeU, portal.edgeV, w);
  return through / solidAngle;
}

double EnvironmentLight::strategyPdf(const LightSampleContext& context, PixelIndex p) const {
  const std::optional<double> local = localPdf(context, p);
  // The light's tables are of its map's size, so this pixel is theirs too.
  return local ? *local : table(context).pdf(p);
}

double EnvironmentLight::mixturePdf(const LightSampleContext& context, const Vec3d& w, PixelIndex p) const {
  const double strategy = strategyPdf(context, p);
  const double portals = portalSolidAngle(context);
  if (!(portals > 0)) return strategy;
  return kPortalShare * portalPdf(*context.position, portals, w) + (1.0 - kPortalShare) * strategy;
}

LightSampleContext EnvironmentLight::atPosition(LightSampleContext context, const Vec3d& position) const {
  context.position = position;
  context.portalSolidAngle.reset();
  if (!options_.portals.empty()) context.portalSolidAngle = portalSolidAngle(position);
  return context;
}

LightSampleContext EnvironmentLight::atNormal(LightSampleContext context, const Vec3d& normal) const {
  context.normal = normal;
  context.localCell.reset();
  if (local_) context.localCell = localCell(context);
  return context;
}

double EnvironmentLight::pdf(const LightSampleContext& context, const Vec3d& w) const {
  return mixturePdf(context, w, map_->mapping().pixelOf(options_.worldFromMap.applyInverse(w)));
}

Rgb EnvironmentLight::eval(const Vec3d& w) const {
  return scaled(map_->radiance(options_.worldFromMap.applyInverse(w)));
}

RadianceAndPdf EnvironmentLight::evalWithPdf(const LightSampleContext& context, const Vec3d& w) const {
  const Vec3d mapDirection = options_.worldFromMap.applyInverse(w);
  const PixelIndex p = map_->mapping().pixelOf(mapDirection);
  return {scaled(map_->radiance(p)), mixturePdf(context, w, p)};
}

std::optional<double> EnvironmentLight::localPdf(const LightSampleContext& context, PixelIndex p) const {
  if (!usesLocal(context)) return std::nullopt;
  return local_->pdfInCell(localCell(context), p);
}

bool EnvironmentLight::usesLocal(const LightSampleContext& context) const {
  return local_ && context.normal && (context.allowIncompletePdf || !local_->compensated());
}

std::size_t EnvironmentLight::localCell(const LightSampleContext& context) const {
  return context.localCell ? *context.localCell : local_->sliceOf(options_.worldFromMap.applyInverse(*context.normal));
}

Rgb EnvironmentLight::scaled(const Rgb& L) const {
  const float k = options_.scale;
  return {k * L.r, k * L.g, k * L.b};
}

bool EnvironmentLight::emitsNothing() const {
  return (!complete_ || complete_->emitsNothing()) && (!incomplete_ || incomplete_->emitsNothing());
}

std::size_t EnvironmentLight::tableBytes() const {
  return (complete_ ? complete_->bytes() : 0) + (incomplete_ ? incomplete_->bytes() : 0) +
         (local_ ? local_->bytes() : 0);
}

}  // namespace acdf
