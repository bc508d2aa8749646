// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_METRICS_H
#define CGAL_LAPLACIAN_DEFORMATION_METRICS_H

#include <CGAL/Laplacian_deformation/Cotangent_weights.h>
#include <CGAL/Laplacian_deformation/Edge_based_representation.h>
#include <CGAL/Laplacian_deformation/Vertex_based_representation.h>
#include <CGAL/Laplacian_deformation/laplacian_matrix.h>
#include <CGAL/Laplacian_deformation/internal/closest_rotation_3.h>

#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/iterator.h>
#include <CGAL/boost/graph/named_params_helper.h>
#include <CGAL/Named_function_parameters.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <vector>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationMetrics
\brief How well a deformation kept the local shape of a region of interest (ROI): the values
computed by `deformation_quality()`. Every value is 0 for the identity deformation; all but the
two Laplacian errors (which also use the rest Laplacian of the representation, see below) and
the constraint residual are invariant under a rigid motion of the deformed mesh.
*/
struct Deformation_quality
{
  /// vertex-based Laplacian-coordinate error
  /// <code>sqrt(sum_a |delta'_a - R_a delta_a|^2 / sum_a |delta_a|^2)</code> over the vertices
  /// whose cotangent stencil touches the ROI: `delta_a` and `delta'_a` are the rest and deformed
  /// Laplacian coordinates with the rest cotangent weights (`Cotangent_weights`),
  /// `R_a` the rotation that best maps the rest cell vectors `x_a - x_b` of the node onto the
  /// deformed ones (unit weights). Rigid-motion invariant.
  double vertex_laplacian_error = 0;
  /// the same with the edge-midpoint nodes of `Edge_based_representation`.
  double edge_laplacian_error = 0;
  /// mean over the edges with a ROI endpoint of `|l' - l| / l` (`l`: rest length).
  double mean_edge_length_distortion = 0;
  /// the largest `|l' - l| / l` over the edges with a ROI endpoint.
  double max_edge_length_distortion = 0;
  /// mean over the non-border edges with a ROI endpoint of the change of the signed dihedral
  /// angle, in degrees (in `[0, 180]`).
  double mean_dihedral_angle_change = 0;
  /// the largest dihedral-angle change, in degrees.
  double max_dihedral_angle_change = 0;
  /// mean, over the pairs (ROI vertex `v`, face `f` around `v`), of the angle in degrees between
  /// the deformed normal of `f` and its rest normal rotated by `R_v`, the rotation that best maps
  /// the rest one-ring edge vectors of `v` onto the deformed ones (unit weights).
  double mean_normal_deviation = 0;
  /// the largest such angle, in degrees.
  double max_normal_deviation = 0;
  /// the cotangent as-rigid-as-possible energy of the ROI vertices,
  /// <code>sum_v sum_j w_vj |e'_vj - R_v e_vj|^2</code> with `R_v` its minimiser, divided by
  /// <code>sum_v sum_j w_vj |e_vj|^2</code>; `e_vj = p_j - p_v`, `w_vj = max(0, (cot alpha + cot beta) / 2)`
  /// from the rest mesh (negative weights are clamped to 0 so that the energy is non-negative).
  double arap_energy = 0;
  /// the largest distance between a control vertex and its target, divided by the bounding-box
  /// diagonal of the rest mesh (0 when no control is given).
  double max_constraint_residual = 0;
};

namespace internal {

inline double angle_in_degrees(const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180. / 3.14159265358979323846;
}

// unit normal of the triangle (a, b, c), or zero if it is degenerate
inline Eigen::Vector3d unit_normal(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c)
{
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double l = n.norm();
  return l > 0 ? Eigen::Vector3d(n / l) : Eigen::Vector3d::Zero();
}

// cotangent of the angle between u and v, 0 for a degenerate angle
inline double guarded_cotangent(const Eigen::Vector3d& u, const Eigen::Vector3d& v)
{
  const double s = u.cross(v).norm();
  return s > 1e-12 * u.norm() * v.norm() ? u.dot(v) / s : 0.;
}

// rest and deformed positions by vertex index, and the ROI as flags
template <class TriangleMesh, class VertexIndexMap>
struct Metric_context
{
  typedef typename boost::graph_traits<TriangleMesh>::vertex_descriptor vertex_descriptor;
  typedef typename boost::graph_traits<TriangleMesh>::halfedge_descriptor halfedge_descriptor;
  const TriangleMesh& tm;
  VertexIndexMap vim;
  std::vector<Eigen::Vector3d> p0, p1;

  Metric_context(const TriangleMesh& tm, const VertexIndexMap& vim) : tm(tm), vim(vim) {}
  std::size_t id(vertex_descriptor v) const { return static_cast<std::size_t>(get(vim, v)); }
  bool isolated(vertex_descriptor v) const
  {
    return halfedge(v, tm) == boost::graph_traits<TriangleMesh>::null_halfedge();
  }
  // S = sum_j w(h) e'_vj e_vj^T over the halfedges h = (j -> v) around v; returns sum_j w |e_vj|^2
  template <class Weight>
  double one_ring_covariance(vertex_descriptor v, const Weight& w, Eigen::Matrix3d& s) const
  {
    s.setZero();
    double rest = 0;
    if(isolated(v))
      return 0;
    const std::size_t i = id(v);
    for(halfedge_descriptor h : CGAL::halfedges_around_target(halfedge(v, tm), tm))
    {
      const std::size_t j = id(source(h, tm));
      const Eigen::Vector3d e0 = p0[j] - p0[i], e1 = p1[j] - p1[i];
      const double c = w(h);
      s += c * e1 * e0.transpose();
      rest += c * e0.squaredNorm();
    }
    return rest;
  }
  // sum_j w(h) |e'_vj - R e_vj|^2
  template <class Weight>
  double one_ring_residual(vertex_descriptor v, const Weight& w, const Eigen::Matrix3d& r) const
  {
    double sum = 0;
    if(isolated(v))
      return 0;
    const std::size_t i = id(v);
    for(halfedge_descriptor h : CGAL::halfedges_around_target(halfedge(v, tm), tm))
    {
      const std::size_t j = id(source(h, tm));
      sum += w(h) * ((p1[j] - p1[i]) - r * (p0[j] - p0[i])).squaredNorm();
    }
    return sum;
  }
  // the rest cotangent weight (cot alpha + cot beta) / 2 of the edge of h, clamped to >= 0: the
  // per-edge weight of the ARAP energy (Sorkine and Alexa 2007), not Cotangent_weights' Laplacian
  // weight (which divides by the cell's mixed Voronoi area and is defined on a representation's
  // fan): the energy must be the one CGAL's Surface_mesh_deformation minimises, to compare with it
  double cotangent_weight(halfedge_descriptor h) const
  {
    double w = 0;
    for(halfedge_descriptor g : {h, opposite(h, tm)})
    {
      if(is_border(g, tm))
        continue;
      const Eigen::Vector3d& a = p0[id(source(g, tm))];
      const Eigen::Vector3d& b = p0[id(target(g, tm))];
      const Eigen::Vector3d& c = p0[id(target(next(g, tm), tm))];
      w += 0.5 * guarded_cotangent(a - c, b - c);
    }
    return (std::max)(w, 0.);
  }
};

// relative Laplacian-coordinate error of one representation (cotangent weights of the rest mesh)
template <class Representation, class TriangleMesh, class RestPointMap, class VertexIndexMap, class GeomTraits>
double laplacian_error(const Metric_context<TriangleMesh, VertexIndexMap>& c, const RestPointMap& rest,
                       const std::vector<unsigned char>& in_roi, const GeomTraits& gt)
{
  const Laplacian_stencils s = rest_operator(c.tm, Representation(), Cotangent_weights(), rest, c.vim, gt, true).stencils;
  std::vector<Eigen::Vector3d> x0, x1;
  node_positions(s, c.p0, x0);
  node_positions(s, c.p1, x1);
  auto touches_roi = [&](std::size_t a) {
    for(std::size_t k = s.combination_start[a]; k < s.combination_start[a + 1]; ++k)
      if(in_roi[s.combination_vertex[k]])
        return true;
    return false;
  };
  double error = 0, norm = 0;
  for(std::size_t a = 0; a < s.number_of_nodes; ++a)
  {
    bool touched = touches_roi(a);
    for(std::size_t k = s.neighbor_start[a]; k < s.neighbor_start[a + 1] && !touched; ++k)
      touched = touches_roi(s.neighbor[k]);
    if(!touched)
      continue;
    Eigen::Vector3d delta0 = Eigen::Vector3d::Zero(), delta1 = Eigen::Vector3d::Zero();
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for(std::size_t k = s.neighbor_start[a]; k < s.neighbor_start[a + 1]; ++k)
    {
      const std::size_t b = s.neighbor[k];
      delta0 += s.weight[k] * (x0[a] - x0[b]);
      delta1 += s.weight[k] * (x1[a] - x1[b]);
      cov += (x1[a] - x1[b]) * (x0[a] - x0[b]).transpose();
    }
    error += (delta1 - closest_rotation(cov) * delta0).squaredNorm();
    norm += delta0.squaredNorm();
  }
  return norm > 0 ? std::sqrt(error / norm) : (error > 0 ? std::sqrt(error) : 0.);
}

template <class TriangleMesh, class RestPointMap, class NamedParameters>
auto metric_context(const TriangleMesh& tm, const RestPointMap& rest, const NamedParameters& np)
{
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  const auto vpm = choose_parameter(get_parameter(np, CGAL::internal_np::vertex_point),
                                    get_const_property_map(CGAL::vertex_point, tm));
  const auto vim = CGAL::get_initialized_vertex_index_map(tm, np);
  Metric_context<TriangleMesh, std::remove_const_t<decltype(vim)>> c(tm, vim);
  c.p0 = vertex_positions(tm, rest, vim);
  c.p1 = vertex_positions(tm, vpm, vim);
  return c;
}

} // namespace internal

/*!
\ingroup PkgLaplacianDeformationMetrics
\brief measures how well the deformed mesh `tm` keeps the local shape of its rest state over the
region of interest `roi` (see `Deformation_quality` for the definitions). The constraint residual
is left at 0: `constraint_residual()` computes it.

Typical use with a `Surface_mesh`: copy the mesh before deforming it and pass
`get(CGAL::vertex_point, rest_copy)` as `rest` (both meshes share their vertex indices).

\tparam TriangleMesh a model of `FaceGraph` whose faces are triangles
\tparam RestPointMap a readable property map from the vertices of `tm` to points: the rest positions
\tparam VertexRange a range of vertices of `tm`

\param tm the deformed mesh
\param rest the rest positions of the vertices of `tm`
\param roi the vertices whose neighbourhoods are measured (for instance `Mesh_deformer::roi_vertices()`)
\param np optional named parameters among the ones below

\cgalNamedParamsBegin
  \cgalParamNBegin{vertex_point_map}
    \cgalParamDescription{a property map associating the deformed points to the vertices of `tm`}
    \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
  \cgalParamNEnd
  \cgalParamNBegin{vertex_index_map}
    \cgalParamDescription{a property map associating to each vertex of `tm` a unique index between `0` and `num_vertices(tm) - 1`}
    \cgalParamDefault{an automatically indexed internal map}
  \cgalParamNEnd
  \cgalParamNBegin{geom_traits}
    \cgalParamDescription{an instance of a geometric traits class, model of `Kernel` (for the cotangent weights of the Laplacian errors)}
    \cgalParamDefault{the kernel of the point type of the vertex point map}
  \cgalParamNEnd
\cgalNamedParamsEnd
*/
template <class TriangleMesh, class RestPointMap, class VertexRange,
          class NamedParameters = CGAL::parameters::Default_named_parameters>
Deformation_quality deformation_quality(const TriangleMesh& tm, const RestPointMap& rest, const VertexRange& roi,
                                        const NamedParameters& np = CGAL::parameters::default_values())
{
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  typedef typename boost::graph_traits<TriangleMesh>::halfedge_descriptor halfedge_descriptor;
  const auto c = internal::metric_context(tm, rest, np);
  const auto gt = choose_parameter<typename GetGeomTraits<TriangleMesh, NamedParameters>::type>(
      get_parameter(np, CGAL::internal_np::geom_traits));
  std::vector<unsigned char> in_roi(c.p0.size(), 0);
  for(auto v : roi)
    in_roi[c.id(v)] = 1;

  Deformation_quality q;
  q.vertex_laplacian_error = internal::laplacian_error<Vertex_based_representation>(c, rest, in_roi, gt);
  q.edge_laplacian_error = internal::laplacian_error<Edge_based_representation>(c, rest, in_roi, gt);

  std::size_t edges_counted = 0, dihedrals_counted = 0, normals_counted = 0;
  const double to_degrees = 180. / 3.14159265358979323846;
  for(auto e : edges(tm))
  {
    const halfedge_descriptor h = halfedge(e, tm);
    const std::size_t a = c.id(source(h, tm)), b = c.id(target(h, tm));
    if(!in_roi[a] && !in_roi[b])
      continue;
    const double l0 = (c.p0[b] - c.p0[a]).norm(), l1 = (c.p1[b] - c.p1[a]).norm();
    const double d = l0 > 0 ? std::abs(l1 - l0) / l0 : 0.;
    q.mean_edge_length_distortion += d;
    q.max_edge_length_distortion = (std::max)(q.max_edge_length_distortion, d);
    ++edges_counted;
    if(is_border(e, tm))
      continue;
    const std::size_t i = c.id(target(next(h, tm), tm)), j = c.id(target(next(opposite(h, tm), tm), tm));
    auto signed_dihedral = [&](const std::vector<Eigen::Vector3d>& p) {
      const Eigen::Vector3d n1 = internal::unit_normal(p[a], p[b], p[i]);
      const Eigen::Vector3d n2 = internal::unit_normal(p[b], p[a], p[j]);
      const Eigen::Vector3d axis = (p[b] - p[a]).normalized();
      return std::atan2(n1.cross(n2).dot(axis), n1.dot(n2));
    };
    const double change = std::abs(std::remainder(signed_dihedral(c.p1) - signed_dihedral(c.p0),
                                                  2. * 3.14159265358979323846)) * to_degrees;
    q.mean_dihedral_angle_change += change;
    q.max_dihedral_angle_change = (std::max)(q.max_dihedral_angle_change, change);
    ++dihedrals_counted;
  }

  const auto unit = [](halfedge_descriptor) { return 1.; };
  const auto cotangent = [&](halfedge_descriptor h) { return c.cotangent_weight(h); };
  double arap = 0, arap_norm = 0;
  for(auto v : roi)
  {
    if(c.isolated(v))
      continue;
    Eigen::Matrix3d s;
    c.one_ring_covariance(v, unit, s);
    const Eigen::Matrix3d r = internal::closest_rotation(s);
    for(halfedge_descriptor h : CGAL::halfedges_around_target(halfedge(v, tm), tm))
    {
      if(is_border(h, tm))
        continue;
      const std::size_t a = c.id(source(h, tm)), b = c.id(target(h, tm)), k = c.id(target(next(h, tm), tm));
      const Eigen::Vector3d n0 = internal::unit_normal(c.p0[a], c.p0[b], c.p0[k]);
      const Eigen::Vector3d n1 = internal::unit_normal(c.p1[a], c.p1[b], c.p1[k]);
      if(n0.isZero() || n1.isZero())
        continue;
      const double angle = internal::angle_in_degrees(n1, r * n0);
      q.mean_normal_deviation += angle;
      q.max_normal_deviation = (std::max)(q.max_normal_deviation, angle);
      ++normals_counted;
    }
    arap_norm += c.one_ring_covariance(v, cotangent, s);
    arap += c.one_ring_residual(v, cotangent, internal::closest_rotation(s));
  }
  if(edges_counted)
    q.mean_edge_length_distortion /= double(edges_counted);
  if(dihedrals_counted)
    q.mean_dihedral_angle_change /= double(dihedrals_counted);
  if(normals_counted)
    q.mean_normal_deviation /= double(normals_counted);
  q.arap_energy = arap_norm > 0 ? arap / arap_norm : 0.;
  return q;
}

/*!
\ingroup PkgLaplacianDeformationMetrics
\brief returns the largest distance between a control vertex of `tm` and its target, divided by
the bounding-box diagonal of the rest positions (0 if `controls` is empty), the value of
`Deformation_quality::max_constraint_residual`.

\tparam ControlRange a range whose value type has `first` (a vertex of `tm`) and `second` (its
        target, a point with `x()`, `y()`, `z()`), for instance `std::vector<std::pair<vertex_descriptor, Point_3> >`

\param tm the deformed mesh
\param rest the rest positions of the vertices of `tm`
\param controls the control vertices and their targets
\param np optional named parameters: `vertex_point_map` and `vertex_index_map`, as for `deformation_quality()`
*/
template <class TriangleMesh, class RestPointMap, class ControlRange,
          class NamedParameters = CGAL::parameters::Default_named_parameters>
double constraint_residual(const TriangleMesh& tm, const RestPointMap& rest, const ControlRange& controls,
                           const NamedParameters& np = CGAL::parameters::default_values())
{
  const auto c = internal::metric_context(tm, rest, np);
  if(c.p0.empty())
    return 0;
  Eigen::Vector3d lo = c.p0.front(), hi = c.p0.front();
  for(const Eigen::Vector3d& p : c.p0)
  {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  double residual = 0;
  for(const auto& control : controls)
  {
    const auto& t = control.second;
    const Eigen::Vector3d target(CGAL::to_double(t.x()), CGAL::to_double(t.y()), CGAL::to_double(t.z()));
    residual = (std::max)(residual, (c.p1[c.id(control.first)] - target).norm());
  }
  const double diagonal = (hi - lo).norm();
  return diagonal > 0 ? residual / diagonal : residual;
}

/*!
\ingroup PkgLaplacianDeformationMetrics
\brief writes into `distortion`, for every vertex `v` of `tm`, its one-ring rigidity error
<code>sqrt(sum_j |e'_vj - R_v e_vj|^2 / sum_j |e_vj|^2)</code> (`e_vj = p_j - p_v` over the
neighbours `j`, `R_v` the rotation that best maps the rest vectors onto the deformed ones):
0 where the neighbourhood moved rigidly, about the relative stretch where it did not;
invariant under rigid motions. Meant for colouring pictures; 0 for an isolated vertex.

\tparam DistortionMap a writable property map from the vertices of `tm` to `double`

\param tm the deformed mesh
\param rest the rest positions of the vertices of `tm`
\param distortion receives the value of every vertex
\param np optional named parameters: `vertex_point_map` and `vertex_index_map`, as for `deformation_quality()`
*/
template <class TriangleMesh, class RestPointMap, class DistortionMap,
          class NamedParameters = CGAL::parameters::Default_named_parameters>
void vertex_distortion_field(const TriangleMesh& tm, const RestPointMap& rest, DistortionMap distortion,
                             const NamedParameters& np = CGAL::parameters::default_values())
{
  const auto c = internal::metric_context(tm, rest, np);
  typedef typename boost::graph_traits<TriangleMesh>::halfedge_descriptor halfedge_descriptor;
  const auto unit = [](halfedge_descriptor) { return 1.; };
  for(auto v : vertices(tm))
  {
    Eigen::Matrix3d s;
    const double norm = c.one_ring_covariance(v, unit, s);
    const double value = norm > 0 ? std::sqrt(c.one_ring_residual(v, unit, internal::closest_rotation(s)) / norm) : 0.;
    put(distortion, v, value);
  }
}

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_METRICS_H
