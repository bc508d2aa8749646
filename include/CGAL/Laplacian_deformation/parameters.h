// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_PARAMETERS_H
#define CGAL_LAPLACIAN_DEFORMATION_PARAMETERS_H

#include <CGAL/Named_function_parameters.h>

namespace CGAL {
namespace Laplacian_deformation {

/// \cond SKIP_IN_MANUAL
namespace internal_np {
enum representation_t { representation };
enum weight_policy_t { weight_policy };
enum transform_policy_t { transform_policy };
enum tolerance_t { tolerance };
enum soft_constraint_weight_t { soft_constraint_weight };
enum concurrency_tag_t { concurrency_tag };
enum start_t { start };
} // namespace internal_np
/// \endcond

/// Package-only named parameters of `deform_mesh()`; each also has an overload that appends to
/// an existing pack, e.g. `parameters::tolerance(0, CGAL::parameters::number_of_iterations(3))`.
namespace parameters {

/// \cond SKIP_IN_MANUAL
#define CGAL_LAPLACIAN_DEFORMATION_PARAMETER(NAME)                                                  \
  template <class T>                                                                                \
  CGAL::Named_function_parameters<T, internal_np::NAME##_t> NAME(const T& t)                        \
  {                                                                                                 \
    return CGAL::Named_function_parameters<T, internal_np::NAME##_t>(t);                            \
  }                                                                                                 \
  template <class T, class T2, class Tag2, class Base2>                                             \
  CGAL::Named_function_parameters<T, internal_np::NAME##_t, CGAL::Named_function_parameters<T2, Tag2, Base2>> \
  NAME(const T& t, const CGAL::Named_function_parameters<T2, Tag2, Base2>& np)                     \
  {                                                                                                 \
    return CGAL::Named_function_parameters<T, internal_np::NAME##_t,                                \
                                           CGAL::Named_function_parameters<T2, Tag2, Base2>>(t, np);\
  }
CGAL_LAPLACIAN_DEFORMATION_PARAMETER(representation)
CGAL_LAPLACIAN_DEFORMATION_PARAMETER(weight_policy)
CGAL_LAPLACIAN_DEFORMATION_PARAMETER(transform_policy)
CGAL_LAPLACIAN_DEFORMATION_PARAMETER(tolerance)
CGAL_LAPLACIAN_DEFORMATION_PARAMETER(soft_constraint_weight)
CGAL_LAPLACIAN_DEFORMATION_PARAMETER(concurrency_tag)
CGAL_LAPLACIAN_DEFORMATION_PARAMETER(start)
#undef CGAL_LAPLACIAN_DEFORMATION_PARAMETER
/// \endcond

} // namespace parameters
} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_PARAMETERS_H
