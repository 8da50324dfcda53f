#include "acdf/integrator/path_integrator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <new>
#include <stdexcept>

#include "acdf/integrator/product_direct_light.h"

namespace acdf {

// The vertices of one path that record what they learn (PathGuiding::records): each keeps the
// throughput from itself on and the radiance that has reached it so far.
class PathIntegrator::PathRecorder {
 public:
  PathRecorder(std::vector<GuidingRecord>* sink, std::vector<GuidingRecord>* lightSink)
      : sink_(sink), lightSink_(lightSink) {}
  PathRecorder(const PathRecorder&) = delete;
  PathRecorder& operator=(const PathRecorder&) = delete;
  ~PathRecorder() {
    for (uint32_t i = 0; i < open_; ++i) {
      Open& v = slots_[i].open;
      const double energy = v.incident.luminance() / v.pdf;
      if (std::isfinite(energy) && energy >= 0) {
        v.record.energy = static_cast<float>(energy);
        sink_->push_back(v.record);
      }
    }
  }

  bool active() const { return sink_ != nullptr; }
  bool recordsLight() const { return lightSink_ != nullptr; }
  // Environment light `radiance` (0 where blocked) arriving at `position` along `direction`, drawn
  // with density `pdf`.
  void light(const Vec3d& position, const Vec3d& normal, const Vec3d& direction, const Rgb& radiance, double pdf) {
    if (!lightSink_ || !(pdf > 0)) return;
    const double energy = radiance.luminance() / pdf;
    if (std::isfinite(energy) && energy >= 0) lightSink_->push_back(guidingRecord(position, normal, direction, energy));
  }
  // Light reaching the newest vertex's point, as it enters the image there (before the throughput).
  void add(const Rgb& light) {
    for (uint32_t i = 0; i < open_; ++i) slots_[i].open.incident += slots_[i].open.throughput * light;
  }
  void scale(const Rgb& weight) {
    for (uint32_t i = 0; i < open_; ++i) slots_[i].open.throughput *= weight;
  }
  // A vertex at `position` with surface normal `normal` continuing along `direction` with density
  // `pdf` (after its weight).
  void open(const Vec3d& position, const Vec3d& normal, const Vec3d& direction, double pdf) {
    if (!active() || open_ == kCapacity) return;
    new (&slots_[open_++].open) Open{guidingRecord(position, normal, direction, 0.0), pdf, Rgb{1, 1, 1}, Rgb{}};
  }

 private:
  // Deeper vertices go unrecorded; the light they pass on still reaches the ones recorded.
  static constexpr uint32_t kCapacity = 32;
  struct Open {
    GuidingRecord record;  // its energy filled in at the end
    double pdf;
    Rgb throughput, incident;
  };
  std::vector<GuidingRecord>* sink_;
  std::vector<GuidingRecord>* lightSink_;
  // Uninitialised until opened: a path that records nothing pays nothing for them.
  union Slot {
    Slot() {}
    Open open;
  };
  std::array<Slot, kCapacity> slots_;
  uint32_t open_ = 0;
};

PathIntegrator::PathIntegrator(const Scene& scene) : scene_(scene) {
  guided_.reserve(scene.bsdfSamplers.size());
  for (const auto& sampler : scene.bsdfSamplers) guided_.push_back(sampler && guidedMaterial(*sampler));
}

bool PathIntegrator::guidedMaterial(const BrdfSampler& sampler) {
  const Vec3d normal{0, 0, 1};
  return sampler.pdf(normal, normal) <= kGuidedPeakDensity;
}

GuidedMixture<LightTechnique> PathIntegrator::guidedLight(const LightSampleContext& context,
                                                         DirectionalDistribution field) const {
  return {LightTechnique(*scene_.environment, context), field, kGuidedLightShare};
}

double PathIntegrator::misWeight(double chosen, double other, double third) const {
  switch (scene_.settings.mis) {
    case MisMode::Power: return chosen * chosen / (chosen * chosen + other * other + third * third);
    case MisMode::Balance: return chosen / (chosen + other + third);
    case MisMode::BsdfOnly:
    case MisMode::LightOnly: break;
  }
  return 1.0;  // single-strategy modes never combine
}

double PathIntegrator::misWeightBesideConnection(double chosen, double other, double reached,
                                                 double connection) const {
  if (!(reached > 0) || !(connection > 0)) return misWeight(chosen, other);
  return misWeight(reached * chosen, reached * other, connection);
}

Rgb PathIntegrator::connect(const SurfaceHit& hit, const BrdfVertex& material, const Frame& frame,
                            const GuidedMixture<BsdfTechnique>& bsdf, const LightVertex& light, double successShare,
                            RayCounts& rays, uint32_t depth) const {
  const Vec3d toLightVertex = light.hit.position - hit.position;
  const double distanceSquared = dot(toLightVertex, toLightVertex);
  const Vec3d direction = toLightVertex * (1.0 / std::sqrt(distanceSquared));
  const Vec3d wi = frame.toLocal(direction);
  const double cosineThere = -dot(light.hit.normal, direction);
  if (!(wi.z > 0) || !(cosineThere > 0)) return {};
  const Rgb f = material.eval(wi);
  if (f.isBlack()) return {};
  const Frame lightFrame(light.hit.normal, light.hit.tangentHint);
  const BrdfVertex there = scene_.bsdfSamplers[light.hit.material]->vertex(lightFrame.toLocal(-direction));
  const Vec3d wiThere = lightFrame.toLocal(light.toLight);
  const Rgb fThere = there.eval(wiThere);
  if (fThere.isBlack()) return {};
  rays.add(depth);
  const Vec3d from = Geometry::offsetOrigin(hit, direction), to = Geometry::offsetOrigin(light.hit, -direction);
  const Vec3d shadow = to - from;
  const double shadowLength = length(shadow);
  if (scene_.geometry->occluded({from, shadow * (1.0 / shadowLength)}, shadowLength)) return {};
  const double geometry = wi.z * cosineThere / distanceSquared;
  const double reached = bsdf.pdf(direction) * cosineThere / distanceSquared;
  const double weight = misWeight(light.density, reached * light.lightPdf, reached * there.pdf(wiThere));
  return f * fThere * light.radianceOverPdf * static_cast<float>(geometry * successShare * weight);
}

[[gnu::always_inline]] inline bool PathIntegrator::extend(PathState& state, const SurfaceHit& hit,
                                                         const GuidedMixture<BsdfTechnique>& bsdf, uint32_t depth,
                                                         float share, Sampler& sampler,
                                                         PathRecorder& recorder) const {
  const auto [u0, u1] = sampler.get2D();
  const TechniqueSample next = bsdf.sample(u0, u1);
  if (!(next.pdf > 0)) return false;
  const Rgb value = next.value();
  if (value.isBlack()) return false;
  const Rgb weight = value * static_cast<float>(share / next.pdf);
  state.throughput *= weight;
  recorder.scale(weight);
  recorder.open(hit.position, hit.normal, next.direction, next.pdf);
  state.bsdfPdf = next.pdf;
  state.lastPosition = hit.position;
  state.lastNormal = hit.normal;
  state.ray = {Geometry::offsetOrigin(hit, next.direction), next.direction};

  if (depth + 1 >= scene_.settings.rouletteDepth) {
    const double survive = std::min<double>(0.95, state.throughput.maxComponent());
    if (sampler.get1D() >= survive) return false;
    const auto rescale = static_cast<float>(1.0 / survive);
    state.throughput *= rescale;
    recorder.scale(Rgb{rescale, rescale, rescale});
  }
  return true;
}

Rgb PathIntegrator::radiance(const Ray& cameraRay, Sampler& sampler, RayCounts& rays, const PathGuiding& guiding,
                             uint32_t branches, const LightPathPool* lightPaths) const {
  PathState state(cameraRay, allowsIncompleteLightPdf(scene_.settings));
  PathRecorder recorder(guiding.records, guiding.lightRecords);
  return walk(state, 0, branches, sampler, rays, guiding, lightPaths, recorder);
}

Rgb PathIntegrator::walk(PathState& state, uint32_t firstDepth, uint32_t branches, Sampler& sampler, RayCounts& rays,
                         const PathGuiding& guiding, const LightPathPool* lightPaths,
                         PathRecorder& recorder) const {
  const EnvironmentLight& env = *scene_.environment;
  const MisMode mis = scene_.settings.mis;
  const bool product = scene_.settings.direct == DirectLighting::Product;
  const bool sampleLight = drawsLightSamples(scene_.settings);
  const bool bsdfSeesLight = !product && mis != MisMode::LightOnly;
  // Connections need all three densities: a light sample, an escape that sees the light, no field.
  const bool connects = lightPaths && sampleLight && bsdfSeesLight && !guiding.field && !guiding.lightField;
  if (lightPaths && !connects) throw std::invalid_argument("radiance: light paths need unguided MIS light sampling");
  // The normal and position are those of the vertex being lit; after a BSDF sample they stay those
  // of the vertex the sample left, for the pdf of the light the sample may reach.
  LightSampleContext& lightContext = state.lightContext;
  const Rgb& throughput = state.throughput;
  const Ray& ray = state.ray;

  Rgb result;
  // Light reaching the current vertex, into the image and the recorded vertices.
  auto add = [&](const Rgb& light) {
    result += throughput * light;
    recorder.add(light);
  };
  for (uint32_t depth = firstDepth;; ++depth) {
    rays.add(depth);
    const bool weighsEscape = depth > 0 && bsdfSeesLight && sampleLight;
    if (weighsEscape && rays.escapesLikely()) env.prefetch(lightContext, ray.direction);
    const std::optional<SurfaceHit> hit = scene_.geometry->intersect(ray);
    if (depth > 0) {
      ++rays.continuations;
      rays.escapes += !hit;
    }
    if (!hit) {
      Rgb seen;
      float weight = 1;  // the image's share of it
      if (depth == 0) {
        seen = env.eval(ray.direction);
      } else if (weighsEscape) {
        const ValueAndPdf light = guidedLight(lightContext, state.lightField).along(ray.direction);
        seen = light.value;
        const double connection = connects && state.reachedDensity > 0
                                      ? lightPaths->source().density(state.lastPosition, state.lastNormal, ray.direction)
                                      : 0.0;
        weight = static_cast<float>(misWeightBesideConnection(state.bsdfPdf, light.pdf, state.reachedDensity, connection));
      } else if (bsdfSeesLight || recorder.recordsLight()) {
        seen = env.eval(ray.direction);
        weight = bsdfSeesLight ? 1.0f : 0.0f;
      }
      result += throughput * seen * weight;
      recorder.add(seen * weight);
      if (depth > 0) recorder.light(state.lastPosition, state.lastNormal, ray.direction, seen, state.bsdfPdf);
      break;
    }
    if (depth >= scene_.settings.maxDepth) break;
    sampler.startVertex(depth);
    // Per unit area, reached by the previous vertex's BSDF sample, which that vertex's connection
    // covers too (it connected: this vertex is within the maximum depth).
    const double reached = connects && depth > 0 ? state.bsdfPdf * std::abs(dot(hit->normal, ray.direction)) /
                                                       (hit->distance * hit->distance)
                                                 : 0.0;

    const Frame frame(hit->normal, hit->tangentHint);
    // The material at ωo, found once for the direct light's calls and the continuation.
    const BrdfVertex material = scene_.bsdfSamplers[hit->material]->vertex(frame.toLocal(-ray.direction));
    env.moveTo(lightContext, hit->position, hit->normal);
    const GuidedMixture bsdf(BsdfTechnique(material, frame),
                             guiding.field && guided_[hit->material] ? guiding.field->at(hit->position, hit->normal)
                                                                     : DirectionalDistribution{},
                             kGuidedBsdfShare);
    // Looked up only where light samples are drawn (and escapes weighed against them).
    state.lightField = sampleLight && guiding.lightField ? guiding.lightField->at(hit->position, hit->normal)
                                                         : DirectionalDistribution{};

    if (product) {
      CandidateValues candidates = sampler.getCandidates(scene_.settings.product.candidates);
      const ProductDirectLight direct(env, lightContext, material, frame, scene_.settings.product);
      if (const std::optional<ProductLightSample> light = direct.sample(candidates)) {
        rays.add(depth);
        if (!scene_.geometry->occluded({Geometry::offsetOrigin(*hit, light->direction), light->direction},
                                       std::numeric_limits<double>::infinity()))
          add(light->estimate);
      }
    } else if (sampleLight) {
      const auto [u0, u1] = sampler.get2D();
      // The light sample's second value picks the light path vertex too: the two estimates are
      // each unbiased, whatever their correlation. Picked now, it loads during the shadow ray.
      const LightVertex* connection =
          connects && depth + 1 < scene_.settings.maxDepth ? lightPaths->pick(u1) : nullptr;
      const TechniqueSample light = guidedLight(lightContext, state.lightField).sample(u0, u1);
      const Vec3d wi = frame.toLocal(light.direction);
      Rgb arriving;  // 0 where blocked
      if (light.pdf > 0 && wi.z > 0) {
        // The shadow ray first: a measured BRDF's eval costs about as much as the ray, a fifth of
        // the demo's shadow rays are blocked (f is rarely 0 where cosθi > 0), and the light's
        // radiance arrives from memory meanwhile.
        rays.add(depth);
        if (!scene_.geometry->occluded({Geometry::offsetOrigin(*hit, light.direction), light.direction},
                                       std::numeric_limits<double>::infinity())) {
          arriving = light.value();
          const Rgb f = material.eval(wi);
          if (!f.isBlack() && !arriving.isBlack()) {
            const double connection =
                reached > 0 ? lightPaths->source().density(hit->position, hit->normal, light.direction) : 0.0;
            const double weight =
                bsdfSeesLight ? misWeightBesideConnection(light.pdf, bsdf.pdf(light.direction), reached, connection)
                              : 1.0;
            add(f * arriving * static_cast<float>(wi.z * weight / light.pdf));
          }
        }
      }
      recorder.light(hit->position, hit->normal, light.direction, arriving, light.pdf);
      if (connection) add(connect(*hit, material, frame, bsdf, *connection, lightPaths->successShare(), rays, depth));
    }
    state.reachedDensity = reached;

    if (depth == 0 && branches > 1) {
      // Branched at the first vertex: each branch continues a copy of the path with its own BSDF
      // sample and its own recorder, and carries a 1/branches share of the light it brings.
      for (uint32_t branch = 0; branch < branches; ++branch) {
        sampler.startBranch(branch, branches);
        PathState branchState = state;
        PathRecorder branchRecorder(guiding.records, guiding.lightRecords);
        if (!extend(branchState, *hit, bsdf, depth, 1.0f / static_cast<float>(branches), sampler, branchRecorder))
          continue;
        result += walk(branchState, depth + 1, 1, sampler, rays, guiding, lightPaths, branchRecorder);
      }
      break;
    }
    if (!extend(state, *hit, bsdf, depth, 1.0f, sampler, recorder)) break;
  }
  return result;
}

}  // namespace acdf
