// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_INTERNAL_LAPLACIAN_STENCILS_H
#define CGAL_LAPLACIAN_DEFORMATION_INTERNAL_LAPLACIAN_STENCILS_H

#include <CGAL/Laplacian_deformation/Node_cell.h>
#include <CGAL/Laplacian_deformation/internal/parallel.h>
#include <CGAL/Laplacian_deformation/internal/Policy_variant.h>

#include <CGAL/assertions.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <array>
#include <cstddef>
#include <algorithm>
#include <utility>
#include <vector>

namespace CGAL {
namespace Laplacian_deformation {
namespace internal {

// The flat (CSR) description of a representation on a mesh, in dense node and vertex indices.
// It is the only thing the assembly, the transform fits and the solver ever see of a
// representation: the vertex- and the edge-based paths share everything below.
struct Laplacian_stencils
{
  std::size_t number_of_nodes = 0;
  std::size_t number_of_vertices = 0;
  // x_a = sum_k combination_coefficient[k] p_{combination_vertex[k]}, k in [combination_start[a], combination_start[a+1])
  std::vector<std::size_t> combination_start;
  std::vector<std::size_t> combination_vertex;
  std::vector<double> combination_coefficient;
  // N(a) = neighbor[k], k in [neighbor_start[a], neighbor_start[a+1]); weight[k] = w_ab
  std::vector<std::size_t> neighbor_start;
  std::vector<std::size_t> neighbor;
  std::vector<double> weight;
  // fan triangles (x_a, x_b, x_c) as local positions of b and c in the neighbour slice of a (only
  // compute_weights() reads them; Mesh_deformer frees them afterwards)
  std::vector<std::size_t> fan_start;
  std::vector<std::array<std::size_t, 2>> fan;

  std::size_t degree(std::size_t a) const { return neighbor_start[a + 1] - neighbor_start[a]; }
};

// Builds the stencils of the nodes `nodes` (a model of DeformationNodes); `vertex_index` maps
// mesh vertices to [0, number_of_vertices).
template <class Nodes, class VertexIndexMap>
Laplacian_stencils laplacian_stencils(const Nodes& nodes, std::size_t number_of_vertices,
                                      const VertexIndexMap& vertex_index)
{
  typedef typename Nodes::node_descriptor node_descriptor;
  Laplacian_stencils s;
  s.number_of_nodes = nodes.number_of_nodes();
  s.number_of_vertices = number_of_vertices;

  std::vector<node_descriptor> by_index(s.number_of_nodes);
  for(node_descriptor a : nodes.nodes())
    by_index[nodes.index(a)] = a;

  // sizes first, so that every array is allocated once at its final size (growing them would
  // touch about twice the memory, and first touches of fresh pages are slow on some machines)
  std::size_t combination_size = 0, neighbor_size = 0, fan_size = 0;
  for(const node_descriptor& a : by_index)
  {
    nodes.combination(a, [&](auto, double) { ++combination_size; });
    for(node_descriptor b : nodes.neighbors(a))
    {
      (void)b;
      ++neighbor_size;
    }
    nodes.fan_triangles(a, [&](node_descriptor, node_descriptor) { ++fan_size; });
  }
  s.combination_start.reserve(s.number_of_nodes + 1);
  s.neighbor_start.reserve(s.number_of_nodes + 1);
  s.fan_start.reserve(s.number_of_nodes + 1);
  s.combination_vertex.reserve(combination_size);
  s.combination_coefficient.reserve(combination_size);
  s.neighbor.reserve(neighbor_size);
  s.fan.reserve(fan_size);
  s.combination_start.push_back(0);
  s.neighbor_start.push_back(0);
  s.fan_start.push_back(0);
  for(const node_descriptor& a : by_index)
  {
    nodes.combination(a, [&](auto v, double c) {
      s.combination_vertex.push_back(static_cast<std::size_t>(get(vertex_index, v)));
      s.combination_coefficient.push_back(c);
    });
    const std::size_t first = s.neighbor.size();
    for(node_descriptor b : nodes.neighbors(a))
      s.neighbor.push_back(nodes.index(b));
    const std::size_t last = s.neighbor.size();
    auto local = [&](node_descriptor b) {
      const std::size_t ib = nodes.index(b);
      for(std::size_t k = first; k < last; ++k)
        if(s.neighbor[k] == ib)
          return k - first;
      CGAL_assertion_msg(false, "a fan triangle vertex is not a neighbour of the node");
      return last - first;
    };
    nodes.fan_triangles(a, [&](node_descriptor b, node_descriptor c) {
      const std::array<std::size_t, 2> t{ local(b), local(c) };
      if(t[0] < last - first && t[1] < last - first)
        s.fan.push_back(t);
    });
    s.combination_start.push_back(s.combination_vertex.size());
    s.neighbor_start.push_back(s.neighbor.size());
    s.fan_start.push_back(s.fan.size());
  }
  s.weight.assign(s.neighbor.size(), 0.);
  return s;
}

// x = P p for every node.
inline void node_positions(const Laplacian_stencils& s, const std::vector<Eigen::Vector3d>& vertex_positions,
                           std::vector<Eigen::Vector3d>& x)
{
  x.assign(s.number_of_nodes, Eigen::Vector3d::Zero());
  for(std::size_t a = 0; a < s.number_of_nodes; ++a)
    for(std::size_t k = s.combination_start[a]; k < s.combination_start[a + 1]; ++k)
      x[a] += s.combination_coefficient[k] * vertex_positions[s.combination_vertex[k]];
}

// Fills s.weight with the weight policy evaluated on every rest cell; with `parallel` (and TBB)
// the nodes are shared among TBB's threads (each cell is independent). `policy` is a concrete
// policy (see compute_weights()).
template <class WeightPolicy, class GeomTraits>
void compute_weights_with(Laplacian_stencils& s, const std::vector<Eigen::Vector3d>& x,
                          const WeightPolicy& policy, const GeomTraits& gt, bool parallel)
{
  typedef typename GeomTraits::Point_3 Point_3;
  auto point = [](const Eigen::Vector3d& p) { return Point_3(p.x(), p.y(), p.z()); };
  for_each_block(s.number_of_nodes, parallel, [&](std::size_t begin, std::size_t end) {
    std::vector<Point_3> neighbors;
    std::vector<double> w;
    for(std::size_t a = begin; a < end; ++a)
    {
      const std::size_t first = s.neighbor_start[a], n = s.degree(a);
      neighbors.clear();
      for(std::size_t k = first; k < first + n; ++k)
        neighbors.push_back(point(x[s.neighbor[k]]));
      const Point_3 center = point(x[a]);
      const Node_cell<GeomTraits> cell(center, neighbors.data(), n, s.fan.data() + s.fan_start[a],
                                       s.fan_start[a + 1] - s.fan_start[a], gt);
      policy.weights(cell, w);
      CGAL_assertion(w.size() == n);
      std::copy(w.begin(), w.end(), s.weight.begin() + first);
    }
  }, 1024);
}

// compute_weights_with() with the policy held by a run-time policy (one dispatch for all the
// cells), or with `policy` itself
template <class WeightPolicy, class GeomTraits>
void compute_weights(Laplacian_stencils& s, const std::vector<Eigen::Vector3d>& x,
                     const WeightPolicy& policy, const GeomTraits& gt, bool parallel = false)
{
  visit_policy(policy, [&](const auto& p) { compute_weights_with(s, x, p, gt, parallel); });
}

// P: nodes x vertices, x = P p.
inline Eigen::SparseMatrix<double> combination_matrix(const Laplacian_stencils& s)
{
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(s.combination_vertex.size());
  for(std::size_t a = 0; a < s.number_of_nodes; ++a)
    for(std::size_t k = s.combination_start[a]; k < s.combination_start[a + 1]; ++k)
      t.emplace_back(int(a), int(s.combination_vertex[k]), s.combination_coefficient[k]);
  Eigen::SparseMatrix<double> p(int(s.number_of_nodes), int(s.number_of_vertices));
  p.setFromTriplets(t.begin(), t.end());
  return p;
}

// The Laplacian operator D = L_w P (rows: nodes, columns: vertices; stored by rows),
// delta_a = sum_b w_ab (x_a - x_b) = (D p)_a. Assembled row by row (row a combines the
// vertices of x_a and of its neighbours) in a dense accumulator, without forming L_w and the
// sparse product; the terms of an entry are summed in the order neighbours, then x_a; exact
// zeros (cancellations) are dropped.
inline Eigen::SparseMatrix<double, Eigen::RowMajor> laplacian_operator(const Laplacian_stencils& s)
{
  typedef Eigen::SparseMatrix<double, Eigen::RowMajor> Row_major;
  std::vector<int> outer(s.number_of_nodes + 1, 0), inner, touched;
  std::vector<double> values, accumulator(s.number_of_vertices, 0.);
  std::vector<std::size_t> mark(s.number_of_vertices, s.number_of_nodes);
  inner.reserve(4 * s.neighbor.size());
  values.reserve(4 * s.neighbor.size());
  for(std::size_t a = 0; a < s.number_of_nodes; ++a)
  {
    touched.clear();
    auto add = [&](std::size_t v, double value) {
      if(mark[v] != a)
      {
        mark[v] = a;
        accumulator[v] = 0.;
        touched.push_back(int(v));
      }
      accumulator[v] += value;
    };
    double diagonal = 0;
    for(std::size_t k = s.neighbor_start[a]; k < s.neighbor_start[a + 1]; ++k)
    {
      const std::size_t b = s.neighbor[k];
      diagonal += s.weight[k];
      for(std::size_t j = s.combination_start[b]; j < s.combination_start[b + 1]; ++j)
        add(s.combination_vertex[j], -s.weight[k] * s.combination_coefficient[j]);
    }
    for(std::size_t j = s.combination_start[a]; j < s.combination_start[a + 1]; ++j)
      add(s.combination_vertex[j], diagonal * s.combination_coefficient[j]);
    std::sort(touched.begin(), touched.end());
    for(int v : touched)
      if(accumulator[std::size_t(v)] != 0)
      {
        inner.push_back(v);
        values.push_back(accumulator[std::size_t(v)]);
      }
    outer[a + 1] = int(inner.size());
  }
  const Eigen::Map<const Row_major> d(Eigen::Index(s.number_of_nodes), Eigen::Index(s.number_of_vertices),
                                      Eigen::Index(values.size()), outer.data(), inner.data(), values.data());
  return Row_major(d);
}

} // namespace internal
} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_INTERNAL_LAPLACIAN_STENCILS_H
