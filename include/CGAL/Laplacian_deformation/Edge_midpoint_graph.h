// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_EDGE_MIDPOINT_GRAPH_H
#define CGAL_LAPLACIAN_DEFORMATION_EDGE_MIDPOINT_GRAPH_H

#include <CGAL/Laplacian_deformation/internal/Edge_midpoint_graph_iterators.h>

#include <CGAL/Default.h>
#include <CGAL/Iterator_range.h>
#include <CGAL/boost/graph/named_params_helper.h>
#include <CGAL/boost/graph/properties.h>

#include <boost/container_hash/hash.hpp>
#include <boost/graph/adjacency_iterator.hpp>
#include <boost/graph/properties.hpp>

#include <cstddef>
#include <functional>
#include <type_traits>
#include <utility>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationRef
\brief Edge descriptor of `Edge_midpoint_graph`: two mesh edges sharing a mesh vertex.

It stores the two halfedges of the mesh edges that point to the shared vertex. Two
descriptors are equal when they name the same pair, whatever their orientation; the
orientation is remembered, so `source(e, g) == u` for every `e` in `out_edges(u, g)`.
\tparam FaceGraph a model of `FaceGraph`
*/
template <class FaceGraph>
class Edge_midpoint_graph_edge
{
public:
  /// the halfedge type of the mesh
  typedef typename boost::graph_traits<FaceGraph>::halfedge_descriptor Halfedge_descriptor;

  /// null edge
  Edge_midpoint_graph_edge() = default;
  /// the edge from `edge(source)` to `edge(target)`; both halfedges point to the shared vertex
  Edge_midpoint_graph_edge(Halfedge_descriptor source, Halfedge_descriptor target) : m_source(source), m_target(target) {}

  /// the halfedge of the source mesh edge that points to the shared vertex
  Halfedge_descriptor source_halfedge() const { return m_source; }
  /// the halfedge of the target mesh edge that points to the shared vertex
  Halfedge_descriptor target_halfedge() const { return m_target; }

  /// orientation-independent equality
  friend bool operator==(const Edge_midpoint_graph_edge& a, const Edge_midpoint_graph_edge& b)
  {
    return (a.m_source == b.m_source && a.m_target == b.m_target) ||
           (a.m_source == b.m_target && a.m_target == b.m_source);
  }
  friend bool operator!=(const Edge_midpoint_graph_edge& a, const Edge_midpoint_graph_edge& b)
  { return !(a == b); }
  /// orientation-independent strict weak order
  friend bool operator<(const Edge_midpoint_graph_edge& a, const Edge_midpoint_graph_edge& b)
  { return a.sorted() < b.sorted(); }
  /// orientation-independent hash
  friend std::size_t hash_value(const Edge_midpoint_graph_edge& e)
  { return boost::hash<std::pair<Halfedge_descriptor, Halfedge_descriptor> >()(e.sorted()); }

private:
  std::pair<Halfedge_descriptor, Halfedge_descriptor> sorted() const
  { return m_target < m_source ? std::make_pair(m_target, m_source) : std::make_pair(m_source, m_target); }

  Halfedge_descriptor m_source, m_target;
};

/*!
\ingroup PkgLaplacianDeformationRef
\brief Boost graph view of a mesh whose vertices are the mesh edges (located at their
midpoints) and whose edges join two mesh edges sharing a mesh vertex.

A node `{i, j}` is adjacent to every other mesh edge incident to `i` or to `j`, so
`num_vertices(g) == num_edges(tm)` and `num_edges(g)` is the sum over mesh vertices of
`deg(v)(deg(v) - 1)/2`. The view stores a pointer to the mesh, which must outlive it and
must not be modified while it is used. The mesh must not have two edges joining the same
two vertices (otherwise the view has parallel edges).

`get(boost::vertex_index, g)` is the (initialised) edge index map of the mesh;
`get(CGAL::vertex_point, g)` is a readable map giving the midpoint of a node.

\tparam FaceGraph a model of `FaceGraph`
\tparam VertexPointMap a readable property map from the vertices of `FaceGraph` to points;
        `CGAL::Default` means `CGAL::GetVertexPointMap<FaceGraph>::const_type`
\tparam EdgeIndexMap a readable property map from the edges of `FaceGraph` to a dense index;
        `CGAL::Default` means `CGAL::GetInitializedEdgeIndexMap<FaceGraph>::const_type`
        (a dynamic index for a `Polyhedron_3` without ids, whose internal one is unusable in CGAL 5.5,
        and for a `Face_filtered_graph`, whose forwarded one is not dense over the selected edges)

\cgalModels{VertexListGraph, IncidenceGraph, AdjacencyGraph, EdgeListGraph}
*/
template <class FaceGraph, class VertexPointMap = CGAL::Default, class EdgeIndexMap = CGAL::Default>
class Edge_midpoint_graph
{
public:
  /// the underlying mesh type
  typedef FaceGraph Face_graph;
  /// the vertex point map type
  typedef typename CGAL::Default::Get<VertexPointMap,
            typename CGAL::GetVertexPointMap<FaceGraph>::const_type>::type Vertex_point_map;
  /// the edge index map type, also the vertex index map of the graph
  typedef typename CGAL::Default::Get<EdgeIndexMap, typename internal::Edge_index_map_selector<
            FaceGraph, CGAL::parameters::Default_named_parameters>::type>::type Edge_index_map;
  /// the point type
  typedef typename boost::property_traits<Vertex_point_map>::value_type Point_3;

  /*!
  builds the view of `tm`.
  \cgalNamedParamsBegin
    \cgalParamNBegin{vertex_point_map}
      \cgalParamDescription{the positions of the mesh vertices}
      \cgalParamType{`Vertex_point_map`}
      \cgalParamDefault{`get_const_property_map(CGAL::vertex_point, tm)`}
    \cgalParamNEnd
    \cgalParamNBegin{edge_index_map}
      \cgalParamDescription{a dense, initialised index of the mesh edges}
      \cgalParamType{`Edge_index_map`}
      \cgalParamDefault{`CGAL::get_initialized_edge_index_map(tm)` (see `EdgeIndexMap`)}
    \cgalParamNEnd
  \cgalNamedParamsEnd
  */
  template <class NamedParameters = CGAL::parameters::Default_named_parameters>
  explicit Edge_midpoint_graph(const FaceGraph& tm,
                               const NamedParameters& np = CGAL::parameters::default_values())
    : m_tm(&tm),
      m_vpm(CGAL::parameters::choose_parameter(CGAL::parameters::get_parameter(np, CGAL::internal_np::vertex_point),
                                               get_const_property_map(CGAL::vertex_point, tm))),
      m_eim(internal::Edge_index_map_selector<FaceGraph, NamedParameters>::index_map(tm, np))
  {
    static_assert(std::is_convertible<typename internal::Edge_index_map_selector<FaceGraph, NamedParameters>::type,
                  Edge_index_map>::value, "EdgeIndexMap must be passed as the edge_index_map named parameter");
  }

  /// the underlying mesh
  const Face_graph& face_graph() const { return *m_tm; }
  /// the vertex point map of the mesh
  Vertex_point_map vertex_point_map() const { return m_vpm; }
  /// the edge index map of the mesh (the vertex index of the graph)
  Edge_index_map edge_index_map() const { return m_eim; }

private:
  const FaceGraph* m_tm;
  Vertex_point_map m_vpm;
  Edge_index_map m_eim;
};

/*!
\relates Edge_midpoint_graph
returns the edge-midpoint view of `tm`, with the map types deduced from `np`
(see the constructor for the named parameters).
*/
template <class FaceGraph, class NamedParameters = CGAL::parameters::Default_named_parameters>
Edge_midpoint_graph<FaceGraph, typename CGAL::GetVertexPointMap<FaceGraph, NamedParameters>::const_type,
                    typename internal::Edge_index_map_selector<FaceGraph, NamedParameters>::type>
make_edge_midpoint_graph(const FaceGraph& tm, const NamedParameters& np = CGAL::parameters::default_values())
{
  return Edge_midpoint_graph<FaceGraph, typename CGAL::GetVertexPointMap<FaceGraph, NamedParameters>::const_type,
                             typename internal::Edge_index_map_selector<FaceGraph, NamedParameters>::type>(tm, np);
}

} // namespace Laplacian_deformation
} // namespace CGAL

namespace boost {

/// \ingroup PkgLaplacianDeformationRef
/// \brief Graph traits of `CGAL::Laplacian_deformation::Edge_midpoint_graph`.
template <class FG, class VPM, class EIM>
struct graph_traits<CGAL::Laplacian_deformation::Edge_midpoint_graph<FG, VPM, EIM> >
{
  typedef typename graph_traits<FG>::edge_descriptor                  vertex_descriptor;
  typedef CGAL::Laplacian_deformation::Edge_midpoint_graph_edge<FG>   edge_descriptor;
  typedef undirected_tag                                              directed_category;
  typedef disallow_parallel_edge_tag                                  edge_parallel_category;
  struct traversal_category : public virtual incidence_graph_tag, public virtual adjacency_graph_tag,
                              public virtual vertex_list_graph_tag, public virtual edge_list_graph_tag {};

  typedef typename graph_traits<FG>::edge_iterator                    vertex_iterator;
  typedef CGAL::Laplacian_deformation::internal::Edge_midpoint_graph_out_edge_iterator<FG, edge_descriptor>
    out_edge_iterator;
  typedef CGAL::Laplacian_deformation::internal::Edge_midpoint_graph_edge_iterator<FG, edge_descriptor>
    edge_iterator;
  typedef typename adjacency_iterator_generator<CGAL::Laplacian_deformation::Edge_midpoint_graph<FG, VPM, EIM>,
                                                vertex_descriptor, out_edge_iterator>::type adjacency_iterator;

  typedef typename graph_traits<FG>::edges_size_type                  vertices_size_type;
  typedef std::size_t                                                 edges_size_type;
  typedef std::size_t                                                 degree_size_type;

  static vertex_descriptor null_vertex() { return vertex_descriptor(); }
};

template <class FG, class VPM, class EIM>
struct graph_traits<const CGAL::Laplacian_deformation::Edge_midpoint_graph<FG, VPM, EIM> >
  : graph_traits<CGAL::Laplacian_deformation::Edge_midpoint_graph<FG, VPM, EIM> >
{};

template <class FG, class VPM, class EIM>
struct property_map<CGAL::Laplacian_deformation::Edge_midpoint_graph<FG, VPM, EIM>, vertex_index_t>
{
  typedef typename CGAL::Laplacian_deformation::Edge_midpoint_graph<FG, VPM, EIM>::Edge_index_map type;
  typedef type const_type;
};

template <class FG, class VPM, class EIM>
struct property_map<CGAL::Laplacian_deformation::Edge_midpoint_graph<FG, VPM, EIM>, vertex_point_t>
{
  typedef CGAL::Laplacian_deformation::internal::Edge_midpoint_map<
            FG, typename CGAL::Laplacian_deformation::Edge_midpoint_graph<FG, VPM, EIM>::Vertex_point_map> type;
  typedef type const_type;
};

template <class FG, class VPM, class EIM, class Tag>
struct property_map<const CGAL::Laplacian_deformation::Edge_midpoint_graph<FG, VPM, EIM>, Tag>
  : property_map<CGAL::Laplacian_deformation::Edge_midpoint_graph<FG, VPM, EIM>, Tag>
{};

} // namespace boost

namespace std {

template <class FG>
struct hash<CGAL::Laplacian_deformation::Edge_midpoint_graph_edge<FG> >
{
  std::size_t operator()(const CGAL::Laplacian_deformation::Edge_midpoint_graph_edge<FG>& e) const
  { return hash_value(e); }
};

} // namespace std

namespace CGAL {
namespace Laplacian_deformation {

namespace internal {
template <class FG, class VPM, class EIM>
using Edge_midpoint_graph_traits = boost::graph_traits<Edge_midpoint_graph<FG, VPM, EIM> >;
} // namespace internal

/// \addtogroup PkgLaplacianDeformationRef
/// Free functions of the BGL concepts and property maps of `Edge_midpoint_graph`, found by ADL.
/// @{

/// \brief the nodes of `g`, i.e.\ the edges of the mesh
template <class FG, class VPM, class EIM>
Iterator_range<typename internal::Edge_midpoint_graph_traits<FG, VPM, EIM>::vertex_iterator>
vertices(const Edge_midpoint_graph<FG, VPM, EIM>& g)
{
  return Iterator_range<typename internal::Edge_midpoint_graph_traits<FG, VPM, EIM>::vertex_iterator>(edges(g.face_graph()));
}

/// \brief the number of edges of the mesh
template <class FG, class VPM, class EIM>
typename internal::Edge_midpoint_graph_traits<FG, VPM, EIM>::vertices_size_type
num_vertices(const Edge_midpoint_graph<FG, VPM, EIM>& g)
{
  return num_edges(g.face_graph());
}

/// \brief every pair of mesh edges sharing a mesh vertex, listed once
template <class FG, class VPM, class EIM>
Iterator_range<typename internal::Edge_midpoint_graph_traits<FG, VPM, EIM>::edge_iterator>
edges(const Edge_midpoint_graph<FG, VPM, EIM>& g)
{
  typedef typename internal::Edge_midpoint_graph_traits<FG, VPM, EIM>::edge_iterator Iterator;
  return make_range(Iterator(g.face_graph(), true), Iterator(g.face_graph(), false));
}

/// \brief the sum over mesh vertices of `deg(v)(deg(v) - 1)/2` (linear time)
template <class FG, class VPM, class EIM>
typename internal::Edge_midpoint_graph_traits<FG, VPM, EIM>::edges_size_type
num_edges(const Edge_midpoint_graph<FG, VPM, EIM>& g)
{
  std::size_t n = 0;
  for(auto v : vertices(g.face_graph()))
  {
    const std::size_t d = static_cast<std::size_t>(degree(v, g.face_graph()));
    n += d * (d - 1) / 2;
  }
  return n;
}

/// \brief the edges from `u = {i, j}` to the other mesh edges around `i`, then around `j`
template <class FG, class VPM, class EIM>
Iterator_range<typename internal::Edge_midpoint_graph_traits<FG, VPM, EIM>::out_edge_iterator>
out_edges(typename boost::graph_traits<FG>::edge_descriptor u,
          const Edge_midpoint_graph<FG, VPM, EIM>& g)
{
  typedef typename internal::Edge_midpoint_graph_traits<FG, VPM, EIM>::out_edge_iterator Iterator;
  return make_range(Iterator(u, g.face_graph(), true), Iterator(u, g.face_graph(), false));
}

/// \brief `deg(i) + deg(j) - 2` for `u = {i, j}`
template <class FG, class VPM, class EIM>
typename internal::Edge_midpoint_graph_traits<FG, VPM, EIM>::degree_size_type
out_degree(typename boost::graph_traits<FG>::edge_descriptor u,
           const Edge_midpoint_graph<FG, VPM, EIM>& g)
{
  const FG& tm = g.face_graph();
  const auto h = halfedge(u, tm);
  return static_cast<std::size_t>(degree(source(h, tm), tm)) +
         static_cast<std::size_t>(degree(target(h, tm), tm)) - 2;
}

/// \brief same as `out_degree()` (the graph is undirected)
template <class FG, class VPM, class EIM>
typename internal::Edge_midpoint_graph_traits<FG, VPM, EIM>::degree_size_type
degree(typename boost::graph_traits<FG>::edge_descriptor u,
       const Edge_midpoint_graph<FG, VPM, EIM>& g)
{
  return out_degree(u, g);
}

/// \brief the mesh edge the graph edge `e` starts from
template <class FG, class VPM, class EIM>
typename boost::graph_traits<FG>::edge_descriptor
source(const Edge_midpoint_graph_edge<FG>& e, const Edge_midpoint_graph<FG, VPM, EIM>& g)
{
  return edge(e.source_halfedge(), g.face_graph());
}

/// \brief the mesh edge the graph edge `e` goes to
template <class FG, class VPM, class EIM>
typename boost::graph_traits<FG>::edge_descriptor
target(const Edge_midpoint_graph_edge<FG>& e, const Edge_midpoint_graph<FG, VPM, EIM>& g)
{
  return edge(e.target_halfedge(), g.face_graph());
}

/// \brief the targets of `out_edges(u, g)`
template <class FG, class VPM, class EIM>
Iterator_range<typename internal::Edge_midpoint_graph_traits<FG, VPM, EIM>::adjacency_iterator>
adjacent_vertices(typename boost::graph_traits<FG>::edge_descriptor u,
                  const Edge_midpoint_graph<FG, VPM, EIM>& g)
{
  typedef typename internal::Edge_midpoint_graph_traits<FG, VPM, EIM>::adjacency_iterator Iterator;
  const auto range = out_edges(u, g);
  return make_range(Iterator(range.begin(), &g), Iterator(range.end(), &g));
}

/// \brief the edge from `u` to `v` and `true` if they share a mesh vertex, `false` otherwise
template <class FG, class VPM, class EIM>
std::pair<Edge_midpoint_graph_edge<FG>, bool>
edge(typename boost::graph_traits<FG>::edge_descriptor u,
     typename boost::graph_traits<FG>::edge_descriptor v,
     const Edge_midpoint_graph<FG, VPM, EIM>& g)
{
  for(const auto& e : out_edges(u, g))
    if(target(e, g) == v)
      return std::make_pair(e, true);
  return std::make_pair(Edge_midpoint_graph_edge<FG>(), false);
}

/// \brief the vertex index map of `g`: the edge index map of the mesh
template <class FG, class VPM, class EIM>
typename Edge_midpoint_graph<FG, VPM, EIM>::Edge_index_map
get(boost::vertex_index_t, const Edge_midpoint_graph<FG, VPM, EIM>& g)
{
  return g.edge_index_map();
}

/// \brief the index of the node `v`
template <class FG, class VPM, class EIM>
typename boost::property_traits<typename Edge_midpoint_graph<FG, VPM, EIM>::Edge_index_map>::value_type
get(boost::vertex_index_t, const Edge_midpoint_graph<FG, VPM, EIM>& g,
    typename boost::graph_traits<FG>::edge_descriptor v)
{
  return get(g.edge_index_map(), v);
}

/// \brief the midpoint map of `g`
template <class FG, class VPM, class EIM>
typename boost::property_map<Edge_midpoint_graph<FG, VPM, EIM>, boost::vertex_point_t>::const_type
get(boost::vertex_point_t, const Edge_midpoint_graph<FG, VPM, EIM>& g)
{
  return {g.face_graph(), g.vertex_point_map()};
}

/// \brief the midpoint of the node `v`
template <class FG, class VPM, class EIM>
typename Edge_midpoint_graph<FG, VPM, EIM>::Point_3
get(boost::vertex_point_t tag, const Edge_midpoint_graph<FG, VPM, EIM>& g,
    typename boost::graph_traits<FG>::edge_descriptor v)
{
  return get(get(tag, g), v);
}

/// @}

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_EDGE_MIDPOINT_GRAPH_H
