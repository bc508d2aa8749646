// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_COTANGENT_WEIGHTS_H
#define CGAL_LAPLACIAN_DEFORMATION_COTANGENT_WEIGHTS_H

#include <CGAL/Laplacian_deformation/Node_cell.h>

#include <CGAL/Weights/utils.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationPolicies

\brief Cotangent weights over the node's fan: `w_ab = (cot g1 + cot g2) / (2 Omega_a)`.

`g1`, `g2` are the angles opposite the spoke `(x_a, x_b)` in the (one or two) fan triangles that
contain it, and `Omega_a` is the mixed Voronoi area of `x_a` in its fan (Meyer et al. 2003,
see `mixed_voronoi_area()`). The cotangents come from CGAL's Weights package
(`CGAL::Weights::cotangent()`).

<b>Linear precision.</b> On a planar mesh whose one-rings are strictly convex, the Laplacian
coordinate of every interior node is zero, in both representations (the edge fans of non-convex
rings contain flipped triangles, so the edge-based property is lost there first).

<b>Guards.</b> A fan triangle whose doubled area is below `degenerate_area_ratio` times the sum of its two
squared spoke lengths contributes neither cotangents nor area. Each cotangent is clamped to
`[-max_cotangent, max_cotangent]` (an angle of about 1e-4 rad, or pi minus that), and `Omega_a`
is floored at `area_floor` times the mean squared spoke length of the cell. The weights are then
always finite. Weights can be negative (obtuse angles); transform fits use `max(w, 0)`.

<b>Invariance.</b> Invariant under rigid motions; under a uniform scale by `s` every weight is
multiplied by `1/s^2`, which leaves the deformation unchanged.

\cgalModels{DeformationWeightPolicy}
*/
struct Cotangent_weights
{
  /// the largest absolute value of a cotangent.
  static constexpr double max_cotangent = 1e4;
  /// relative floor of the Voronoi area, in units of the mean squared spoke length.
  static constexpr double area_floor = 1e-6;
  /// relative area below which a fan triangle counts as degenerate.
  static constexpr double degenerate_area_ratio = 1e-12;

  /// The mixed Voronoi area of `a` in the triangle `(a, b, c)` (Meyer et al. 2003): the Voronoi
  /// area `(|ab|^2 cot c + |ac|^2 cot b) / 8` when no angle is obtuse, half the triangle's area
  /// when the angle at `a` is obtuse, a quarter otherwise. This rule is continuous at right
  /// angles. (`CGAL::Weights::mixed_voronoi_area()` of CGAL 5.5 takes half the area whichever
  /// angle is obtuse, which jumps at right angles: on a grid of right triangles a mere translation
  /// changed the operator; hence this function, built on CGAL's cotangents.)
  static double mixed_voronoi_area(double triangle_area, double ab2, double ac2, double cot_b,
                                   double cot_c, double dot_at_a)
  {
    if(dot_at_a < 0)
      return triangle_area / 2;
    if(cot_b < 0 || cot_c < 0)
      return triangle_area / 4;
    return (ab2 * cot_c + ac2 * cot_b) / 8;
  }

  /// fills `w` (of size `cell.number_of_neighbors()`) with the cotangent weights of the cell.
  template <class GeomTraits>
  void weights(const Node_cell<GeomTraits>& cell, std::vector<double>& w) const
  {
    const GeomTraits& gt = cell.traits();
    const auto& a = cell.center();
    const std::size_t n = cell.number_of_neighbors();
    w.assign(n, 0.);
    if(n == 0)
      return;

    auto squared_length = [&](const auto& p, const auto& q) {
      return CGAL::to_double(gt.compute_squared_distance_3_object()(p, q));
    };
    auto clamp = [](double c) { return std::clamp(c, -max_cotangent, max_cotangent); };

    double mean_squared_spoke = 0;
    for(std::size_t i = 0; i < n; ++i)
      mean_squared_spoke += squared_length(a, cell.neighbor(i));
    mean_squared_spoke /= static_cast<double>(n);

    double area = 0;
    for(std::size_t k = 0; k < cell.number_of_fan_triangles(); ++k)
    {
      const auto& t = cell.fan_triangle(k);
      const auto& b = cell.neighbor(t[0]);
      const auto& c = cell.neighbor(t[1]);
      const auto ab = gt.construct_vector_3_object()(a, b), ac = gt.construct_vector_3_object()(a, c);
      const double ab2 = squared_length(a, b), ac2 = squared_length(a, c);
      const double triangle_area = 0.5 * std::sqrt(CGAL::to_double(
          gt.compute_squared_length_3_object()(gt.construct_cross_product_vector_3_object()(ab, ac))));
      if(!(2 * triangle_area > degenerate_area_ratio * (ab2 + ac2)))
        continue;
      // the angle at c is opposite the spoke (a, b), the angle at b opposite (a, c)
      const double cot_c = CGAL::to_double(CGAL::Weights::cotangent(a, c, b, gt));
      const double cot_b = CGAL::to_double(CGAL::Weights::cotangent(a, b, c, gt));
      w[t[0]] += clamp(cot_c);
      w[t[1]] += clamp(cot_b);
      area += mixed_voronoi_area(triangle_area, ab2, ac2, cot_b, cot_c,
                                 CGAL::to_double(gt.compute_scalar_product_3_object()(ab, ac)));
    }
    area = (std::max)(area, area_floor * mean_squared_spoke);
    if(!(area > 0))     // every spoke has zero length: no geometry to encode
    {
      w.assign(n, 0.);
      return;
    }
    for(double& x : w)
      x /= 2 * area;
  }
};

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_COTANGENT_WEIGHTS_H
