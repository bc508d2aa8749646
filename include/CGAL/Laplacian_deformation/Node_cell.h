// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_NODE_CELL_H
#define CGAL_LAPLACIAN_DEFORMATION_NODE_CELL_H

#include <Eigen/Core>

#include <array>
#include <cstddef>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationPolicies

\brief The rest cell of one node, as seen by a weight policy: the node position `x_a`,
its neighbours' positions `x_b`, `b` in `N(a)`, and its fan triangles.

A fan triangle `(x_a, x_b, x_c)` is given by the local indices of `b` and `c` in the neighbour
list. This is a read-only view: it does not own the points.

\tparam GeomTraits a model of `Kernel`; points are `GeomTraits::Point_3`.
*/
template <class GeomTraits>
class Node_cell
{
public:
  /// The geometric traits.
  typedef GeomTraits Geom_traits;
  /// The point type.
  typedef typename GeomTraits::Point_3 Point_3;

  /// \cond SKIP_IN_MANUAL
  Node_cell(const Point_3& center, const Point_3* neighbors, std::size_t number_of_neighbors,
            const std::array<std::size_t, 2>* fans, std::size_t number_of_fans,
            const GeomTraits& traits)
    : m_center(center), m_neighbors(neighbors), m_number_of_neighbors(number_of_neighbors),
      m_fans(fans), m_number_of_fans(number_of_fans), m_traits(traits)
  {}
  /// \endcond

  /// the node position `x_a`.
  const Point_3& center() const { return m_center; }
  /// `|N(a)|`.
  std::size_t number_of_neighbors() const { return m_number_of_neighbors; }
  /// the position of the `i`-th neighbour.
  const Point_3& neighbor(std::size_t i) const { return m_neighbors[i]; }
  /// the number of fan triangles.
  std::size_t number_of_fan_triangles() const { return m_number_of_fans; }
  /// the local neighbour indices `(b, c)` of the `k`-th fan triangle `(x_a, x_b, x_c)`.
  const std::array<std::size_t, 2>& fan_triangle(std::size_t k) const { return m_fans[k]; }
  /// the traits.
  const GeomTraits& traits() const { return m_traits; }

private:
  const Point_3& m_center;
  const Point_3* m_neighbors;
  std::size_t m_number_of_neighbors;
  const std::array<std::size_t, 2>* m_fans;
  std::size_t m_number_of_fans;
  const GeomTraits& m_traits;
};

/*!
\ingroup PkgLaplacianDeformationPolicies

\brief The cell of one node, as seen by a transform policy: for each spoke `(a, b)`, the rest
edge vector `e_ab = x_a - x_b`, the current one <code>e'_ab</code>, and the fit weight `c_ab = max(w_ab, 0)`.

A read-only view over the deformer's arrays. `Mesh_deformer` scales the rest and current edge
vectors of a cell by one power of two, so that their largest coordinate is close to 1 (see
`DeformationTransformPolicy`); the weights are not scaled.
*/
class Transform_cell
{
public:
  /// \cond SKIP_IN_MANUAL
  Transform_cell(const Eigen::Vector3d* rest, const Eigen::Vector3d* current,
                 const double* weights, std::size_t size)
    : m_rest(rest), m_current(current), m_weights(weights), m_size(size)
  {}
  /// \endcond

  /// the number of spokes `|N(a)|`.
  std::size_t size() const { return m_size; }
  /// the rest edge vector `e_ab` of spoke `i`.
  const Eigen::Vector3d& rest(std::size_t i) const { return m_rest[i]; }
  /// the current edge vector <code>e'_ab</code> of spoke `i`.
  const Eigen::Vector3d& current(std::size_t i) const { return m_current[i]; }
  /// the non-negative fit weight `c_ab` of spoke `i`.
  double weight(std::size_t i) const { return m_weights[i]; }

  /// <code>sum_i c_i e'_i e_i^T</code>, the weighted cross-covariance every rotation fit starts from.
  Eigen::Matrix3d covariance() const
  {
    Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
    for(std::size_t i = 0; i < m_size; ++i)
      s.noalias() += m_weights[i] * m_current[i] * m_rest[i].transpose();
    return s;
  }

private:
  const Eigen::Vector3d* m_rest;
  const Eigen::Vector3d* m_current;
  const double* m_weights;
  std::size_t m_size;
};

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_NODE_CELL_H
