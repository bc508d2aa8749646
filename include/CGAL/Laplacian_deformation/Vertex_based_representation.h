// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_VERTEX_BASED_REPRESENTATION_H
#define CGAL_LAPLACIAN_DEFORMATION_VERTEX_BASED_REPRESENTATION_H

#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/iterator.h>
#include <CGAL/boost/graph/named_params_helper.h>

#include <cstddef>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationRepresentations

\brief The classical representation: one node per mesh vertex, `x_v = p_v`.

The cell of vertex `v` is its one-ring: `N(v)` are the vertices adjacent to `v`, and its fan
triangles are the faces `(v, k, l)` around `v`, as the triangles `(x_v, x_k, x_l)`.
On a polygon face (see \ref LapDefPolygons) `k` and `l` are the two vertices of the face adjacent
to `v`, so the face contributes its corner triangle at `v`; the other vertices of the face are not
neighbours of `v`.
The node graph is the mesh itself. Laplacian coordinates are evaluated at `n` points.

\cgalModels{DeformationRepresentation}
\sa `Edge_based_representation`
*/
struct Vertex_based_representation
{
  /*!
  \brief The nodes of this representation on a given mesh (a model of `DeformationNodes`).
  \tparam TriangleMesh a model of `FaceGraph`
  \tparam VertexPointMap a readable property map from vertices to points (unused: the node
          positions are the vertex positions)
  */
  template <class TriangleMesh, class VertexPointMap>
  class Nodes
  {
  public:
    /// The mesh type.
    typedef TriangleMesh Triangle_mesh;
    /// The node graph: the mesh itself.
    typedef TriangleMesh Node_graph;
    /// A node: a mesh vertex.
    typedef typename boost::graph_traits<TriangleMesh>::vertex_descriptor node_descriptor;
    /// A mesh vertex.
    typedef typename boost::graph_traits<TriangleMesh>::vertex_descriptor vertex_descriptor;

    /// builds the nodes of `tm`; `tm` must outlive this object.
    Nodes(const TriangleMesh& tm, VertexPointMap)
      : m_tm(&tm), m_index(CGAL::get_initialized_vertex_index_map(tm))
    {}

    /// the node graph.
    const Node_graph& graph() const { return *m_tm; }
    /// the number of nodes (`num_vertices(tm)`).
    std::size_t number_of_nodes() const { return static_cast<std::size_t>(num_vertices(*m_tm)); }
    /// the nodes, in any order.
    decltype(auto) nodes() const { return vertices(*m_tm); }
    /// the dense index of node `a`, in `[0, number_of_nodes())`.
    std::size_t index(node_descriptor a) const { return static_cast<std::size_t>(get(m_index, a)); }
    /// calls `f(v, c)` for each term of `x_a = sum c p_v`: here once, with `(a, 1)`.
    template <class F>
    void combination(node_descriptor a, F&& f) const { f(a, 1.); }
    /// calls `f(a)` for each node whose combination involves the vertex `v`: `v` itself.
    template <class F>
    void incident_nodes(vertex_descriptor v, F&& f) const { f(v); }
    /// the neighbours `N(a)`: the adjacent vertices.
    decltype(auto) neighbors(node_descriptor a) const
    {
      return CGAL::vertices_around_target(halfedge(a, *m_tm), *m_tm);
    }
    /// calls `f(b, c)` for each fan triangle `(x_a, x_b, x_c)` of `a`: one per face around `a`.
    template <class F>
    void fan_triangles(node_descriptor a, F&& f) const
    {
      for(auto h : CGAL::halfedges_around_target(halfedge(a, *m_tm), *m_tm))
      {
        if(is_border(h, *m_tm))
          continue;
        // face (a, k, ..., l) with h = (l -> a): its corner triangle at a
        f(target(next(h, *m_tm), *m_tm), source(h, *m_tm));
      }
    }

  private:
    const TriangleMesh* m_tm;
    typename CGAL::GetInitializedVertexIndexMap<TriangleMesh>::const_type m_index;
  };
};

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_VERTEX_BASED_REPRESENTATION_H
