#include <set>

#include "acdf/integrator/scene.h"

namespace acdf {

Scene::TableBytes Scene::tableBytes() const {
  TableBytes bytes;
  std::set<const BrdfSampler*> samplers;
  for (const auto& material : bsdfSamplers)
    if (samplers.insert(material.get()).second) bytes.brdf += material->bytes();
  bytes.environment = environment->tableBytes();
  return bytes;
}

void Scene::buildDeferredTables() const {
  if (const LocalEnvironmentTable* local = environment->localTable()) local->buildAll();
}

}  // namespace acdf
