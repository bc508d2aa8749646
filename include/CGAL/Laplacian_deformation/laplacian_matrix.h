// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_LAPLACIAN_MATRIX_H
#define CGAL_LAPLACIAN_DEFORMATION_LAPLACIAN_MATRIX_H

#include <CGAL/Laplacian_deformation/internal/Laplacian_stencils.h>

#include <CGAL/boost/graph/named_params_helper.h>
#include <CGAL/Named_function_parameters.h>

#include <Eigen/SparseCore>

#include <vector>

namespace CGAL {
namespace Laplacian_deformation {

namespace internal {

// positions of all vertices, indexed by the vertex index map
template <class TriangleMesh, class VertexPointMap, class VertexIndexMap>
std::vector<Eigen::Vector3d> vertex_positions(const TriangleMesh& tm, const VertexPointMap& vpm,
                                              const VertexIndexMap& vim)
{
  std::vector<Eigen::Vector3d> p(static_cast<std::size_t>(num_vertices(tm)));
  for(auto v : vertices(tm))
  {
    const auto& q = get(vpm, v);
    p[static_cast<std::size_t>(get(vim, v))] =
        Eigen::Vector3d(CGAL::to_double(q.x()), CGAL::to_double(q.y()), CGAL::to_double(q.z()));
  }
  return p;
}

// the stencils of `representation` on `tm` with their fan triangles, weighted by `weights` (as
// they are: not scale-safe)
template <class Representation, class WeightPolicy, class TriangleMesh, class VertexPointMap,
          class VertexIndexMap, class GeomTraits>
Laplacian_stencils weighted_stencils(const TriangleMesh& tm, const Representation&, const WeightPolicy& weights,
                                     const VertexPointMap& vpm, const VertexIndexMap& vim, const GeomTraits& gt)
{
  const typename Representation::template Nodes<TriangleMesh, VertexPointMap> nodes(tm, vpm);
  Laplacian_stencils s;
  std::vector<Eigen::Vector3d> x;
  build_weighted_stencils(s, x, nodes, vim, vertex_positions(tm, vpm, vim), weights, gt, false, 0.);
  return s;
}

// the rest operator of `representation` on `tm`, weighted by `weights` (the shared rest-operator
// builder; `scale_safe`: see build_rest_operator())
template <class Representation, class WeightPolicy, class TriangleMesh, class VertexPointMap,
          class VertexIndexMap, class GeomTraits>
Rest_operator rest_operator(const TriangleMesh& tm, const Representation&, const WeightPolicy& weights,
                            const VertexPointMap& vpm, const VertexIndexMap& vim, const GeomTraits& gt,
                            bool scale_safe)
{
  const typename Representation::template Nodes<TriangleMesh, VertexPointMap> nodes(tm, vpm);
  Rest_operator r;
  const std::vector<Eigen::Vector3d> rest = vertex_positions(tm, vpm, vim);
  build_rest_operator(r, nodes, vim, rest, weights, gt, false, scale_safe ? largest_coordinate(rest) : 0.);
  return r;
}

} // namespace internal

/*!
\ingroup PkgLaplacianDeformationFunctions

\brief returns the Laplacian operator `D = L_w P` of `tm` in the given representation and weights.

Row `a` (in the representation's dense node index) gives the Laplacian coordinate of node `a`
as a linear combination of the vertex positions: `delta_a = sum_b w_ab (x_a - x_b) = (D p)_a`,
with columns in the order of the vertex index map. `D` annihilates constant fields.

\tparam TriangleMesh a model of `FaceGraph`; its faces may be polygons (see \ref LapDefPolygons)
\tparam Representation a model of `DeformationRepresentation`
\tparam WeightPolicy a model of `DeformationWeightPolicy`

\cgalNamedParamsBegin
  \cgalParamNBegin{vertex_point_map}
    \cgalParamDescription{a property map associating points to the vertices of `tm`}
    \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
  \cgalParamNEnd
  \cgalParamNBegin{vertex_index_map}
    \cgalParamDescription{a property map associating to each vertex of `tm` a unique index between `0` and `num_vertices(tm) - 1`}
    \cgalParamDefault{an automatically indexed internal map}
  \cgalParamNEnd
  \cgalParamNBegin{geom_traits}
    \cgalParamDescription{an instance of a geometric traits class, model of `Kernel`}
    \cgalParamDefault{the kernel of the point type of the vertex point map}
  \cgalParamNEnd
\cgalNamedParamsEnd
*/
template <class TriangleMesh, class Representation, class WeightPolicy,
          class NamedParameters = CGAL::parameters::Default_named_parameters>
Eigen::SparseMatrix<double> laplacian_matrix(const TriangleMesh& tm,
                                             const Representation& representation,
                                             const WeightPolicy& weights,
                                             const NamedParameters& np = CGAL::parameters::default_values())
{
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  const auto vpm = choose_parameter(get_parameter(np, CGAL::internal_np::vertex_point),
                                    get_const_property_map(CGAL::vertex_point, tm));
  const auto vim = CGAL::get_initialized_vertex_index_map(tm, np);
  const auto gt = choose_parameter<typename GetGeomTraits<TriangleMesh, NamedParameters>::type>(
      get_parameter(np, CGAL::internal_np::geom_traits));
  return Eigen::SparseMatrix<double>(internal::rest_operator(tm, representation, weights, vpm, vim, gt, false).d);
}

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_LAPLACIAN_MATRIX_H
