// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_EDGE_BASED_REPRESENTATION_H
#define CGAL_LAPLACIAN_DEFORMATION_EDGE_BASED_REPRESENTATION_H

#include <CGAL/Laplacian_deformation/Edge_midpoint_graph.h>

#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/iterator.h>
#include <CGAL/Named_function_parameters.h>

#include <cstddef>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationRepresentations

\brief The paper's edge-based representation: one node per mesh edge, placed at its midpoint
`x_e = (p_i + p_j) / 2`.

The cell of edge `e = (i, j)` holds every other edge incident to `i` or to `j`. Its fan
triangles are built from the faces around both endpoints: for each of the (up to two) faces
`(i, j, a)` containing `e`, the medial triangle `(m_e, m_ia, m_ja)`; for each other face
`(i, k, l)` around `i` (likewise around `j`), the triangle `(m_e, m_ik, m_il)`, which is the face
scaled by 1/2 about `p_i` once `m_e` replaces `p_i`'s role. In the interior every spoke lies in
exactly two fan triangles, on the boundary in one.

<b>Polygon faces.</b> The same rules hold on faces of any degree (see \ref LapDefPolygons): the
cell of `e` is still every other edge incident to `i` or `j` (an edge of an incident face that
touches neither endpoint is not a neighbour); a face containing `e` gives the triangle of `m_e` and
the midpoints of the face's other edge at `i` and its other edge at `j`; any other face around
`i` gives `(m_e, m_ik, m_il)` with `(i, k)` and `(i, l)` the face's two edges at `i`. On a
triangle these are the triangle rules above, and the fan is closed in the same way.
A mesh with `n` vertices has about `3n` edges, so the Laplacian coordinates are evaluated at
about three times as many points as with `Vertex_based_representation`, and each row of the
operator touches the one-rings of both endpoints.
The node graph is `Edge_midpoint_graph`.

\cgalModels{DeformationRepresentation}
\sa `Vertex_based_representation`
*/
struct Edge_based_representation
{
  /*!
  \brief The nodes of this representation on a given mesh (a model of `DeformationNodes`).
  \tparam TriangleMesh a model of `FaceGraph`
  \tparam VertexPointMap a readable property map from vertices to points
  */
  template <class TriangleMesh, class VertexPointMap>
  class Nodes
  {
  public:
    /// The mesh type.
    typedef TriangleMesh Triangle_mesh;
    /// The node graph: the edge-midpoint graph of the mesh.
    typedef Edge_midpoint_graph<TriangleMesh, VertexPointMap> Node_graph;
    /// A node: a mesh edge.
    typedef typename boost::graph_traits<TriangleMesh>::edge_descriptor node_descriptor;
    /// A mesh vertex.
    typedef typename boost::graph_traits<TriangleMesh>::vertex_descriptor vertex_descriptor;

    /// builds the nodes of `tm`; `tm` must outlive this object.
    Nodes(const TriangleMesh& tm, VertexPointMap vpm)
      : m_tm(&tm), m_graph(tm, CGAL::parameters::vertex_point_map(vpm)),
        m_index(get(boost::vertex_index, m_graph)), m_vertex_index(CGAL::get_initialized_vertex_index_map(tm))
    {}

    /// the node graph.
    const Node_graph& graph() const { return m_graph; }
    /// the number of nodes (`num_edges(tm)`).
    std::size_t number_of_nodes() const { return static_cast<std::size_t>(num_vertices(m_graph)); }
    /// the nodes, in any order.
    decltype(auto) nodes() const { return vertices(m_graph); }
    /// the dense index of node `a`, in `[0, number_of_nodes())`.
    std::size_t index(node_descriptor a) const { return static_cast<std::size_t>(get(m_index, a)); }
    /// calls `f(v, c)` for each term of `x_a = sum c p_v`: the two endpoints with `c = 1/2`.
    template <class F>
    void combination(node_descriptor a, F&& f) const
    {
      f(source(a, *m_tm), 0.5);
      f(target(a, *m_tm), 0.5);
    }
    /// calls `f(a)` for each node whose combination involves the vertex `v`: the edges incident to `v`.
    template <class F>
    void incident_nodes(vertex_descriptor v, F&& f) const
    {
      if(halfedge(v, *m_tm) == boost::graph_traits<TriangleMesh>::null_halfedge())
        return;
      for(auto h : CGAL::halfedges_around_target(halfedge(v, *m_tm), *m_tm))
        f(edge(h, *m_tm));
    }
    /// the neighbours `N(a)`: every other edge incident to an endpoint of `a`.
    /// (listed from `a`'s canonical orientation, so that the order does not depend on the
    /// orientation of the descriptor, see `fan_triangles()`)
    decltype(auto) neighbors(node_descriptor a) const { return adjacent_vertices(edge(canonical_halfedge(a), *m_tm), m_graph); }
    /// calls `f(b, c)` for each fan triangle `(x_a, x_b, x_c)` of `a` (see the class documentation).
    template <class F>
    void fan_triangles(node_descriptor a, F&& f) const
    {
      const TriangleMesh& tm = *m_tm;
      const auto h_ij = canonical_halfedge(a);
      const auto i = source(h_ij, tm);
      for(auto endpoint : { h_ij, opposite(h_ij, tm) })        // targets j, then i
      {
        for(auto h : CGAL::halfedges_around_target(endpoint, tm))
        {
          if(is_border(h, tm))
            continue;
          // face f = (source(h), v, target(next(h))) around v = target(endpoint)
          const auto e1 = edge(h, tm), e2 = edge(next(h, tm), tm);
          if(e1 != a && e2 != a)
            f(e1, e2);                                        // (m_e, m_vk, m_vl)
          else if(target(endpoint, tm) == i)                  // a face containing e: once, from i
          {
            // f = (..., s, i, t, ...) with e = (s, i) or (i, t): the other edge of f at i, and
            // the other edge of f at j (for a triangle both are the edge opposite to i)
            if(e1 == a)                                       // j = s: the edge of f before s
              f(e2, edge(prev(h, tm), tm));
            else                                              // j = t: the edge of f after t
              f(e1, edge(next(next(h, tm), tm), tm));         // medial (m_e, m_if, m_jf)
          }
        }
      }
    }

  private:
    // the halfedge of `a` pointing to its endpoint of larger vertex index: an edge descriptor
    // carries an orientation (e.g. Surface_mesh's remembers a halfedge), and the cells are
    // listed from this one whatever the descriptor's, so that a node reached through
    // incident_nodes() or neighbors() has exactly the cell it has when reached through nodes()
    typename boost::graph_traits<TriangleMesh>::halfedge_descriptor canonical_halfedge(node_descriptor a) const
    {
      const auto h = halfedge(a, *m_tm);
      return get(m_vertex_index, target(h, *m_tm)) >= get(m_vertex_index, source(h, *m_tm)) ? h : opposite(h, *m_tm);
    }

    const TriangleMesh* m_tm;
    Node_graph m_graph;
    typename boost::property_map<Node_graph, boost::vertex_index_t>::const_type m_index;
    typename CGAL::GetInitializedVertexIndexMap<TriangleMesh>::const_type m_vertex_index;
  };
};

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_EDGE_BASED_REPRESENTATION_H
