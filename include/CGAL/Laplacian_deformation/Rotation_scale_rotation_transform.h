// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_ROTATION_SCALE_ROTATION_TRANSFORM_H
#define CGAL_LAPLACIAN_DEFORMATION_ROTATION_SCALE_ROTATION_TRANSFORM_H

#include <CGAL/Laplacian_deformation/Scaled_rotation_transform.h>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationPolicies

\brief The paper's full `T_a = R2_a S_a R1_a` (equation 8), fitted in the paper's order.

`S_a R1_a` exactly as `Scaled_rotation_transform`; then `R2_a` is the rotation closest to
mapping `S_a R1_a e_ab` onto <code>e'_ab</code> (the SVD of <code>sum c_ab e'_ab (S_a R1_a e_ab)^T</code>). The paper
drops `R2` ("little effect on the final result"); this policy exists to measure that claim.
Like `Scaled_rotation_transform`, not invariant under rotations of the whole problem.

\cgalModels{DeformationTransformPolicy}
*/
struct Rotation_scale_rotation_transform
{
  /// returns `R2_a S_a R1_a`.
  Eigen::Matrix3d transform(const Transform_cell& cell) const
  {
    const Eigen::Matrix3d sr = Scaled_rotation_transform().transform(cell);
    Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
    for(std::size_t i = 0; i < cell.size(); ++i)
      s.noalias() += cell.weight(i) * cell.current(i) * (sr * cell.rest(i)).transpose();
    return internal::closest_rotation(s) * sr;
  }

  /// computes `out[i] = transform(cells[i])` for `i < n`, several cells at a time with the
  /// vectorised kernels of the batched local step (see \ref LapDefPerformance; the results are
  /// those of `transform()`).
  void transform_block(const Transform_cell* cells, std::size_t n, Eigen::Matrix3d* out) const
  {
    internal::batched::transform_cells<internal::batched::Stage::scaled_rotation_then_covariance>(*this, cells, n, out);
  }

  /// \cond SKIP_IN_MANUAL
  // the same on m cells that the caller has gathered into `b` (internal::batched::begin_lanes())
  void transform_lanes(internal::batched::Lanes& b, int m, Eigen::Matrix3d* out) const
  {
    internal::batched::fit_lanes<internal::batched::Stage::scaled_rotation_then_covariance>(internal::batched::batch_target(), *this, b, m,
                                                              internal::batched::Lane_cells(b), out);
  }
  /// \endcond
};

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_ROTATION_SCALE_ROTATION_TRANSFORM_H
