// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_INTERNAL_CLOSEST_ROTATION_3_H
#define CGAL_LAPLACIAN_DEFORMATION_INTERNAL_CLOSEST_ROTATION_3_H

#include <CGAL/Laplacian_deformation/Node_cell.h>

#include <Eigen/Core>
#include <Eigen/SVD>

#include <algorithm>

namespace CGAL {
namespace Laplacian_deformation {
namespace internal {

// argmax_R trace(R^T S) over proper rotations, S = sum c e' e^T (Sorkine and Alexa 2007):
// R = U V^T from the SVD S = U Sigma V^T, with the sign of the column of U of the smallest
// singular value flipped when det(U V^T) < 0. Eigen's JacobiSVD sorts singular values in
// decreasing order, so that column is the last one.
inline Eigen::Matrix3d closest_rotation(const Eigen::Matrix3d& s)
{
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(s, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  const Eigen::Matrix3d& v = svd.matrixV();
  if((u * v.transpose()).determinant() < 0)
    u.col(2) = -u.col(2);
  return u * v.transpose();
}

// Scale factors used by the scaled policies, each the 1-D least-squares fit
// s = sum c (e'.u)(f.u) / sum c (f.u)^2 along a unit axis u, where f = M e is the already
// transformed rest vector. When the denominator is tiny relative to sum c |f|^2 the axis is
// not seen by the cell, and the cell's isotropic scale is used instead.
struct Scale_fit
{
  static constexpr double axis_guard = 1e-6;     // relative denominator below which an axis is unseen
  static constexpr double min_scale = 1e-2;      // clamp range of every scale factor
  static constexpr double max_scale = 1e2;

  static double clamp(double s) { return std::clamp(s, min_scale, max_scale); }

  // isotropic scale sum c e'.f / sum c |f|^2 (1 when the cell has no extent)
  static double isotropic(const Transform_cell& cell, const Eigen::Matrix3d& m)
  {
    double num = 0, den = 0;
    for(std::size_t i = 0; i < cell.size(); ++i)
    {
      const Eigen::Vector3d f = m * cell.rest(i);
      num += cell.weight(i) * cell.current(i).dot(f);
      den += cell.weight(i) * f.squaredNorm();
    }
    return den > 0 ? clamp(num / den) : 1.;
  }

  // scales along the three orthonormal columns of `axes`
  static Eigen::Vector3d along_axes(const Transform_cell& cell, const Eigen::Matrix3d& m,
                                    const Eigen::Matrix3d& axes)
  {
    Eigen::Vector3d num = Eigen::Vector3d::Zero(), den = Eigen::Vector3d::Zero();
    double total = 0, iso_num = 0;
    for(std::size_t i = 0; i < cell.size(); ++i)
    {
      const Eigen::Vector3d f = m * cell.rest(i);
      const Eigen::Vector3d fa = axes.transpose() * f;
      const Eigen::Vector3d ea = axes.transpose() * cell.current(i);
      const double c = cell.weight(i);
      num += c * ea.cwiseProduct(fa);
      den += c * fa.cwiseProduct(fa);
      total += c * f.squaredNorm();
      iso_num += c * cell.current(i).dot(f);
    }
    if(!(total > 0))
      return Eigen::Vector3d::Ones();
    const double iso = clamp(iso_num / total);
    Eigen::Vector3d s;
    for(int k = 0; k < 3; ++k)
      s[k] = den[k] > axis_guard * total ? clamp(num[k] / den[k]) : iso;
    return s;
  }
};

} // namespace internal
} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_INTERNAL_CLOSEST_ROTATION_3_H
