#pragma once
// The runtime choice of energy density: one variant over the models of
// src/kernels, visited once per element loop (never per element).
#include <variant>

#include "io/scene.hpp"
#include "kernels/arap.hpp"
#include "kernels/corotated.hpp"
#include "kernels/fung.hpp"
#include "kernels/mooney_rivlin.hpp"
#include "kernels/neo_hookean.hpp"
#include "kernels/stvk.hpp"

namespace descent {

template <class Real>
using ElasticModel = std::variant<StVK<Real>, NeoHookean<Real>, MooneyRivlin<Real>, Fung<Real>,
                                  Corotated<Real>, Arap<Real>>;

// The scene validated the name; anything else is a bug.
template <class Real>
ElasticModel<Real> make_elastic_model(const MaterialSpec& spec);

}  // namespace descent
