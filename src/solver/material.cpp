#include "solver/material.hpp"

#include "common/error.hpp"

namespace descent {

template <class Real>
ElasticModel<Real> make_elastic_model(const MaterialSpec& spec) {
  const Real e = static_cast<Real>(spec.young), nu = static_cast<Real>(spec.poisson);
  const Real c2 = static_cast<Real>(spec.c2), c3 = static_cast<Real>(spec.c3);
  if (spec.model == "stvk") return StVK<Real>::from_young_poisson(e, nu);
  if (spec.model == "neo_hookean") return NeoHookean<Real>::from_young_poisson(e, nu);
  if (spec.model == "mooney_rivlin") return MooneyRivlin<Real>::from_young_poisson(e, nu, c2);
  if (spec.model == "fung") return Fung<Real>::from_young_poisson(e, nu, c2, c3);
  if (spec.model == "corotated") return Corotated<Real>::from_young_poisson(e, nu);
  if (spec.model == "arap") return Arap<Real>::from_young_poisson(e, nu);
  throw LogicError("make_elastic_model: unknown model '" + spec.model + "'");
}

template ElasticModel<double> make_elastic_model(const MaterialSpec&);
template ElasticModel<float> make_elastic_model(const MaterialSpec&);

}  // namespace descent
