#include "acdf/integrator/path_integrator.h"

#include <algorithm>
#include <limits>

#include "acdf/integrator/product_direct_light.h"
#include "acdf/sampling/frame.h"

namespace acdf {

double PathIntegrator::misWeight(double chosen, double other) const {
  switch (scene_.settings.mis) {
    case MisMode::Power: return chosen * chosen / (chosen * chosen + other * other);
    case MisMode::Balance: return chosen / (chosen + other);
    case MisMode::BsdfOnly:
    case MisMode::LightOnly: break;
  }
  return 1.0;  // single-strategy modes never combine
}

Rgb PathIntegrator::radiance(const Ray& cameraRay, Sampler& sampler, uint64_t& rays) const {
  const EnvironmentLight& env = *scene_.environment;
  const MisMode mis = scene_.settings.mis;
  const bool product = scene_.settings.direct == DirectLighting::Product;
  const bool sampleLight = !product && mis != MisMode::BsdfOnly;
  const bool bsdfSeesLight = !product && mis != MisMode::LightOnly;
  // The normal and position are those of the vertex being lit; after a BSDF sample they stay those
  // of the vertex the sample left, for the pdf of the light the sample may reach.
  LightSampleContext lightContext{.allowIncompletePdf = allowsIncompleteLightPdf(scene_.settings)};

  Rgb result, throughput{1, 1, 1};
  Ray ray = cameraRay;
  double bsdfPdf = 0;  // density of the BSDF sample that produced `ray`; 0 for the camera ray
  for (uint32_t depth = 0;; ++depth) {
    ++rays;
    const std::optional<SurfaceHit> hit = scene_.geometry->intersect(ray);
    if (!hit) {
      if (depth == 0) {
        result += throughput * env.eval(ray.direction);
      } else if (bsdfSeesLight && sampleLight) {
        const RadianceAndPdf light = env.evalWithPdf(lightContext, ray.direction);
        result += throughput * light.radiance * misWeight(bsdfPdf, light.pdf);
      } else if (bsdfSeesLight) {
        result += throughput * env.eval(ray.direction);
      }
      break;
    }
    if (depth >= scene_.settings.maxDepth) break;
    sampler.startVertex(depth);

    const Frame frame(hit->normal, hit->tangentHint);
    // The material at ωo, found once for the direct light's calls and the continuation.
    const BrdfVertex material = scene_.bsdfSamplers[hit->material]->vertex(frame.toLocal(-ray.direction));
    lightContext = env.atPosition(env.atNormal(lightContext, hit->normal), hit->position);

    if (product) {
      CandidateValues candidates = sampler.getCandidates(scene_.settings.product.candidates);
      const ProductDirectLight direct(env, lightContext, material, frame, scene_.settings.product);
      if (const std::optional<ProductLightSample> light = direct.sample(candidates)) {
        ++rays;
        if (!scene_.geometry->occluded({Geometry::offsetOrigin(*hit, light->direction), light->direction},
                                       std::numeric_limits<double>::infinity()))
          result += throughput * light->estimate;
      }
    } else if (sampleLight) {
      const auto [u0, u1] = sampler.get2D();
      const LightSample light = env.sample(lightContext, u0, u1);
      const Vec3d wi = frame.toLocal(light.direction);
      if (light.pdf > 0 && wi.z > 0 && !light.radiance.isBlack()) {
        // The shadow ray first: a measured BRDF's eval costs about as much as the ray, and a
        // fifth of the demo's shadow rays are blocked (f is rarely 0 where cosθi > 0).
        ++rays;
        if (!scene_.geometry->occluded({Geometry::offsetOrigin(*hit, light.direction), light.direction},
                                       std::numeric_limits<double>::infinity())) {
          const Rgb f = material.eval(wi);
          if (!f.isBlack()) {
            const double weight = bsdfSeesLight ? misWeight(light.pdf, material.pdf(wi)) : 1.0;
            result += throughput * f * light.radiance * (wi.z * weight / light.pdf);
          }
        }
      }
    }

    const auto [u0, u1] = sampler.get2D();
    const BrdfSample s = material.sample(u0, u1);
    if (!(s.pdf > 0) || s.weight.isBlack()) break;
    throughput *= s.weight;
    bsdfPdf = s.pdf;
    const Vec3d direction = normalize(frame.toWorld(s.wi));
    ray = {Geometry::offsetOrigin(*hit, direction), direction};

    if (depth + 1 >= scene_.settings.rouletteDepth) {
      const double survive = std::min<double>(0.95, throughput.maxComponent());
      if (sampler.get1D() >= survive) break;
      throughput *= static_cast<float>(1.0 / survive);
    }
  }
  return result;
}

}  // namespace acdf
