#include "acdf/envmap/environment_light.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "acdf/sampling/sample.h"

namespace acdf {

namespace {
std::uint64_t newLightId() {
  static std::atomic<std::uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
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
    : map_(std::move(map)), options_(std::move(options)), id_(newLightId()) {
  if (!map_) throw std::invalid_argument("EnvironmentLight: no map");
  validate(options_);
  for (const Portal& portal : options_.portals)
    portals_.push_back(std::make_shared<const PortalTable>(portal, *map_, options_.worldFromMap, options_.simplify));
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

template <class Use>
auto EnvironmentLight::withPortalsSeen(const LightSampleContext& context, Use&& use) const {
  if (options_.portals.empty() || !context.position) return use(nullptr);
  const std::optional<PortalsSeen>& kept = context.portals;
  if (kept && kept->light_ == id_ && kept->from_ == *context.position)
    return use(kept->total_ > 0 ? &*kept : nullptr);
  PortalsSeen found;
  see(found, *context.position);
  return use(found.total_ > 0 ? &found : nullptr);
}

LightSample EnvironmentLight::sample(const LightSampleContext& context, float u0, float u1) const {
  const LightDirection drawn = sampleDirection(context, u0, u1);
  if (!drawn.pixel) return {};
  return {drawn.direction, radiance(*drawn.pixel), drawn.pdf};
}

LightDirection EnvironmentLight::sampleDirection(const LightSampleContext& context, float u0, float u1) const {
  return withPortalsSeen(context,
                         [&](const PortalsSeen* seen) { return sampleDirectionWith(context, seen, u0, u1); });
}

Rgb EnvironmentLight::radiance(PixelIndex p) const { return scaled(map_->radiance(p)); }

LightDirection EnvironmentLight::sampleDirectionWith(const LightSampleContext& context, const PortalsSeen* seen,
                                                     float u0, float u1) const {
  if (seen) {
    if (emitsNothing()) return {};
    const double u = clampUnit(u0), share = portalShare(context);
    if (u < share) {
      // The seen portal whose share of Σ P_i holds u, and u rescaled into that share (the last
      // seen one takes what rounding leaves over, at its far end).
      double at = u / share * seen->total_;
      std::size_t chosen = 0;
      PortalTable::View view;
      for (std::size_t i = 0; i < options_.portals.size(); ++i) {
        const PortalTable::View next = portalView(*seen, i);
        if (!(next.power > 0)) continue;
        at -= view.power;  // past the one before
        chosen = i;
        view = next;
        if (at < view.power) break;
      }
      const Vec3d w = portals_[chosen]->sample(view, std::clamp(at / view.power, 0.0, 1.0), clampUnit(u1));
      const PixelIndex p = pixelOf(w);
      map_->prefetchRadiance(p);
      return {w, mixturePdf(context, seen, w, p), p};
    }
    u0 = rescaledVariate(u, share);
  }
  const EnvironmentTable::Sample s =
      usesLocal(context) ? local_->sampleInCell(localCell(context), u0, u1) : table(context).sample(u0, u1);
  if (!(s.pdf > 0)) return {};
  map_->prefetchRadiance(s.pixel);
  const Vec3d w = options_.worldFromMap.apply(s.direction);
  return {w, seen ? mixturePdf(context, seen, w, s.pixel) : s.pdf, s.pixel};
}

PortalTable::View EnvironmentLight::portalView(const PortalsSeen& seen, std::size_t i) const {
  return i < PortalsSeen::kCapacity ? seen.views_[i] : portals_[i]->viewFrom(seen.from_);
}

void EnvironmentLight::see(PortalsSeen& seen, const Vec3d& position) const {
  seen.from_ = position;
  seen.light_ = id_;
  for (std::size_t i = 0; i < portals_.size(); ++i) {
    const PortalTable::View view = portals_[i]->viewFrom(position);
    if (i < PortalsSeen::kCapacity) seen.views_[i] = view;
    seen.total_ += view.power;
  }
}

double EnvironmentLight::strategyPdf(const LightSampleContext& context, PixelIndex p) const {
  const std::optional<double> local = localPdf(context, p);
  // The light's tables are of its map's size, so this pixel is theirs too.
  return local ? *local : table(context).pdf(p);
}

double EnvironmentLight::mixturePdf(const LightSampleContext& context, const PortalsSeen* seen, const Vec3d& w,
                                    PixelIndex p) const {
  if (!seen) return strategyPdf(context, p);
  // p_portals(w): the seen portals' tables per steradian at w, where w passes through, over Σ P_i.
  double through = 0;
  for (std::size_t i = 0; i < portals_.size(); ++i) {
    const PortalTable::View view = portalView(*seen, i);
    if (view.power > 0) through += portals_[i]->densityThrough(view.window, w);
  }
  const double share = portalShare(context);
  return share * (through / seen->total_) + (share < 1.0 ? (1.0 - share) * strategyPdf(context, p) : 0.0);
}

LightSampleContext EnvironmentLight::atPosition(const LightSampleContext& context, const Vec3d& position) const {
  LightSampleContext at = context;
  movePosition(at, position);
  return at;
}

LightSampleContext EnvironmentLight::atNormal(const LightSampleContext& context, const Vec3d& normal) const {
  LightSampleContext at = context;
  moveNormal(at, normal);
  return at;
}

void EnvironmentLight::moveTo(LightSampleContext& context, const Vec3d& position, const Vec3d& normal) const {
  moveNormal(context, normal);
  movePosition(context, position);
}

void EnvironmentLight::movePosition(LightSampleContext& context, const Vec3d& position) const {
  context.position = position;
  context.portals.reset();
  if (!options_.portals.empty()) see(context.portals.emplace(), position);  // in place, not a 368-byte copy
}

void EnvironmentLight::moveNormal(LightSampleContext& context, const Vec3d& normal) const {
  context.normal = normal;
  context.localCell.reset();
  if (local_) {
    LocalCellFound found;
    found.normal_ = normal;
    found.light_ = id_;
    found.cell_ = localCell(context);
    context.localCell = found;
  }
}

double EnvironmentLight::pdf(const LightSampleContext& context, const Vec3d& w) const {
  const PixelIndex p = pixelOf(w);
  return withPortalsSeen(context, [&](const PortalsSeen* seen) { return mixturePdf(context, seen, w, p); });
}

Rgb EnvironmentLight::eval(const Vec3d& w) const {
  return scaled(map_->radiance(options_.worldFromMap.applyInverse(w)));
}

void EnvironmentLight::prefetch(LightSampleContext& context, const Vec3d& w) const {
  EscapePixelFound& found = context.escape.emplace();
  found.direction_ = w;
  found.light_ = id_;
  found.pixel_ = pixelOf(w);
  map_->prefetchRadiance(found.pixel_);
}

PixelIndex EnvironmentLight::pixelOf(const Vec3d& w) const {
  return map_->mapping().pixelOf(options_.worldFromMap.applyInverse(w));
}

PixelIndex EnvironmentLight::pixelOf(const LightSampleContext& context, const Vec3d& w) const {
  const std::optional<EscapePixelFound>& kept = context.escape;
  if (kept && kept->light_ == id_ && kept->direction_ == w) return kept->pixel_;
  return pixelOf(w);
}

RadianceAndPdf EnvironmentLight::evalWithPdf(const LightSampleContext& context, const Vec3d& w) const {
  const PixelIndex p = pixelOf(context, w);
  // The pdf's search first, while the pixel's radiance (usually a cache miss) is on its way.
  map_->prefetchRadiance(p);
  const double pdf =
      withPortalsSeen(context, [&](const PortalsSeen* seen) { return mixturePdf(context, seen, w, p); });
  return {scaled(map_->radiance(p)), pdf};
}

std::optional<double> EnvironmentLight::localPdf(const LightSampleContext& context, PixelIndex p) const {
  if (!usesLocal(context)) return std::nullopt;
  return local_->pdfInCell(localCell(context), p);
}

bool EnvironmentLight::usesLocal(const LightSampleContext& context) const {
  return local_ && context.normal && (context.allowIncompletePdf || !local_->compensated());
}

std::size_t EnvironmentLight::localCell(const LightSampleContext& context) const {
  const std::optional<LocalCellFound>& kept = context.localCell;
  if (kept && kept->light_ == id_ && kept->normal_ == *context.normal) return kept->cell_;
  return local_->sliceOf(options_.worldFromMap.applyInverse(*context.normal));
}

Rgb EnvironmentLight::scaled(const Rgb& L) const {
  const float k = options_.scale;
  return {k * L.r, k * L.g, k * L.b};
}

bool EnvironmentLight::emitsNothing() const {
  return (!complete_ || complete_->emitsNothing()) && (!incomplete_ || incomplete_->emitsNothing());
}

std::size_t EnvironmentLight::tableBytes() const {
  std::size_t bytes = (complete_ ? complete_->bytes() : 0) + (incomplete_ ? incomplete_->bytes() : 0) +
                      (local_ ? local_->bytes() : 0);
  for (const auto& portal : portals_) bytes += portal->table().bytes();
  return bytes;
}

}  // namespace acdf
