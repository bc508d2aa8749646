// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_SIMILARITY_TRANSFORM_H
#define CGAL_LAPLACIAN_DEFORMATION_SIMILARITY_TRANSFORM_H

#include <CGAL/Laplacian_deformation/internal/batched_transforms.h>
#include <CGAL/Laplacian_deformation/internal/closest_rotation_3.h>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationPolicies

\brief `T_a = s_a R_a`: rotation and isotropic scale (beyond the paper).

`R_a` as in `Rotation_transform`, then <code>s_a = sum c e'.f / sum c |f|^2</code> with `f = R_a e_ab`,
clamped to `[1e-2, 1e2]`. A rigid motion or a uniform scaling of all constraints is a fixed
point and the limit of the iterations. Invariant under every similarity of the whole problem.

\cgalModels{DeformationTransformPolicy}
*/
struct Similarity_transform
{
  /// returns `s_a R_a`.
  Eigen::Matrix3d transform(const Transform_cell& cell) const
  {
    const Eigen::Matrix3d r = internal::closest_rotation(cell.covariance());
    return internal::Scale_fit::isotropic(cell, r) * r;
  }

  /// computes `out[i] = transform(cells[i])` for `i < n`, several cells at a time with the
  /// vectorised kernels of the batched local step (see \ref LapDefPerformance; the results are
  /// those of `transform()`).
  void transform_block(const Transform_cell* cells, std::size_t n, Eigen::Matrix3d* out) const
  {
    internal::batched::transform_cells<internal::batched::Stage::similarity>(*this, cells, n, out);
  }

  /// \cond SKIP_IN_MANUAL
  // the same on m cells that the caller has gathered into `b` (internal::batched::begin_lanes())
  void transform_lanes(internal::batched::Lanes& b, int m, Eigen::Matrix3d* out) const
  {
    internal::batched::fit_lanes<internal::batched::Stage::similarity>(internal::batched::batch_target(), *this, b, m,
                                                              internal::batched::Lane_cells(b), out);
  }
  /// \endcond
};

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_SIMILARITY_TRANSFORM_H
