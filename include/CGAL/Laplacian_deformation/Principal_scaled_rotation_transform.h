// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_PRINCIPAL_SCALED_ROTATION_TRANSFORM_H
#define CGAL_LAPLACIAN_DEFORMATION_PRINCIPAL_SCALED_ROTATION_TRANSFORM_H

#include <CGAL/Laplacian_deformation/internal/batched_transforms.h>
#include <CGAL/Laplacian_deformation/internal/closest_rotation_3.h>

#include <Eigen/Eigenvalues>

#include <cmath>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationPolicies

\brief A rotation-invariant anisotropic variant of S*R1 (beyond the paper): the scale axes are
the rest cell's own principal axes, rotated by `R_a`.

Let `q_1, q_2, q_3` be the eigenvectors of the rest covariance `sum c_ab e_ab e_ab^T` by
decreasing eigenvalue (`q_3` approximates the surface normal) and `u_k = R_a q_k`. The two
tangential scales are the 1-D fits <code>s_k = sum c (e'.u_k)(f.u_k) / sum c (f.u_k)^2</code>, `f = R_a e_ab`
(with the same guards as `Scaled_rotation_transform`), and the normal scale is tied to their
geometric mean `s_3 = sqrt(s_1 s_2)`. Then `T_a = U diag(s) U^T R_a` with `U = [u_1 u_2 u_3]`.

<b>Why tied.</b> In our trials a free scale along the normal drifted and did not even keep rigid
motions; the tied variant behaves better but can still stall around `1e-2` of the bounding-box
diagonal on some meshes, where `Similarity_transform` converged in every trial.

<b>Invariance.</b> Invariant under every similarity of the whole problem. Caveat: where the two
tangential rest eigenvalues of a cell coincide (regular grids, isotropic cells) the principal
frame is decided by round-off, so results can differ at about `1e-7` of the diagonal between
a problem and its translated or scaled copy (measured on a 12x12 bumpy grid).

\cgalModels{DeformationTransformPolicy}
*/
struct Principal_scaled_rotation_transform
{
  /// returns `U diag(s) U^T R_a`.
  Eigen::Matrix3d transform(const Transform_cell& cell) const
  {
    const Eigen::Matrix3d r = internal::closest_rotation(cell.covariance());
    const Eigen::Matrix3d u = r * rest_axes(cell);
    Eigen::Vector3d s = internal::Scale_fit::along_axes(cell, r, u);
    s[2] = std::sqrt(s[0] * s[1]);
    return u * s.asDiagonal() * u.transpose() * r;
  }

  /// \cond SKIP_IN_MANUAL
  // q = [q_1 q_2 q_3], the eigenvectors of the rest covariance by decreasing eigenvalue (the
  // batched path takes them from here too, so that both see the same frame)
  static Eigen::Matrix3d rest_axes(const Transform_cell& cell)
  {
    Eigen::Matrix3d rest = Eigen::Matrix3d::Zero();
    for(std::size_t i = 0; i < cell.size(); ++i)
      rest.noalias() += cell.weight(i) * cell.rest(i) * cell.rest(i).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(rest);
    // eigenvalues in increasing order: reverse so that the normal is the last axis
    return eigen.eigenvectors().rowwise().reverse();
  }
  /// \endcond

  /// computes `out[i] = transform(cells[i])` for `i < n`, several cells at a time with the
  /// vectorised kernels of the batched local step (see \ref LapDefPerformance; the results are
  /// those of `transform()`).
  void transform_block(const Transform_cell* cells, std::size_t n, Eigen::Matrix3d* out) const
  {
    internal::batched::transform_cells<internal::batched::Stage::principal_scaled_rotation>(*this, cells, n, out, &rest_axes);
  }

  /// \cond SKIP_IN_MANUAL
  // the same on m cells that the caller has gathered into `b` (internal::batched::begin_lanes())
  void transform_lanes(internal::batched::Lanes& b, int m, Eigen::Matrix3d* out) const
  {
    internal::batched::fit_lanes<internal::batched::Stage::principal_scaled_rotation>(internal::batched::batch_target(), *this, b, m,
                                                              internal::batched::Lane_cells(b), out, &rest_axes);
  }
  /// \endcond
};

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_PRINCIPAL_SCALED_ROTATION_TRANSFORM_H
