// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_ANY_WEIGHTS_H
#define CGAL_LAPLACIAN_DEFORMATION_ANY_WEIGHTS_H

#include <CGAL/Laplacian_deformation/Cotangent_weights.h>
#include <CGAL/Laplacian_deformation/Node_cell.h>
#include <CGAL/Laplacian_deformation/Uniform_weights.h>
#include <CGAL/Laplacian_deformation/internal/Policy_variant.h>

#include <vector>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationPolicies

\brief A weight policy chosen at run time among `WeightPolicies...` (held by value in a
`std::variant`): one `Mesh_deformer` type for all of them (see \ref LapDefRunTime).

It is constructible from each alternative (implicitly); the default constructor holds the first
one, default-constructed. `Mesh_deformer`, `deform_mesh()` and `laplacian_matrix()` look at the
alternative once per call, before their loop over the cells, which then calls the held policy
directly: the result is bitwise that of the held policy used as a template argument.
`weights()` (per cell) is for other callers.

\tparam WeightPolicies models of `DeformationWeightPolicy`, `CopyConstructible`, each given once

\cgalModels{DeformationWeightPolicy}

\sa `Any_weights`
*/
template <class... WeightPolicies>
class Weight_policy_variant
#ifndef DOXYGEN_RUNNING
  : public internal::Policy_variant<WeightPolicies...>
#endif
{
  typedef internal::Policy_variant<WeightPolicies...> Base;

public:
#ifdef DOXYGEN_RUNNING
  /// the first alternative, default-constructed.
  Weight_policy_variant();
  /// holds `policy` (a copy), one of `WeightPolicies...`.
  template <class WeightPolicy>
  Weight_policy_variant(const WeightPolicy& policy);
  /// returns `f(p)`, `p` the held policy (a `const` reference of its own type).
  template <class F>
  decltype(auto) visit(F&& f) const;
  /// the index of the held policy in `WeightPolicies...`.
  std::size_t index() const;
  /// whether the held policy is a `WeightPolicy`.
  template <class WeightPolicy>
  bool holds() const;
  /// the held policy if it is a `WeightPolicy`, else `nullptr`.
  template <class WeightPolicy>
  const WeightPolicy* get_if() const;
#else
  using Base::Base;
#endif

  /// the weights of the held policy.
  template <class GeomTraits>
  void weights(const Node_cell<GeomTraits>& cell, std::vector<double>& w) const
  {
    this->visit([&](const auto& policy) { policy.weights(cell, w); });
  }
};

/*!
\ingroup PkgLaplacianDeformationPolicies

\brief The built-in weight policies chosen at run time: `Cotangent_weights` (the default) or
`Uniform_weights` (see \ref LapDefRunTime).

\cgalModels{DeformationWeightPolicy}
*/
typedef Weight_policy_variant<Cotangent_weights, Uniform_weights> Any_weights;

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_ANY_WEIGHTS_H
