// Product sampling in Python: direct environment light at shading points, sampled in proportion to
// f·L·cos by resampling (acdf/integrator/product_direct_light.h), batched over shading points.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <optional>
#include <string>

#include "acdf/integrator/product_direct_light.h"
#include "acdf/sampling/frame.h"
#include "acdf/sampling/option_error.h"
#include "arrays.h"
#include "bindings.h"

namespace acdf::python {

using namespace pybind11::literals;

namespace {

// One light and one material; the light is the Python object's (kept alive by the binding).
struct ProductSampler {
  const EnvironmentLight* light;
  std::shared_ptr<const BrdfSampler> material;
  ProductSamplingOptions options;

  // The estimator at shading point (wo, n), both world-frame: the frame is Frame(n) (its tangent
  // from the normal alone), wo points away from the surface.
  ProductDirectLight at(const Vec3d& wo, const Vec3d& n) const {
    const Frame frame(n);
    const LightSampleContext context{.allowIncompletePdf = options.bsdfFraction > 0, .normal = n};
    return ProductDirectLight(*light, context, *material, frame, frame.toLocal(wo), options);
  }
};

constexpr const char* kDoc = R"(Direct environment light at shading points by resampled importance
sampling of f(wo, wi) L(wi) cos(theta_i) (Talbot et al. 2005), as `acdf render --direct product`.

ProductSampler(light, material, candidates=2, bsdf_fraction=0.5): each shading point draws
`candidates` (M) directions from the mixture q = (1 - b) p_light + b p_bsdf (b = bsdf_fraction;
the light's local table for the point's normal when its strategy is "local"), weights each by
w = luminance(f L cos) / q and keeps one in proportion to w.

sample(wo, normal, seed=0, first_stream=0) -> (wi, estimate, mixture_pdf):
  wo, normal: (n, 3) or (3,) float64, world frame; wo points away from the surface. The shading
    frame is acdf's Frame(normal): a 4D-tabulated material sees the tangent it derives.
  wi (n, 3): the direction kept (world frame; 0 where every candidate's weight was 0);
  estimate (n, 3) float32: f L cos(theta_i) / p_hat(wi) * (1/M) sum(w), the unbiased estimate of
    the direct light for an unoccluded wi (multiply by its visibility); 0 where nothing was kept;
  mixture_pdf (n,): q at wi, per steradian (0 where nothing was kept).
  Row i draws its values from PCG32 stream first_stream + i of `seed`: results do not depend on
  the batch's threads, and a batch split into chunks (each given its first row's index as
  first_stream) gives the same samples as the whole.
mixture_pdf(wo, normal, wi) -> (n,): q at world directions wi.)";

}  // namespace

void bindProductSampling(py::module_& m) {
  py::class_<ProductSampler>(m, "ProductSampler", kDoc)
      .def(py::init([](const EnvironmentLight& light, std::shared_ptr<BrdfSampler> material, uint32_t candidates,
                       double bsdfFraction) {
             if (!material) throw py::value_error("material: a BrdfSampler, not None");
             const ProductSamplingOptions options{candidates, bsdfFraction};
             try {
               validate(options);
             } catch (const OptionError& e) {
               throw py::value_error(e.what());
             }
             return ProductSampler{&light, std::move(material), options};
           }),
           "light"_a, "material"_a, "candidates"_a = ProductSamplingOptions{}.candidates,
           "bsdf_fraction"_a = ProductSamplingOptions{}.bsdfFraction, py::keep_alive<1, 2>())
      .def_property_readonly("candidates", [](const ProductSampler& s) { return s.options.candidates; })
      .def_property_readonly("bsdf_fraction", [](const ProductSampler& s) { return s.options.bsdfFraction; })
      .def(
          "sample",
          [](const ProductSampler& s, const ArrayArg& wo, const ArrayArg& normal, uint64_t seed,
             uint64_t firstStream) {
            const Directions o = directions(wo, "wo"), nrm = directions(normal, "normal");
            const std::size_t n = pairedRows(o.rows(), nrm.rows(), "wo and normal");
            auto wi = output<double>(n, 3), pdf = output<double>(n);
            auto estimate = output<float>(n, 3);
            double *ws = wi.mutable_data(), *ps = pdf.mutable_data();
            float* es = estimate.mutable_data();
            forEachRow(n, [&](std::size_t i) {
              CandidateValues values{Pcg32(seed, firstStream + i)};
              const std::optional<ProductLightSample> l = s.at(o[i], nrm[i]).sample(values);
              storeVec3(ws, i, l ? l->direction : Vec3d{});
              storeRgb(es, i, l ? l->estimate : Rgb{});
              ps[i] = l ? l->mixturePdf : 0.0;
            });
            return py::make_tuple(wi, estimate, pdf);
          },
          "wo"_a, "normal"_a, "seed"_a = 0, "first_stream"_a = 0)
      .def(
          "mixture_pdf",
          [](const ProductSampler& s, const ArrayArg& wo, const ArrayArg& normal, const ArrayArg& wi) {
            const Directions o = directions(wo, "wo"), nrm = directions(normal, "normal"), w = directions(wi, "wi");
            const std::size_t n = pairedRows(pairedRows(o.rows(), nrm.rows(), "wo and normal"), w.rows(), "wo and wi");
            auto pdf = output<double>(n);
            double* ps = pdf.mutable_data();
            forEachRow(n, [&](std::size_t i) { ps[i] = s.at(o[i], nrm[i]).mixturePdf(w[i]); });
            return pdf;
          },
          "wo"_a, "normal"_a, "wi"_a);
}

}  // namespace acdf::python
