// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_ROTATION_TRANSFORM_H
#define CGAL_LAPLACIAN_DEFORMATION_ROTATION_TRANSFORM_H

#include <CGAL/Laplacian_deformation/internal/batched_transforms.h>
#include <CGAL/Laplacian_deformation/internal/closest_rotation_3.h>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationPolicies

\brief `T_a = R_a`, the rotation closest to the cell's deformation (Sorkine and Alexa 2007).

<code>R_a = argmin_R sum c_ab |e'_ab - R e_ab|^2</code> over proper rotations, from the SVD of
<code>sum c_ab e'_ab e_ab^T</code> with the reflection fix. With this policy the deformer is an
as-rigid-as-possible method on the chosen representation. A rigid motion of all constraints is
a fixed point and, on closed meshes, the limit of the iterations; a uniform scaling is not
reached (the details keep their rest size). Invariant under rigid motions and uniform scalings
of the whole problem.

\cgalModels{DeformationTransformPolicy}
*/
struct Rotation_transform
{
  /// returns `R_a`.
  Eigen::Matrix3d transform(const Transform_cell& cell) const
  {
    return internal::closest_rotation(cell.covariance());
  }

  /// computes `out[i] = transform(cells[i])` for `i < n`, several cells at a time with the
  /// vectorised kernels of the batched local step (see \ref LapDefPerformance; the results are
  /// those of `transform()`).
  void transform_block(const Transform_cell* cells, std::size_t n, Eigen::Matrix3d* out) const
  {
    internal::batched::transform_cells<internal::batched::Stage::rotation>(*this, cells, n, out);
  }

  /// \cond SKIP_IN_MANUAL
  // the same on m cells that the caller has gathered into `b` (internal::batched::begin_lanes())
  void transform_lanes(internal::batched::Lanes& b, int m, Eigen::Matrix3d* out) const
  {
    internal::batched::fit_lanes<internal::batched::Stage::rotation>(internal::batched::batch_target(), *this, b, m,
                                                              internal::batched::Lane_cells(b), out);
  }
  /// \endcond
};

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_ROTATION_TRANSFORM_H
