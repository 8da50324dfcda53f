#include "acdf/brdf/brdf_model.h"

#include "acdf/brdf/coordinates.h"

namespace acdf {

Rgb BrdfModel::evalHalfDiff(double thetaHalf, double thetaDiff, double phiDiff) const {
  const DirectionPair pair = fromHalfDiff({thetaHalf, 0.0, thetaDiff, phiDiff});
  return eval(pair.wo, pair.wi);
}

}  // namespace acdf
