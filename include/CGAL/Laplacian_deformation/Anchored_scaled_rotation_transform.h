// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_ANCHORED_SCALED_ROTATION_TRANSFORM_H
#define CGAL_LAPLACIAN_DEFORMATION_ANCHORED_SCALED_ROTATION_TRANSFORM_H

#include <CGAL/Laplacian_deformation/internal/batched_transforms.h>
#include <CGAL/Laplacian_deformation/internal/closest_rotation_3.h>

#include <algorithm>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationPolicies

\brief The paper's `T_a = S_a R1_a` with each scale anchored at 1: an anisotropic policy that
does not drift (see \ref LapDefDrift).

`R1_a` as in `Rotation_transform`; then, with `f = R1_a e_ab`, `F = sum c_ab |f|^2 / 3` and the
anchor `mu = 1`, for each world axis `c` in `{x, y, z}`:
<code>s_c = (sum c_ab e'_c f_c + mu F) / (sum c_ab f_c^2 + mu F)</code>, `S_a = diag(s_x, s_y, s_z)`,
each clamped to `[1e-2, 1e2]`. This is the least-squares scale of the paper's S*R1 with the
penalty <code>mu F (s_c - 1)^2</code>: a cell stretched along an axis still gets its scale there
(a stretch by 1.5 along the axis a cell extends most in gives about 1.3), but a scale that the
cells do not demand is pulled back to 1 at every iteration, so the scales cannot accumulate
from one iteration to the next the way those of `Scaled_rotation_transform` do. Rigid motions of
all constraints are fixed points; uniform scalings are not (the details keep part of their rest
size, as with `Rotation_transform`). Like the paper's S*R1 it is invariant under translations,
not under rotations of the whole problem (world axes).

\cgalModels{DeformationTransformPolicy}
*/
struct Anchored_scaled_rotation_transform
{
  /// the weight of the anchor at 1, relative to the cell's mean squared extent per axis.
  static constexpr double anchor = 1.;

  /// returns `S_a R1_a`.
  Eigen::Matrix3d transform(const Transform_cell& cell) const
  {
    const Eigen::Matrix3d r = internal::closest_rotation(cell.covariance());
    Eigen::Vector3d num = Eigen::Vector3d::Zero(), den = Eigen::Vector3d::Zero();
    for(std::size_t i = 0; i < cell.size(); ++i)
    {
      const Eigen::Vector3d f = r * cell.rest(i);
      num += cell.weight(i) * cell.current(i).cwiseProduct(f);
      den += cell.weight(i) * f.cwiseProduct(f);
    }
    const double prior = anchor * den.sum() / 3;
    if(!(prior > 0))
      return r;
    Eigen::Vector3d s;
    for(int k = 0; k < 3; ++k)
      s[k] = internal::Scale_fit::clamp((num[k] + prior) / (den[k] + prior));
    return s.asDiagonal() * r;
  }

  /// computes `out[i] = transform(cells[i])` for `i < n`, several cells at a time with the
  /// vectorised kernels of the batched local step (see \ref LapDefPerformance; the results are
  /// those of `transform()`).
  void transform_block(const Transform_cell* cells, std::size_t n, Eigen::Matrix3d* out) const
  {
    internal::batched::transform_cells<internal::batched::Stage::anchored_scaled_rotation>(*this, cells, n, out);
  }

  /// \cond SKIP_IN_MANUAL
  // the same on m cells that the caller has gathered into `b` (internal::batched::begin_lanes())
  void transform_lanes(internal::batched::Lanes& b, int m, Eigen::Matrix3d* out) const
  {
    internal::batched::fit_lanes<internal::batched::Stage::anchored_scaled_rotation>(internal::batched::batch_target(), *this, b, m,
                                                              internal::batched::Lane_cells(b), out);
  }
  /// \endcond
};

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_ANCHORED_SCALED_ROTATION_TRANSFORM_H
