#pragma once
// The techniques a path vertex draws directions with, each with its density beside it, and the
// one-sample mixture of a technique with a learned field (guiding_field.h).
//
// A technique (BsdfTechnique, LightTechnique) answers
//   sample(u0, u1) → TechniqueSample: a world direction, the technique's value along it, and the
//                    density it was drawn with (0: nothing drawn);
//   along(ω)       → ValueAndPdf: its value along ω and the density sample() gives ω;
//   pdf(ω)         → that density alone;
// where the value is the factor of the integrand the technique knows: f · cosθ for the BSDF at a
// vertex, the environment's radiance for the light. An estimate divides it by the density.
//
// GuidedMixture mixes a technique of density p with a field of density p_F, which knows directions
// but no values:
//   q(ω) = c · p(ω) + (1 − c) · p_F(ω),      c = the technique's share,
// u0 choosing between them (rescaledVariate) and the value always the technique's, the field's
// directions evaluated by it. The field only adds density, so wherever p covers the integrand q
// does; q replaces p in sample(), along() and pdf(), hence in every MIS weight. Without a field
// the mixture is the technique itself.

#include "acdf/brdf/brdf_sampler.h"
#include "acdf/envmap/environment_light.h"
#include "acdf/integrator/guiding_field.h"
#include "acdf/sampling/frame.h"
#include "acdf/sampling/sample.h"

namespace acdf {

// A drawn direction, its density, and the technique's value along it, which value() reads. The
// BSDF's value is known when it draws; the light's is a pixel of its map, whose radiance the draw
// only starts loading (LightDirection), so that a path reading it after the shadow ray finds it there.
class TechniqueSample {
 public:
  TechniqueSample() = default;
  TechniqueSample(const Vec3d& direction, const Rgb& value, double pdf)
      : direction(direction), pdf(pdf), value_(value) {}
  TechniqueSample(const EnvironmentLight& light, const LightDirection& drawn)
      : direction(drawn.direction), pdf(drawn.pixel ? drawn.pdf : 0.0), light_(&light), pixel_(drawn.pixel) {}

  Rgb value() const { return light_ ? (pixel_ ? light_->radiance(*pixel_) : Rgb{}) : value_; }

  Vec3d direction;  // world frame, unit
  double pdf = 0;   // per steradian; 0: nothing drawn

 private:
  Rgb value_;
  const EnvironmentLight* light_ = nullptr;
  std::optional<PixelIndex> pixel_;
};

struct ValueAndPdf {
  Rgb value;
  double pdf = 0;
};

// The BSDF at a vertex: f · cosθ (0 below the surface).
class BsdfTechnique {
 public:
  BsdfTechnique(const BrdfVertex& material, const Frame& frame) : material_(material), frame_(frame) {}

  TechniqueSample sample(float u0, float u1) const {
    const BrdfSample s = material_.sample(u0, u1);
    if (!(s.pdf > 0) || s.weight.isBlack()) return {};
    // The sample's weight is f · cosθ / pdf.
    return {normalize(frame_.toWorld(s.wi)), s.weight * static_cast<float>(s.pdf), s.pdf};
  }
  ValueAndPdf along(const Vec3d& w) const {
    const Vec3d wi = frame_.toLocal(w);
    if (!(wi.z > 0)) return {Rgb{}, material_.pdf(wi)};
    return {material_.eval(wi) * static_cast<float>(wi.z), material_.pdf(wi)};
  }
  double pdf(const Vec3d& w) const { return material_.pdf(frame_.toLocal(w)); }

 private:
  const BrdfVertex& material_;
  const Frame& frame_;
};

// The environment light seen from a point (LightSampleContext): its radiance.
class LightTechnique {
 public:
  LightTechnique(const EnvironmentLight& light, const LightSampleContext& context) : light_(light), context_(context) {}

  TechniqueSample sample(float u0, float u1) const { return {light_, light_.sampleDirection(context_, u0, u1)}; }
  ValueAndPdf along(const Vec3d& w) const {
    const RadianceAndPdf r = light_.evalWithPdf(context_, w);
    return {r.radiance, r.pdf};
  }
  double pdf(const Vec3d& w) const { return light_.pdf(context_, w); }

 private:
  const EnvironmentLight& light_;
  const LightSampleContext& context_;
};

template <class Technique>
class GuidedMixture {
 public:
  // `field` may be none (the technique alone); `share` in (0, 1) is the technique's.
  GuidedMixture(const Technique& technique, DirectionalDistribution field, double share)
      : technique_(technique), field_(field), share_(share) {}

  TechniqueSample sample(float u0, float u1) const {
    if (!field_) return technique_.sample(u0, u1);
    if (u0 < share_) {
      TechniqueSample s = technique_.sample(rescaledVariate(u0, share_), u1);
      if (s.pdf > 0) s.pdf = mixed(s.pdf, field_.pdf(s.direction));
      return s;
    }
    const DirectionalDistribution::DirectionAndPdf g = field_.sample(rescaledVariate(u0, share_), u1);
    const ValueAndPdf own = technique_.along(g.direction);
    return {g.direction, own.value, mixed(own.pdf, g.pdf)};
  }
  ValueAndPdf along(const Vec3d& w) const {
    ValueAndPdf own = technique_.along(w);
    if (field_) own.pdf = mixed(own.pdf, field_.pdf(w));
    return own;
  }
  double pdf(const Vec3d& w) const {
    const double own = technique_.pdf(w);
    return field_ ? mixed(own, field_.pdf(w)) : own;
  }

 private:
  double mixed(double own, double field) const { return share_ * own + (1.0 - share_) * field; }

  Technique technique_;
  DirectionalDistribution field_;
  double share_;
};

}  // namespace acdf
