#pragma once
// The interface every BRDF model implements, measured (MerlBrdf) or analytic (AnalyticBrdf,
// LambertianBrdf): what the samplers (brdf_sampler.h) sample and the renderer evaluates.
//
// Directions are unit vectors in the local shading frame (z = the normal, sphere.h), in pbrt's
// argument order: ωo (towards the viewer) first, then ωi (towards the light). Values are linear RGB
// in 1/sr, 0 unless both directions are strictly above the horizon. Implementations are immutable
// after construction, so every method may be called from any number of threads.
//
// What tabulation (TabulatedBrdfSampler) needs beyond f, so that a table of any model is as fast
// and as exact to build as MERL's:
//   isotropic()     f depends on the azimuths only through φi − φo. Such a model is tabulated on
//                   a lattice of (θo, θh, Δφ) through evalHalfDiff() (a 4D table reuses it for
//                   every φo) and may use the isotropic table layout; any other model is
//                   evaluated at each 4D point through luminance().
//   evalHalfDiff()  f at Rusinkiewicz angles (coordinates.h) with φh = 0, for isotropic models;
//                   by default eval() at fromHalfDiff(), overridden where the model is defined
//                   in these angles (MERL reads its table cell directly).
//   addToKey()      what the values depend on, for the table cache's keys (docs/table-cache.md).

#include <memory>
#include <string>

#include "acdf/sampling/rgb.h"
#include "acdf/sampling/sphere.h"
#include "acdf/sampling/table_cache.h"

namespace acdf {

class BrdfSampler;

class BrdfModel {
 public:
  virtual ~BrdfModel() = default;

  // f(ωo, ωi) in 1/sr.
  virtual Rgb eval(const Vec3d& wo, const Vec3d& wi) const = 0;
  // Its luminance (Rgb::luminance), what importance sampling follows.
  virtual float luminance(const Vec3d& wo, const Vec3d& wi) const { return eval(wo, wi).luminance(); }
  virtual bool isotropic() const = 0;

  // f at half/difference angles (φh = 0). Isotropic models only; no horizon test beyond eval()'s.
  virtual Rgb evalHalfDiff(double thetaHalf, double thetaDiff, double phiDiff) const;

  // Hashes the model's data into `content` and returns its parameters as exact text (hex floats),
  // starting with a word no other model uses, e.g. "analytic-ggx conductor alpha=0x1.3333333333333p-3 ...".
  // Two models with the same content and text evaluate alike everywhere.
  virtual std::string addToKey(ContentHash& content) const = 0;

  // The sampler the model's own data or formula gives (an RGL file's warps, GGX's distribution of
  // normals), or null for a model without one. `self` is this model, whose ownership the sampler
  // shares (std::invalid_argument otherwise).
  virtual std::shared_ptr<const BrdfSampler> nativeSampler(const std::shared_ptr<const BrdfModel>& self) const;
};

// Throws std::invalid_argument unless `self` points to `model` (nativeSampler's precondition).
void checkIsSelf(const BrdfModel& model, const std::shared_ptr<const BrdfModel>& self);

}  // namespace acdf
