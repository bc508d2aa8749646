// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_UNIFORM_WEIGHTS_H
#define CGAL_LAPLACIAN_DEFORMATION_UNIFORM_WEIGHTS_H

#include <CGAL/Laplacian_deformation/Node_cell.h>

#include <vector>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationPolicies

\brief Uniform (umbrella) weights: `w_ab = 1 / |N(a)|`.

The Laplacian coordinate is then the vector from the centroid of the neighbours to the node.
Purely combinatorial: always finite and positive, invariant under every similarity of the mesh,
but without linear precision (a planar irregular mesh has non-zero Laplacian coordinates).

\cgalModels{DeformationWeightPolicy}
*/
struct Uniform_weights
{
  /// fills `w` (of size `cell.number_of_neighbors()`) with `1 / |N(a)|`.
  template <class GeomTraits>
  void weights(const Node_cell<GeomTraits>& cell, std::vector<double>& w) const
  {
    const std::size_t n = cell.number_of_neighbors();
    w.assign(n, n == 0 ? 0. : 1. / static_cast<double>(n));
  }
};

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_UNIFORM_WEIGHTS_H
