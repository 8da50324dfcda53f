#include "acdf/brdf/brdf_model.h"

#include <stdexcept>

#include "acdf/brdf/brdf_sampler.h"
#include "acdf/brdf/coordinates.h"

namespace acdf {

Rgb BrdfModel::evalHalfDiff(double thetaHalf, double thetaDiff, double phiDiff) const {
  const DirectionPair pair = fromHalfDiff({thetaHalf, 0.0, thetaDiff, phiDiff});
  return eval(pair.wo, pair.wi);
}

std::shared_ptr<const BrdfSampler> BrdfModel::nativeSampler(const std::shared_ptr<const BrdfModel>&) const {
  return nullptr;
}

void checkIsSelf(const BrdfModel& model, const std::shared_ptr<const BrdfModel>& self) {
  if (self.get() != &model) throw std::invalid_argument("nativeSampler: `self` must be the model itself");
}

}  // namespace acdf
