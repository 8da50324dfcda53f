// Fuzzes the RGL .bsdf reader (acdf/brdf/tensor_file.h, acdf/brdf/rgl.h) on the bytes as they are:
// the tensor file's header (counts, names, dtypes, extents, offsets beyond the file) and the RGL
// fields' checks (missing, wrong dtype or shape, NaN/Inf, negative, zero slices). Invariants: the
// reader returns a model or throws FileError with a one-line message naming the file; a model
// evaluates to finite, non-negative values, and its own sampler (rgl_sampler.h) returns unit
// directions with a finite, positive pdf, at directions taken from the input's last bytes.

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "acdf/brdf/rgl.h"
#include "acdf/brdf/rgl_sampler.h"
#include "fuzz_input.h"

namespace {

constexpr const char* kName = "fuzz.bsdf";

void checkModel(const std::shared_ptr<const acdf::RglBrdf>& model, const uint8_t* data, std::size_t size) {
  const acdf::RglBrdfSampler sampler(model);
  const std::size_t tail = size > 64 ? 64 : size;
  acdf::fuzz::Bytes in(data + size - tail, tail);
  for (int i = 0; i < 4; ++i) {
    const float a = in.take<uint16_t>() / 65536.0f, b = in.take<uint16_t>() / 65536.0f;
    const float c = in.take<uint16_t>() / 65536.0f, d = in.take<uint16_t>() / 65536.0f;
    const acdf::Vec3d wo = acdf::sampleCosineHemisphere(a, b), wi = acdf::sampleCosineHemisphere(c, d);
    const acdf::Rgb f = model->eval(wo, wi);
    for (float v : {f.r, f.g, f.b}) acdf::fuzz::require(std::isfinite(v) && v >= 0.0f, "rgl: eval not finite and >= 0");
    const acdf::BrdfSample s = sampler.sample(wo, c, d);
    acdf::fuzz::require(std::fabs(acdf::length(s.wi) - 1.0) < 1e-5, "rgl: sample not a unit vector");
    acdf::fuzz::require(std::isfinite(s.pdf) && s.pdf > 0.0, "rgl: sample pdf not finite and > 0");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  using namespace acdf;
  try {
    const TensorFile file = TensorFile::parse({data, size}, kName);
    const auto model = std::make_shared<const RglBrdf>(file, kName);
    checkModel(model, data, size);
  } catch (const FileError& e) {
    const std::string message = e.what();
    fuzz::require(message.rfind(std::string(kName) + ": ", 0) == 0, "rgl: message does not name the file", message);
    fuzz::require(message.find('\n') == std::string::npos, "rgl: message spans lines", message);
  }
  return 0;
}
