#include "acdf/envmap/environment_light.h"

#include <cmath>
#include <stdexcept>
#include <utility>

namespace acdf {

void validate(const EnvironmentLightOptions& o) {
  if (!(o.scale > 0.0f) || !std::isfinite(o.scale))
    throw OptionError("environment light", "scale", "must be finite and > 0, got " + OptionError::number(o.scale));
  validate(o.simplify);
  validate(o.local);
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
  const EnvironmentTable::Sample s =
      usesLocal(context) ? local_->sampleInCell(localCell(context), u0, u1) : table(context).sample(u0, u1);
  if (!(s.pdf > 0)) return {};
  const Rgb L = map_->radiance(s.pixel);
  const float k = options_.scale;
  return {options_.worldFromMap.apply(s.direction), {k * L.r, k * L.g, k * L.b}, s.pdf};
}

LightSampleContext EnvironmentLight::atNormal(LightSampleContext context, const Vec3d& normal) const {
  context.normal = normal;
  context.localCell.reset();
  if (local_) context.localCell = localCell(context);
  return context;
}

double EnvironmentLight::pdf(const LightSampleContext& context, const Vec3d& w) const {
  const PixelIndex p = map_->mapping().pixelOf(options_.worldFromMap.applyInverse(w));
  if (const std::optional<double> local = localPdf(context, p)) return *local;
  return table(context).pdf(p);
}

Rgb EnvironmentLight::eval(const Vec3d& w) const {
  return scaled(map_->radiance(options_.worldFromMap.applyInverse(w)));
}

RadianceAndPdf EnvironmentLight::evalWithPdf(const LightSampleContext& context, const Vec3d& w) const {
  const Vec3d mapDirection = options_.worldFromMap.applyInverse(w);
  const PixelIndex p = map_->mapping().pixelOf(mapDirection);
  const std::optional<double> local = localPdf(context, p);
  // The light's tables are of its map's size, so this pixel is theirs too.
  return {scaled(map_->radiance(p)), local ? *local : table(context).pdf(p)};
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
