// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_SCALED_ROTATION_TRANSFORM_H
#define CGAL_LAPLACIAN_DEFORMATION_SCALED_ROTATION_TRANSFORM_H

#include <CGAL/Laplacian_deformation/internal/batched_transforms.h>
#include <CGAL/Laplacian_deformation/internal/closest_rotation_3.h>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationPolicies

\brief The paper's `T_a = S_a R1_a` (section 3.4): rotation, then anisotropic scale along the
world axes.

`R1_a` as in `Rotation_transform`; then, with `f = R1_a e_ab`, for each world axis `c` in
`{x, y, z}`: <code>s_c = sum c_ab e'_c f_c / sum c_ab f_c^2</code>, and `S_a = diag(s_x, s_y, s_z)`.

<b>Guards.</b> Where the denominator of an axis is below `1e-6` times `sum c_ab |f|^2` (the cell
does not extend along that axis, e.g. a flat cell aligned with a world plane), the cell's
isotropic scale <code>sum c_ab e'.f / sum c_ab |f|^2</code> is used for that axis, which keeps uniform
scalings a fixed point (falling back to 1 would break it by about the guard size).
Every scale factor is clamped to `[1e-2, 1e2]`.

<b>Invariance.</b> The scale axes are the world axes, so this policy is <em>not</em> invariant under a
rotation of the whole problem: rotating mesh and targets together can change the result
(see `Principal_scaled_rotation_transform` for a rotation-invariant variant). It is invariant
under translations and uniform scalings. World-axis S*R1 can drift over many iterations; the
paper uses 3 to 4.

\cgalModels{DeformationTransformPolicy}
*/
struct Scaled_rotation_transform
{
  /// returns `S_a R1_a`.
  Eigen::Matrix3d transform(const Transform_cell& cell) const
  {
    const Eigen::Matrix3d r = internal::closest_rotation(cell.covariance());
    return internal::Scale_fit::along_world_axes(cell, r).asDiagonal() * r;
  }

  /// computes `out[i] = transform(cells[i])` for `i < n`, several cells at a time with the
  /// vectorised kernels of the batched local step (see \ref LapDefPerformance; the results are
  /// those of `transform()`).
  void transform_block(const Transform_cell* cells, std::size_t n, Eigen::Matrix3d* out) const
  {
    internal::batched::transform_cells<internal::batched::Stage::scaled_rotation>(*this, cells, n, out);
  }

  /// \cond SKIP_IN_MANUAL
  // the same on m cells that the caller has gathered into `b` (internal::batched::begin_lanes())
  void transform_lanes(internal::batched::Lanes& b, int m, Eigen::Matrix3d* out) const
  {
    internal::batched::fit_lanes<internal::batched::Stage::scaled_rotation>(internal::batched::batch_target(), *this, b, m,
                                                              internal::batched::Lane_cells(b), out);
  }
  /// \endcond
};

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_SCALED_ROTATION_TRANSFORM_H
