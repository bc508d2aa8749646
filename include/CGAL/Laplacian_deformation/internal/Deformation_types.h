// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_INTERNAL_DEFORMATION_TYPES_H
#define CGAL_LAPLACIAN_DEFORMATION_INTERNAL_DEFORMATION_TYPES_H

#include <CGAL/Laplacian_deformation/Edge_based_representation.h>
#include <CGAL/Laplacian_deformation/Cotangent_weights.h>
#include <CGAL/Laplacian_deformation/Scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Least_squares_solver.h>

#include <CGAL/Default.h>
#include <CGAL/Kernel_traits.h>
#include <CGAL/boost/graph/properties.h>

namespace CGAL {
namespace Laplacian_deformation {
namespace internal {

// The one place where Mesh_deformer's CGAL::Default parameters are resolved.
template <class TriangleMesh, class Representation, class WeightPolicy, class TransformPolicy,
          class SolverTraits, class VertexPointMap>
struct Deformation_types
{
  typedef typename CGAL::Default::Get<Representation, Edge_based_representation>::type Representation_type;
  typedef typename CGAL::Default::Get<WeightPolicy, Cotangent_weights>::type Weight_policy;
  typedef typename CGAL::Default::Get<TransformPolicy, Scaled_rotation_transform>::type Transform_policy;
  typedef typename Least_squares_solver<SolverTraits>::Solver_traits Solver_traits;
  typedef typename CGAL::Default::Get<
      VertexPointMap, typename boost::property_map<TriangleMesh, CGAL::vertex_point_t>::type>::type
      Vertex_point_map;
  typedef typename boost::property_traits<Vertex_point_map>::value_type Point;
  typedef typename CGAL::Kernel_traits<Point>::Kernel Geom_traits;
  typedef typename Representation_type::template Nodes<TriangleMesh, Vertex_point_map> Nodes;
};

} // namespace internal
} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_INTERNAL_DEFORMATION_TYPES_H
