#pragma once
// An environment light: an EnvironmentMap placed in the world (rotation, scale) and sampled with
// the tables of one strategy (environment_table.h). The light alone owns the placement: its
// tables work in the map's frame and are shared by lights of any rotation and scale, so a light
// is cheap to make once its tables exist.
//
// Complete and incomplete pdfs (pbrt-v4's allowIncompletePDF). A Compensated table has pdf 0
// where the map is dimmer than its mean: right for an estimator that combines light samples with
// BSDF samples by MIS (the BSDF samples cover those directions), biased for one that uses light
// samples alone. So a compensated light keeps the complete table (Adaptive) beside it and every
// sample() / pdf() says which it may use (LightSampleContext::allowIncompletePdf); the two must
// agree within one estimator. Every other strategy's table is complete and serves both.
//
// Local sampling (local_environment_table.h) draws from L(ω) max(0, n · ω) for the shading normal
// n the call gives (LightSampleContext::normal); its pdf is positive wherever that product is, so
// it is complete for any estimator of reflected light. A call without a normal (a light-only
// estimate of something other than a surface's reflection, a test) falls back to the complete
// Adaptive table the light keeps beside it; sample() and pdf() of one estimator must then agree on
// giving the normal or not, as they must on allowIncompletePdf. LocalCompensated's per-normal
// tables are incomplete (compensated): calls that need a complete pdf get the Adaptive table too.

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "acdf/envmap/environment_map.h"
#include "acdf/envmap/environment_table.h"
#include "acdf/envmap/local_environment_table.h"
#include "acdf/envmap/portal_table.h"
#include "acdf/sampling/rgb.h"
#include "acdf/sampling/transform.h"

namespace acdf {

// A rectangle the map is seen through from inside a closed space (a window, a door): corner +
// s·edgeU + t·edgeV for s, t in [0, 1], world frame, edges perpendicular. Light from the map passes
// it towards the side edgeU × edgeV points to (into the room). Declaring it adds a technique to
// the light's sampling, no geometry: the walls around it are the scene's.
struct Portal {
  Vec3d corner, edgeU, edgeV;
};
// Why a portal cannot be used (an edge zero or not finite, edges not perpendicular), or none.
std::optional<std::string> portalProblem(const Portal& portal);

struct EnvironmentLightOptions {
  EnvironmentSampling strategy = EnvironmentSampling::Adaptive;
  SimplifyOptions simplify{};       // Adaptive, Compensated and Local
  Rotation worldFromMap{};          // the map frame's directions in the world (default: the same)
  float scale = 1.0f;               // radiance multiplier; finite and > 0
  LocalEnvironmentOptions local{};  // Local: the normal grid and blocks
  std::vector<Portal> portals{};    // see Portal and EnvironmentLight::sample
};

// The one check of these options, for the light and the scene loader. Throws OptionError
// ("scale", or the simplify or local options' own).
void validate(const EnvironmentLightOptions& options);

// The portals of one light as seen from one point, found once for the calls there by
// EnvironmentLight::atPosition: each portal's view (PortalTable::View: its window, and the light
// through it, 0 for one whose inner side the point is not on) and the sum of that light. Only the
// light fills one, and a call uses it only from that light and at the position it was found for: a
// context moved to another position or given to another light has its portals found again by each
// call, never a stale view.
class PortalsSeen {
 public:
  // The portals whose views are kept, inline: scenes declare a few windows and doors. For a light
  // with more, the sum still covers all, and the calls find the other views where they need them.
  static constexpr std::size_t kCapacity = 8;

 private:
  friend class EnvironmentLight;
  Vec3d from_;                                   // the point they are seen from
  std::uint64_t light_ = 0;                      // the light's identity (EnvironmentLight::id_)
  double total_ = 0;                                  // Σ of the portals' power
  std::array<PortalTable::View, kCapacity> views_{};  // of the first kCapacity portals
};

// The local table's normal cell of one shading normal, found once for the calls there by
// EnvironmentLight::atNormal. Like PortalsSeen, a call uses it only from the light that found it
// and for the normal it was found for: a context given another normal or another light finds the
// cell again, never a stale one (another light's grid may have other cells).
class LocalCellFound {
 private:
  friend class EnvironmentLight;
  Vec3d normal_;             // world frame
  std::uint64_t light_ = 0;  // EnvironmentLight::id_
  std::size_t cell_ = 0;
};

// The map pixel along one world direction, found by EnvironmentLight::prefetch before a ray along
// it is traced. Like LocalCellFound, used only by the light that found it and for that direction:
// the pixel depends on nothing else, so it is never stale.
class EscapePixelFound {
 private:
  friend class EnvironmentLight;
  Vec3d direction_;
  std::uint64_t light_ = 0;  // EnvironmentLight::id_
  PixelIndex pixel_;
};

// What a light sample or pdf depends on besides its variates or direction.
struct LightSampleContext {
  // True when another technique samples every direction the light lights (BSDF sampling, the
  // estimator combining both by MIS): the light may then leave out what it covers (compensated).
  bool allowIncompletePdf = false;
  // The shading normal of the point lit (world frame, non-zero): Local sampling's condition.
  std::optional<Vec3d> normal = std::nullopt;
  // The local table's normal cell of `normal`, found once for the calls of one shading point by
  // EnvironmentLight::atNormal; without it (or with one found elsewhere) each call finds the cell.
  std::optional<LocalCellFound> localCell = std::nullopt;
  // The point lit (world frame): what the portals are seen from. Without it no portal is used.
  std::optional<Vec3d> position = std::nullopt;
  // The portals seen from `position`, found once for the calls of one shading point by
  // EnvironmentLight::atPosition; without it (or with one found elsewhere) each call finds them.
  std::optional<PortalsSeen> portals = std::nullopt;
  // The pixel of the direction last prefetched (EnvironmentLight::prefetch), for evalWithPdf.
  std::optional<EscapePixelFound> escape = std::nullopt;
};

struct LightSample {
  Vec3d direction;  // world frame, unit length
  Rgb radiance;     // scale × the pixel's radiance
  double pdf = 0;   // per steradian; 0 only for a light that emits nothing
};

// A light sample before its radiance is read: EnvironmentLight::sampleDirection() finds the
// direction and its density and starts loading the pixel's radiance, which radiance(pixel) reads
// later. A path tracer reads it after the shadow ray, whose trace then hides the map's cache miss
// (the map is megabytes; the read had stalled 4 % of a spheres render and 6 % behind the door).
struct LightDirection {
  Vec3d direction;                  // world frame, unit length
  double pdf = 0;                   // per steradian
  std::optional<PixelIndex> pixel;  // the map pixel it lies in; none where nothing was drawn
};

// What arrives from a direction, and the density sample() gives it.
struct RadianceAndPdf {
  Rgb radiance;
  double pdf = 0;
};

// The calls a light will serve: with LightSampleContext::allowIncompletePdf false, true, or
// either. A light gets only the tables those calls use.
enum class LightPdfs { Complete, Incomplete, Either };

// A table of the light's map for a strategy and simplify options: built, or shared from a cache.
using EnvironmentTableSource =
    std::function<std::shared_ptr<const EnvironmentTable>(EnvironmentTableStrategy strategy, const SimplifyOptions&)>;

class EnvironmentLight {
 public:
  // Builds its own tables, for calls of either kind. Throws std::invalid_argument for no map, a
  // bad scale or bad simplify options (or what a table's constructor throws).
  explicit EnvironmentLight(std::shared_ptr<const EnvironmentMap> map, EnvironmentLightOptions options = {});
  // The tables the calls `pdfs` use, from `tables` (which must give tables of `map`'s size; the
  // same pixels are the source's concern, e.g. a cache key). A Local light builds its local
  // table itself: its slices are built lazily, all 2048 of a 1024 × 512 map in a third of a
  // second, so they are not worth a cache file.
  EnvironmentLight(std::shared_ptr<const EnvironmentMap> map, EnvironmentLightOptions options, LightPdfs pdfs,
                   const EnvironmentTableSource& tables);

  // u0, u1 in [0, 1) (clamped into it, uniform-sphere sampling aside).
  //
  // Portals. From a position on the inner side of at least one portal, sample() draws from the
  // one-sample mixture  p(ω) = c · p_portals(ω) + (1 − c) · p_table(ω), c = portalShare(context):
  // p_portals picks a portal with probability proportional to the map's light through it from
  // the point (P_i, its view's power), then a direction through it with density ∝ luminance
  // (PortalTable), so p_portals(ω) = Σ_i f_i(ω) / Σ P_i over the seen portals ω passes through,
  // f_i the portal's table per steradian; p_table is the strategy's own density. u0 chooses the
  // technique (and the portal) and is rescaled for it. pdf() and evalWithPdf() return the
  // mixture, so MIS against BSDF sampling weighs it whole. Elsewhere (no position, behind every
  // portal) the light samples as without portals. atPosition() finds the portals' views once for
  // the calls of a shading point.
  LightSample sample(const LightSampleContext& context, float u0, float u1) const;
  // sample() without its radiance, which radiance(*pixel) gives, bit for bit (see LightDirection).
  LightDirection sampleDirection(const LightSampleContext& context, float u0, float u1) const;
  // The scaled radiance of map pixel p.
  Rgb radiance(PixelIndex p) const;
  // c: where the caller combines light and BSDF samples by MIS (allowIncompletePdf), the portals
  // take every light sample: directions through no portal (a skylight left out) are left to BSDF
  // samples, as the compensated table leaves them the map's dim half, and no table pdf is looked
  // up for a portal's sample (in the room and behind the door ajar, 1.13–1.14× the efficiency of
  // c = 0.9). Else kPortalShare, the table keeping the mixture complete.
  static constexpr double kPortalShare = 0.9;
  static double portalShare(const LightSampleContext& context) {
    return context.allowIncompletePdf ? 1.0 : kPortalShare;
  }
  // Density per steradian of sample(context, ·) at the world direction w (non-zero).
  double pdf(const LightSampleContext& context, const Vec3d& w) const;
  // `context` at the shading normal `normal` (world frame, non-zero), with its local table cell
  // (Local only) found once for every call there.
  LightSampleContext atNormal(const LightSampleContext& context, const Vec3d& normal) const;
  // `context` at the point `position` (world frame), with its portals' views found once for every
  // call there.
  LightSampleContext atPosition(const LightSampleContext& context, const Vec3d& position) const;
  // atPosition(atNormal(context, normal), position), in place: a path tracer moves one context
  // from vertex to vertex, and copying it (with the portals' views) twice per vertex costs
  // more than finding what changed.
  void moveTo(LightSampleContext& context, const Vec3d& position, const Vec3d& normal) const;
  // Radiance arriving from the world direction w (non-zero): nearest pixel, times the scale.
  Rgb eval(const Vec3d& w) const;
  // eval(w) and pdf(context, w), bit for bit, finding w's pixel once: an escaped ray needs both.
  RadianceAndPdf evalWithPdf(const LightSampleContext& context, const Vec3d& w) const;
  // Finds w's pixel into `context` and starts loading its radiance, for an evalWithPdf(context, w)
  // after a ray along w has been traced and escaped: the map is megabytes, so the pixel is usually
  // a cache miss, which the trace then hides (spheres: 5 % of the render's time).
  void prefetch(LightSampleContext& context, const Vec3d& w) const;

  // The table sample() and pdf() use in `context` (for Local, the Adaptive one of calls without a
  // normal). Throws std::logic_error for a context the light was not made for (a complete pdf
  // from a light made for incomplete ones only).
  const EnvironmentTable& table(const LightSampleContext& context) const;
  // True for a black map (and one whose every pixel underflows in its tables): nothing to sample.
  bool emitsNothing() const;
  const EnvironmentMap& map() const { return *map_; }
  const EnvironmentLightOptions& options() const { return options_; }
  // Local only (else null): the table of the calls with a normal.
  const LocalEnvironmentTable* localTable() const { return local_.get(); }
  // Portal i's table (options().portals[i]).
  const PortalTable& portalTable(std::size_t i) const { return *portals_[i]; }
  // Bytes of the tables the light holds (0 for uniform-sphere sampling; the local slices built so
  // far; the portals').
  std::size_t tableBytes() const;

 private:
  // atPosition and atNormal of `context` itself.
  void movePosition(LightSampleContext& context, const Vec3d& position) const;
  void moveNormal(LightSampleContext& context, const Vec3d& normal) const;
  Rgb scaled(const Rgb& L) const;
  // The map pixel of the world direction w; the second as prefetch() found it into `context`, or
  // found now.
  PixelIndex pixelOf(const Vec3d& w) const;
  PixelIndex pixelOf(const LightSampleContext& context, const Vec3d& w) const;
  // Local's density at map pixel p in a call with a normal (the pixel alone does not give it),
  // else none.
  std::optional<double> localPdf(const LightSampleContext& context, PixelIndex p) const;
  // Whether calls in `context` use the local table: a local light's calls with a normal, those of a
  // compensated one only when they allow an incomplete pdf.
  bool usesLocal(const LightSampleContext& context) const;
  // The local table's normal cell of a context with a normal (Local only).
  std::size_t localCell(const LightSampleContext& context) const;
  // The strategy's density at pixel p (the table's, or the local one's).
  double strategyPdf(const LightSampleContext& context, PixelIndex p) const;
  // Portal i's view as `seen` keeps it, or found now for a portal beyond its capacity.
  PortalTable::View portalView(const PortalsSeen& seen, std::size_t i) const;
  // Every portal's view from `position`, into `seen`.
  void see(PortalsSeen& seen, const Vec3d& position) const;
  // use(the portals seen from the context's position): atPosition's when they are this light's at
  // that position, else found now; null without a position or a portal seen from it. The views
  // found now live in this call's frame, built only then (GCC zeroes an empty std::optional of
  // them, 368 bytes, on construction: measurable on every call of a light without portals).
  template <class Use>
  auto withPortalsSeen(const LightSampleContext& context, Use&& use) const;
  // sampleDirection() with the portals seen from the context's position (null: none).
  LightDirection sampleDirectionWith(const LightSampleContext& context, const PortalsSeen* seen, float u0,
                                     float u1) const;
  // The mixture's density at the world direction w of pixel p, the portals `seen` from the
  // context's position (null: the strategy's alone; see sample()).
  double mixturePdf(const LightSampleContext& context, const PortalsSeen* seen, const Vec3d& w, PixelIndex p) const;

  std::shared_ptr<const EnvironmentMap> map_;
  EnvironmentLightOptions options_;
  // complete_ serves calls that need a complete pdf; incomplete_, when set (Compensated), those
  // that allow an incomplete one. Either may be null when no call will need it.
  std::shared_ptr<const EnvironmentTable> complete_, incomplete_;
  std::shared_ptr<const LocalEnvironmentTable> local_;
  std::vector<std::shared_ptr<const PortalTable>> portals_;  // one per options_.portals
  // Distinct for every light constructed (a copy shares its portals and so its identity): what
  // PortalsSeen::light_ holds.
  std::uint64_t id_;
};

}  // namespace acdf
