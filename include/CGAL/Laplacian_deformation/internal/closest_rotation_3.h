// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_INTERNAL_CLOSEST_ROTATION_3_H
#define CGAL_LAPLACIAN_DEFORMATION_INTERNAL_CLOSEST_ROTATION_3_H

#include <CGAL/Laplacian_deformation/Node_cell.h>

#include <Eigen/Core>
#include <Eigen/Geometry>   // cross()
#include <Eigen/LU>         // determinant()
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

namespace CGAL {
namespace Laplacian_deformation {
namespace internal {

// The power of two that brings `largest` (a magnitude, >= 0) into [1/2, 1); 1 for zero, NaN or
// infinity. Multiplying by it is exact (no rounding) unless the product is subnormal, so a
// computation that is homogeneous in its input gives bitwise the same result on the scaled input,
// without the overflows and underflows of squares and products far from 1. For a subnormal
// `largest` the factor stops at 2^1000 (finite).
// Computed from the bits of `largest` (the local step calls it twice per cell; std::frexp and
// std::ldexp are library calls): bitwise the value of std::ldexp(1., -max(e, -1000)) with e the
// exponent of std::frexp(largest) (test NormalizingPowerOfTwo.BitwiseTheLibraryValue).
inline double normalizing_power_of_two(double largest)
{
  if(!(largest > 0) || !(largest <= (std::numeric_limits<double>::max)()))
    return 1.;
  std::uint64_t bits;
  std::memcpy(&bits, &largest, sizeof bits);
  const int biased = int(bits >> 52);                  // the sign bit is 0: largest > 0
  // frexp's exponent of a normal number is biased - 1022; subnormals (biased 0) are below 2^-1000
  const int exponent = biased == 0 ? -1000 : (std::max)(biased - 1022, -1000);
  // 2^-exponent, exponent in [-1000, 1024]: normal down to 2^-1022, subnormal for 2^-1023, 2^-1024
  const int power = -exponent;
  const std::uint64_t result_bits = power >= -1022 ? std::uint64_t(power + 1023) << 52
                                                   : std::uint64_t(1) << (52 + (power + 1022));
  double result;
  std::memcpy(&result, &result_bits, sizeof result);
  return result;
}


// argmax_R trace(R^T S) over proper rotations, S = sum c e' e^T (Sorkine and Alexa 2007):
// R = U V^T from the SVD S = U Sigma V^T, with the sign of the column of U of the smallest
// singular value flipped when det(U V^T) < 0. Eigen's JacobiSVD sorts singular values in
// decreasing order, so that column is the last one. The reference (and fallback) computation.
// A non-finite `s` gives NaN (JacobiSVD leaves U and V uninitialised on such input).
inline Eigen::Matrix3d closest_rotation_svd(const Eigen::Matrix3d& s)
{
  if(!s.allFinite())
    return Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(s, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  const Eigen::Matrix3d& v = svd.matrixV();
  if((u * v.transpose()).determinant() < 0)
    u.col(2) = -u.col(2);
  return u * v.transpose();
}

// Eigen-decomposition of the symmetric 3x3 matrix `a` by cyclic Jacobi rotations (the
// Numerical Recipes update): on return `a` is diagonal to round-off and a_in = v a v^T,
// `v` orthogonal. Allocation-free, a few hundred flops (3 or 4 sweeps in practice). For entries
// of magnitude between about 1e-100 and 1e100 (closest_rotation() calls it on S^T S with S scaled
// into [1/2, 1)): the squares of the rotation angle's formula neither overflow nor underflow.
inline void symmetric_eigen_jacobi_3(Eigen::Matrix3d& a, Eigen::Matrix3d& v)
{
  v.setIdentity();
  for(int sweep = 0; sweep < 24; ++sweep)
  {
    const double off = a(0, 1) * a(0, 1) + a(0, 2) * a(0, 2) + a(1, 2) * a(1, 2);
    const double diag = a(0, 0) * a(0, 0) + a(1, 1) * a(1, 1) + a(2, 2) * a(2, 2);
    if(!(off > 1e-32 * diag))              // off-diagonal at round-off; also stops on zero and NaN
      return;
    for(int k = 0; k < 3; ++k)
    {
      const int p = (k == 2) ? 1 : 0, q = (k == 0) ? 1 : 2;   // (0,1), (0,2), (1,2)
      const double apq = a(p, q);
      if(apq == 0)
        continue;
      // t = tan of the rotation angle, the root of smaller magnitude of t^2 + 2 theta t - 1 = 0,
      // theta = d / (2 a_pq): sign(theta) / (|theta| + sqrt(theta^2 + 1)) written as
      // sign(d) 2 a_pq / (|d| + sqrt(d^2 + 4 a_pq^2)) (one division less on the chain); then
      // c = 1 / x, s = t c and tau = s / (1 + c) = t / (x + 1) with x = sqrt(t^2 + 1), so that the
      // two divisions after the second square root are independent
      const double d = a(q, q) - a(p, p);
      const double root = std::sqrt(d * d + 4 * apq * apq);
      double t = (2 * apq) / (std::abs(d) + root);
      if(d < 0)
        t = -t;
      const double x = std::sqrt(t * t + 1.);
      const double c = 1. / x, sn = t * c, tau = t / (x + 1.), h = t * apq;
      a(p, p) -= h;
      a(q, q) += h;
      a(p, q) = a(q, p) = 0;
      const int r = 3 - p - q;
      const double g = a(r, p), hh = a(r, q);
      a(r, p) = a(p, r) = g - sn * (hh + g * tau);
      a(r, q) = a(q, r) = hh + sn * (g - hh * tau);
      for(int j = 0; j < 3; ++j)
      {
        const double vg = v(j, p), vh = v(j, q);
        v(j, p) = vg - sn * (vh + vg * tau);
        v(j, q) = vh + sn * (vg - vh * tau);
      }
    }
  }
}

// The same rotation as closest_rotation_svd(), computed from the eigenvectors v1, v2 of S^T S
// (two largest eigenvalues): u1 = S v1 / |S v1|, u2 = the part of S v2 orthogonal to u1,
// normalised, u3 = u1 x u2, v3 = v1 x v2, R = U V^T (a proper rotation by construction; the
// sign flip of the smallest singular direction is the u3 = u1 x u2 choice). Squaring S costs
// accuracy in the second direction by (sigma1 / sigma2)^2, so cells whose second singular value
// is below 1e-2 of the first (nearly collinear cells, rare) and non-finite input go to the SVD:
// the result then agrees with closest_rotation_svd() to about 1e4 x machine epsilon.
// The rotation does not depend on the magnitude of S: S is first scaled by the power of two that
// brings its largest entry into [1/2, 1) (exact in floating point, so the result is bitwise the
// same as without scaling wherever S^T S neither overflows nor underflows); without it S^T S
// overflows or underflows beyond about 1e+-77 and the eigenvectors come out as the identity.
inline Eigen::Matrix3d closest_rotation(const Eigen::Matrix3d& s_in)
{
  const double largest = s_in.cwiseAbs().maxCoeff();
  if(!std::isfinite(largest))
    return closest_rotation_svd(s_in);     // NaN or infinite: the caller sees a non-finite result
  const Eigen::Matrix3d s = normalizing_power_of_two(largest) * s_in;
  Eigen::Matrix3d a = s.transpose() * s, v;
  symmetric_eigen_jacobi_3(a, v);
  int i0 = 0, i1 = 1, i2 = 2;
  if(a(i0, i0) < a(i1, i1)) std::swap(i0, i1);
  if(a(i1, i1) < a(i2, i2)) std::swap(i1, i2);
  if(a(i0, i0) < a(i1, i1)) std::swap(i0, i1);
  const Eigen::Vector3d v1 = v.col(i0), v2 = v.col(i1);
  const Eigen::Vector3d b1 = s * v1;
  const double n1 = b1.norm();
  if(n1 == 0)
    return Eigen::Matrix3d::Identity();    // no information: what the SVD gives for S = 0
  const Eigen::Vector3d u1 = b1 / n1;
  Eigen::Vector3d b2 = s * v2;
  b2 -= u1.dot(b2) * u1;
  const double n2 = b2.norm();
  if(!(n2 > 1e-2 * n1) || !std::isfinite(n1))
    return closest_rotation_svd(s);
  const Eigen::Vector3d u2 = b2 / n2;
  Eigen::Matrix3d u, w;
  u << u1, u2, u1.cross(u2);
  w << v1, v2, v1.cross(v2);
  return u * w.transpose();
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
    return fit(cell, m, [&axes](const Eigen::Vector3d& x) -> Eigen::Vector3d { return axes.transpose() * x; });
  }
  // along_axes(cell, m, I), without the projections
  static Eigen::Vector3d along_world_axes(const Transform_cell& cell, const Eigen::Matrix3d& m)
  {
    return fit(cell, m, [](const Eigen::Vector3d& x) -> const Eigen::Vector3d& { return x; });
  }

private:
  template <class Project>
  static Eigen::Vector3d fit(const Transform_cell& cell, const Eigen::Matrix3d& m, const Project& project)
  {
    Eigen::Vector3d num = Eigen::Vector3d::Zero(), den = Eigen::Vector3d::Zero();
    double total = 0, iso_num = 0;
    for(std::size_t i = 0; i < cell.size(); ++i)
    {
      const Eigen::Vector3d f = m * cell.rest(i);
      const Eigen::Vector3d fa = project(f);
      const Eigen::Vector3d ea = project(cell.current(i));
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
