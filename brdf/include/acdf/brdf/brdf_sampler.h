#pragma once
// The interface every BRDF importance sampler implements: given the outgoing direction ωo,
// choose an incident direction ωi with a known density, and report the Monte Carlo weight
// f(ωo, ωi)·cosθi / pdf(ωi) a renderer multiplies the incident radiance by. With eval() beside
// sample() and pdf(), a sampler is everything a renderer asks of a surface (Nori's BSDF): the
// renderer's materials are BrdfSamplers of their models.
//
// Directions are unit vectors in the local shading frame (z = the normal, sphere.h). Densities
// are per steradian over the whole sphere: a sampler may return an ωi below the horizon (where
// f = 0, so its weight is 0) and pdf() integrates to 1 over the sphere. That keeps pdf() exact
// for samplers that reflect ωo about a sampled half vector, whose image is not confined to the
// upper hemisphere. For ωo at or below the horizon the BRDF is 0; samplers then fall back to
// cosine-weighted sampling, so sample() still returns a valid direction with a positive pdf.
//
// sample() reports the density at the direction it drew, computed along its sampling path (the
// table cell, the warps' densities at the sampled values), not recomputed from ωi: that inversion
// costs as much again. pdf(ωo, ωi) is the density of ωi, for MIS. The two agree on every sample,
// |pdf(ωo, s.wi) − s.pdf| ≤ kPdfRoundTrip · s.pdf for s = sample(ωo, u): a sampler whose density
// is constant on cells keeps its samples a margin inside their cell, so that pdf() finds the same
// cell again from ωi, and a half-vector sampler reports pdf() itself where ωi does not determine
// ωh well enough (reflected()). The exception is RGL's warps, whose round trip inverts a float
// bilinear warp: at the extreme variates, on an edge of their domain, they agree less closely
// (rgl_sampler_test.cpp).
//
// A sampler shares ownership of its model: the model lives as long as any sampler of it (a
// renderer's materials, a table cache's samplers, a binding's objects), and several samplers, or
// models of one MERL file with different interpolations, share one copy of the data.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "acdf/brdf/brdf_model.h"
#include "acdf/brdf/half_vector.h"
#include "acdf/sampling/rgb.h"
#include "acdf/sampling/sphere.h"

namespace acdf {

// A direction drawn by a sampler with its density per steradian: of the whole sampler (every
// mixture component included) at wi, finite and > 0.
struct SampledDirection {
  Vec3d wi;  // unit vector
  double pdf = 0;
};

// Cosine-weighted hemisphere sampling with its density cosθi/π: the cosine sampler, and every
// sampler's fallback for ωo at or below the horizon.
inline SampledDirection sampleCosineDirection(float u0, float u1) {
  const Vec3d wi = sampleCosineHemisphere(u0, u1);
  return {wi, cosineHemispherePdf(wi.z)};
}

struct BrdfSample {
  Vec3d wi;        // unit vector
  Rgb weight;      // f(ωo, ωi)·max(cosθi, 0) / pdf
  double pdf = 0;  // per steradian, finite and > 0
};

// How a sampler's density at one ωo above the horizon is made, for the χ² test's expected counts
// (brdf_chi_square.h): `cosineShare` of it cosine-weighted, the rest the reflection about ωo of a
// half-vector density over the upper hemisphere, integrated on sCells × phiCells cells in
// (s = √(θh / (π/2)), φh − phiOrigin) fine enough to resolve it.
struct HalfVectorDensity {
  double cosineShare = 1;
  uint32_t sCells = 0, phiCells = 0;
  double phiOrigin = 0;
  // Constant per cell (a table's, on its own cells), so one evaluation at the centre gives the
  // cell's mass; otherwise (a smooth density) each sub-cell is weighted by the density at its
  // jittered point.
  bool constantPerCell = false;
  std::function<double(const Vec3d& wh)> density;  // per steradian of ωh
  // Smooth densities only: sub-cells uniform in (s, φh) instead of solid angle, each weighted by
  // the density per unit (s, φh) area, p(ωh) sinθh dθh/ds = p(ωh) sinθh π s — bounded where
  // p(ωh) per steradian is not (the RGL warps' p ~ 1/s² at the pole).
  bool uniformInS = false;
};

class BrdfSampler;

// A sampler at one shading vertex: ωo, and what the sampler finds from ωo alone (a tabulated
// sampler's conditioning slice), found once and shared by every sample, pdf and eval there (a
// product estimator's candidates and the path's continuation). Made by BrdfSampler::vertex;
// valid while its sampler lives. Its answers are the sampler's per-call ones, bit for bit.
class BrdfVertex {
 public:
  // u0, u1 in [0, 1) (clamped into it).
  BrdfSample sample(float u0, float u1) const;
  // sample() without f and the weight: for a caller that evaluates f itself, once.
  SampledDirection sampleDirection(float u0, float u1) const;
  double pdf(const Vec3d& wi) const;
  Rgb eval(const Vec3d& wi) const;

  const Vec3d& wo() const { return wo_; }
  // The sampler's conditioning cell of ωo; 0 for a sampler without one.
  std::size_t slice() const { return slice_; }

 private:
  friend class BrdfSampler;
  BrdfVertex(const BrdfSampler& sampler, const Vec3d& wo, std::size_t slice)
      : sampler_(&sampler), wo_(wo), slice_(slice) {}

  const BrdfSampler* sampler_;
  Vec3d wo_;
  std::size_t slice_;
};

class BrdfSampler {
 public:
  // Throws std::invalid_argument for a null model.
  explicit BrdfSampler(std::shared_ptr<const BrdfModel> model);
  virtual ~BrdfSampler() = default;
  BrdfSampler(const BrdfSampler&) = delete;
  BrdfSampler& operator=(const BrdfSampler&) = delete;

  // The agreement of sample() and pdf() (above), relative.
  static constexpr double kPdfRoundTrip = 1e-4;

  // The sampler at ωo, for the several calls of one shading vertex (BrdfVertex).
  virtual BrdfVertex vertex(const Vec3d& wo) const { return {*this, wo, 0}; }

  // u0, u1 in [0, 1) (clamped into it).
  BrdfSample sample(const Vec3d& wo, float u0, float u1) const { return vertex(wo).sample(u0, u1); }
  // Density of choosing ωi given ωo, per steradian; 0 where the sampler never goes.
  virtual double pdf(const Vec3d& wo, const Vec3d& wi) const = 0;
  // The model's f(ωo, ωi).
  Rgb eval(const Vec3d& wo, const Vec3d& wi) const { return model_->eval(wo, wi); }

  // The makeup of pdf(ωo, ·) for ωo above the horizon (HalfVectorDensity); the default is all
  // cosine-weighted. A sampler must override it for brdfChiSquareTest to know its density.
  virtual HalfVectorDensity halfVectorDensity(const Vec3d& wo) const;

  // Memory of the sampling tables (0 for an analytic sampler).
  virtual std::size_t bytes() const = 0;
  virtual std::string name() const = 0;

  const BrdfModel& model() const { return *model_; }

 protected:
  friend class BrdfVertex;
  // The direction and its density; sample() adds the weight. u0, u1 already in [0, 1).
  virtual SampledDirection sampleDirection(const Vec3d& wo, float u0, float u1) const = 0;
  // The same two at a vertex. A sampler that finds something from ωo alone overrides vertex()
  // and these; the others need not: these default to the per-call ones.
  virtual SampledDirection sampleDirectionAt(const BrdfVertex& v, float u0, float u1) const {
    return sampleDirection(v.wo(), u0, u1);
  }
  virtual double pdfAt(const BrdfVertex& v, const Vec3d& wi) const { return pdf(v.wo(), wi); }
  // A vertex at ωo with the sampler's conditioning cell `slice`.
  BrdfVertex vertexWithSlice(const Vec3d& wo, std::size_t slice) const { return {*this, wo, slice}; }
  // A half-vector sampler's ωi = reflect(ωo, h) with `density`, its density along the sampling
  // path; pdf(ωo, ωi) instead where ωh cannot be found again from ωi (HalfVector::roundTripExact).
  SampledDirection reflected(const BrdfVertex& v, const Vec3d& wi, const HalfVector& h, double density) const;

 private:
  std::shared_ptr<const BrdfModel> model_;
};

// Cosine-weighted hemisphere sampling, pdf cosθi/π: the baseline renderers use for measured BRDFs
// and the one the paper replaces, and the exact one for a Lambertian BRDF. Ignores ωo.
class CosineBrdfSampler final : public BrdfSampler {
 public:
  using BrdfSampler::BrdfSampler;
  double pdf(const Vec3d& wo, const Vec3d& wi) const override;
  std::size_t bytes() const override { return 0; }
  std::string name() const override { return "cosine"; }

 protected:
  SampledDirection sampleDirection(const Vec3d& wo, float u0, float u1) const override;
};

}  // namespace acdf
