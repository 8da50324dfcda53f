#include "acdf/brdf/measured_file.h"

#include "acdf/brdf/rgl.h"

namespace acdf {

std::shared_ptr<const BrdfModel> loadMeasuredBrdf(const std::filesystem::path& path,
                                                  MerlBrdf::Interpolation interpolation) {
  if (RglBrdf::isRglFile(path)) return std::make_shared<const RglBrdf>(RglBrdf::load(path));
  return std::make_shared<const MerlBrdf>(MerlBrdf::load(path, interpolation));
}

}  // namespace acdf
