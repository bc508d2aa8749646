// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_ANY_TRANSFORM_H
#define CGAL_LAPLACIAN_DEFORMATION_ANY_TRANSFORM_H

#include <CGAL/Laplacian_deformation/Anchored_scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Fixed_transform.h>
#include <CGAL/Laplacian_deformation/Node_cell.h>
#include <CGAL/Laplacian_deformation/Principal_scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Rotation_scale_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Rotation_transform.h>
#include <CGAL/Laplacian_deformation/Scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Similarity_transform.h>
#include <CGAL/Laplacian_deformation/internal/Policy_variant.h>

#include <Eigen/Core>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationPolicies

\brief A transform policy chosen at run time among `TransformPolicies...` (held by value in a
`std::variant`): one `Mesh_deformer` type for all of them (see \ref LapDefRunTime).

It is constructible from each alternative (implicitly); the default constructor holds the first
one, default-constructed. The local step of `Mesh_deformer::deform()` looks at the alternative
once per iteration, before its loop over the nodes, which then calls the held policy directly:
the result is bitwise that of the held policy used as a template argument. When it holds
`Fixed_transform`, the deformer treats it as `Fixed_transform` (no start transforms, see
\ref LapDefStart). `transform()` (per cell) is for other callers.

\tparam TransformPolicies models of `DeformationTransformPolicy`, `CopyConstructible`, each given once

\cgalModels{DeformationTransformPolicy}

\sa `Any_transform`
*/
template <class... TransformPolicies>
class Transform_policy_variant
#ifndef DOXYGEN_RUNNING
  : public internal::Policy_variant<TransformPolicies...>
#endif
{
  typedef internal::Policy_variant<TransformPolicies...> Base;

public:
#ifdef DOXYGEN_RUNNING
  /// the first alternative, default-constructed.
  Transform_policy_variant();
  /// holds `policy` (a copy), one of `TransformPolicies...`.
  template <class TransformPolicy>
  Transform_policy_variant(const TransformPolicy& policy);
  /// returns `f(p)`, `p` the held policy (a `const` reference of its own type).
  template <class F>
  decltype(auto) visit(F&& f) const;
  /// the index of the held policy in `TransformPolicies...`.
  std::size_t index() const;
  /// whether the held policy is a `TransformPolicy`.
  template <class TransformPolicy>
  bool holds() const;
  /// the held policy if it is a `TransformPolicy`, else `nullptr`.
  template <class TransformPolicy>
  const TransformPolicy* get_if() const;
#else
  using Base::Base;
#endif

  /// the transform of the held policy.
  Eigen::Matrix3d transform(const Transform_cell& cell) const
  {
    return this->visit([&](const auto& policy) -> Eigen::Matrix3d { return policy.transform(cell); });
  }
};

/*!
\ingroup PkgLaplacianDeformationPolicies

\brief The seven built-in transform policies chosen at run time: `Scaled_rotation_transform`
(the default), `Fixed_transform`, `Rotation_transform`, `Similarity_transform`,
`Principal_scaled_rotation_transform`, `Rotation_scale_rotation_transform` or
`Anchored_scaled_rotation_transform` (see \ref LapDefRunTime).

\cgalModels{DeformationTransformPolicy}
*/
typedef Transform_policy_variant<Scaled_rotation_transform, Fixed_transform, Rotation_transform,
                                 Similarity_transform, Principal_scaled_rotation_transform,
                                 Rotation_scale_rotation_transform, Anchored_scaled_rotation_transform>
    Any_transform;

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_ANY_TRANSFORM_H
