#pragma once
// A scene ready to render, and its loader from the JSON format of docs/scene-format.md.
//
// The loader validates everything before anything expensive happens: unknown keys, wrong types
// and bad values are reported with their JSON path ("$.shapes[2].radius: expected a number,
// got a string"); relative file paths resolve against the scene file's directory. Then it loads
// only what the shapes use — a material no shape refers to is never read — and asks the
// SceneAssets for just the tables the chosen strategies need.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "acdf/brdf/brdf_sampler.h"
#include "acdf/envmap/environment_light.h"
#include "acdf/integrator/camera.h"
#include "acdf/integrator/geometry.h"
#include "acdf/integrator/openings.h"
#include "acdf/integrator/product_direct_light.h"
#include "acdf/integrator/sampler.h"
#include "acdf/integrator/scene_assets.h"
#include "acdf/sampling/file_error.h"

namespace acdf {

// How BSDF sampling and light sampling are combined.
enum class MisMode {
  Power,      // both strategies, power heuristic (β = 2)
  Balance,    // both strategies, balance heuristic
  BsdfOnly,   // BSDF sampling alone (no next-event estimation)
  LightOnly,  // light sampling alone for direct light (BSDF sampling only continues paths)
};
// "power", "balance", "bsdf-only", "light-only"; parse throws std::invalid_argument.
std::string_view toString(MisMode mode);
MisMode parseMisMode(std::string_view name);
// Whether light sampling may have an incomplete pdf (LightSampleContext): when BSDF samples see
// the light too, in every mode but light-only.
inline bool allowsIncompleteLightPdf(MisMode mode) { return mode != MisMode::LightOnly; }

// What a scene gets where it names no strategy: the combinations that won at equal time on the
// example scenes (docs/performance.md, "Defaults"). Owen-scrambled Sobol samples below, the
// compensated environment table here, and the isotropic table layout for isotropic materials
// (scene_loader.cpp).
inline constexpr EnvironmentSampling kSceneEnvironmentSampling = EnvironmentSampling::Compensated;

// How a surface vertex estimates the environment light reaching it directly.
enum class DirectLighting {
  Mis,      // a light sample and the escaped BSDF sample, combined by the MIS mode
  Product,  // resampled product sampling (product_direct_light.h); the MIS mode does not apply
};
// "mis", "product"; parse throws std::invalid_argument.
std::string_view toString(DirectLighting direct);
DirectLighting parseDirectLighting(std::string_view name);

// Whether the render learns where the light comes from as it goes (guiding_field.h, renderer.h,
// path_integrator.h): never; the environment light each place sees (light sampling guided);
// that and the radiance paths carry (their continuations guided too); or the light where the
// render's own second pass measures that it pays.
enum class GuidingMode { Off, Light, Paths, Auto };
// "off", "light", "paths", "auto"; parse throws std::invalid_argument.
std::string_view toString(GuidingMode mode);
GuidingMode parseGuidingMode(std::string_view name);

// Which portals the environment light uses: the scene's, or where it declares none the openings
// found by tracing (openings.h); only the scene's; or none, even declared ones.
enum class PortalSource { Auto, Declared, None };
// "auto", "declared", "none"; parse throws std::invalid_argument.
std::string_view toString(PortalSource source);
PortalSource parsePortalSource(std::string_view name);

// Whether the camera's paths connect to light paths started at the portals (light_paths.h), where
// the light has portals and the render draws unguided MIS light samples: where the render's first
// samples measure that they pay (renderer.h), always, or never.
enum class LightPathMode { Auto, On, Off };
// "auto", "on", "off"; parse throws std::invalid_argument.
std::string_view toString(LightPathMode mode);
LightPathMode parseLightPathMode(std::string_view name);

// RenderSettings::branches: at most this many, or auto (renderer.h).
inline constexpr uint32_t kMaxBranches = 64;
inline constexpr uint32_t kAutoBranches = 0;
// "auto" or an integer in [1, kMaxBranches]; parse throws std::invalid_argument.
std::string branchesName(uint32_t branches);
uint32_t parseBranches(std::string_view name);

struct RenderSettings {
  uint32_t spp = 16;
  uint64_t seed = 1;
  uint32_t maxDepth = 8;       // bounces; 1 = direct light only
  // Russian roulette from this bounce on: the fifth surface interaction, as Mitsuba 3's rr_depth 5.
  // From the third, the example scenes' efficiency at equal time was 0.72-0.99x this (performance.md).
  uint32_t rouletteDepth = 5;
  // The balance heuristic: the compensated table is the one MIS compensation (Karlik et al. 2019)
  // derives for it, and it gave 2-13% less variance per sample than power on every open example
  // scene, the same in the interiors (performance.md).
  MisMode mis = MisMode::Balance;
  // Paths per camera sample from the first vertex on (branched path tracing): the camera ray, its
  // vertex and that vertex's light sample are shared, each branch has its own BSDF sample and
  // carries 1/branches of its light. Pays where the light after the first bounce is the noisy
  // part and a branch costs less than the camera sample: 1.2-1.4x the efficiency on the open
  // scenes with glossy analytic materials, 1 branch is best in the interiors. Auto by default
  // (renderer.h: a probe of 13,824 samples measures both): 2 branches on the glossy
  // spheres (1.24x) and conductors, 1 on the other example scenes (performance.md, "Auto branching
  // measured").
  uint32_t branches = kAutoBranches;
  SamplerKind sampler = SamplerKind::Sobol;
  DirectLighting direct = DirectLighting::Mis;
  ProductSamplingOptions product{};  // under DirectLighting::Product
  GuidingMode guiding = GuidingMode::Off;
  PortalSource portals = PortalSource::Auto;
  // Auto: in scenes/room.json connections gave 1.72x the efficiency of none at equal time, behind
  // the door ajar 0.97x, and auto's measure keeps them there only (performance.md, "Light paths
  // through the portals").
  LightPathMode lightPaths = LightPathMode::Auto;
};

// Whether the render's light samples may have an incomplete pdf: under product sampling when the
// candidates' mixture includes BSDF sampling, else as the MIS mode says.
inline bool allowsIncompleteLightPdf(const RenderSettings& settings) {
  if (settings.direct == DirectLighting::Product) return settings.product.bsdfFraction > 0;
  return allowsIncompleteLightPdf(settings.mis);
}

// Whether paths draw light samples at their vertices (what guiding of the light can improve): under
// MIS direct lighting with a mode that samples the light.
inline bool drawsLightSamples(const RenderSettings& settings) {
  return settings.direct == DirectLighting::Mis && settings.mis != MisMode::BsdfOnly;
}

// Whether a render with these settings may connect its paths to light paths, given portals: unless
// off, where paths draw light samples, weigh escapes against them by MIS and are not guided.
inline bool connectsLightPaths(const RenderSettings& settings) {
  return settings.lightPaths != LightPathMode::Off && drawsLightSamples(settings) &&
         (settings.mis == MisMode::Balance || settings.mis == MisMode::Power) && settings.guiding == GuidingMode::Off;
}

// Command-line choices that replace the scene file's.
struct SceneOverrides {
  std::optional<MisMode> mis = std::nullopt;
  std::optional<SamplerKind> sampler = std::nullopt;
  std::optional<DirectLighting> direct = std::nullopt;
  std::optional<uint32_t> candidates = std::nullopt;  // product sampling's M
  std::optional<uint32_t> branches = std::nullopt;
  std::optional<GuidingMode> guiding = std::nullopt;
  std::optional<PortalSource> portals = std::nullopt;
  std::optional<LightPathMode> lightPaths = std::nullopt;
  std::optional<BrdfSampling> bsdfSampling = std::nullopt;  // every measured material
  std::optional<EnvironmentSampling> envSampling = std::nullopt;
  std::optional<uint32_t> spp = std::nullopt;
  std::optional<uint64_t> seed = std::nullopt;
  std::optional<CropWindow> crop = std::nullopt;
};

struct Scene {
  std::unique_ptr<Camera> camera;
  std::unique_ptr<Geometry> geometry;
  // The materials' BRDF samplers (each with its model: eval, sample and pdf), indexed by the
  // shapes' material ids; two materials of one table share one.
  std::vector<std::shared_ptr<const BrdfSampler>> bsdfSamplers;
  std::unique_ptr<EnvironmentLight> environment;
  RenderSettings settings;
  // The search for openings, when the scene declared no portals and its settings let it look
  // (PortalSource::Auto); the light's portals are its openings.
  std::optional<OpeningSearch> openingSearch;

  struct TableBytes {
    std::size_t brdf = 0, environment = 0;
  };
  // Bytes of the sampling tables it renders with (a sampler two materials share counts once); of
  // the local environment table, the slices built so far.
  TableBytes tableBytes() const;
  // Builds now, in parallel, what a render would build on first use (the local environment
  // table's slices), so that a timed render measures sampling alone.
  void buildDeferredTables() const;
  // Whether a shape uses a measured material (a MERL or RGL file, or a preset tabulated in the
  // MERL layout): only then does the BRDF sampling strategy (--bsdf-sampling) change the image.
  bool usesMeasuredMaterial = false;
};

// Throws FileError for any problem with the scene or a file it names; a problem in the scene
// carries its JSON path ("$.shapes[2].radius: ..."), one in a file it names says where the scene
// refers to it ("(referenced by $.materials.x.file)").
Scene loadScene(const std::filesystem::path& file, const SceneOverrides& overrides, SceneAssets& tables);
// The same from the text of a scene file; `file` names it in messages and its directory resolves
// relative paths.
Scene loadSceneText(const std::string& text, const std::filesystem::path& file, const SceneOverrides& overrides,
                    SceneAssets& tables);

}  // namespace acdf
