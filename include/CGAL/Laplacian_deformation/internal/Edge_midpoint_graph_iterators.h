// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_INTERNAL_EDGE_MIDPOINT_GRAPH_ITERATORS_H
#define CGAL_LAPLACIAN_DEFORMATION_INTERNAL_EDGE_MIDPOINT_GRAPH_ITERATORS_H

// Machinery of `CGAL::Laplacian_deformation::Edge_midpoint_graph`: its iterators, its midpoint
// map and the choice of its default edge index map. This file only knows about the underlying
// face graph and the edge descriptor type (a template parameter constructible from two
// halfedges pointing to the shared mesh vertex); it never includes the public header.

#include <CGAL/Kernel_traits.h>
#include <CGAL/Polyhedron_3_fwd.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/internal/Has_member_id.h>
#include <CGAL/boost/graph/iterator.h>
#include <CGAL/boost/graph/named_params_helper.h>
#include <CGAL/boost/graph/properties.h>

#include <boost/graph/graph_traits.hpp>
#include <boost/iterator/iterator_facade.hpp>
#include <boost/property_map/property_map.hpp>

#include <cstddef>
#include <type_traits>

namespace CGAL {

template <typename Graph, typename FIMap, typename VIMap, typename HIMap>
struct Face_filtered_graph;

namespace Laplacian_deformation {
namespace internal {

// Out-edges of the node `u = {i, j}` (a mesh edge): every other mesh edge around `i`,
// then every other mesh edge around `j`. Each mesh vertex is walked like
// `halfedges_around_target()` does (`h = opposite(next(h))`), which also visits border
// halfedges, so vertices on a boundary are handled.
template <class FaceGraph, class Edge>
class Edge_midpoint_graph_out_edge_iterator
  : public boost::iterator_facade<Edge_midpoint_graph_out_edge_iterator<FaceGraph, Edge>,
                                  Edge, boost::forward_traversal_tag, Edge>
{
  typedef boost::graph_traits<FaceGraph>                  Graph_traits;
  typedef typename Graph_traits::halfedge_descriptor      halfedge_descriptor;
  typedef typename Graph_traits::edge_descriptor          mesh_edge_descriptor;

public:
  Edge_midpoint_graph_out_edge_iterator() = default;

  // `begin == true`: first out-edge of `u`; otherwise the past-the-end iterator.
  Edge_midpoint_graph_out_edge_iterator(mesh_edge_descriptor u, const FaceGraph& tm, bool begin)
    : m_tm(&tm)
  {
    m_pivots[1] = halfedge(u, tm);            // points to j
    m_pivots[0] = opposite(m_pivots[1], tm);  // points to i
    if(begin)
      start_pass(0);
  }

private:
  friend class boost::iterator_core_access;

  void start_pass(int pass)
  {
    for(m_pass = pass; m_pass < 2; ++m_pass)
    {
      m_current = opposite(next(m_pivots[m_pass], *m_tm), *m_tm);
      if(m_current != m_pivots[m_pass])
        return;
    }
  }

  void increment()
  {
    m_current = opposite(next(m_current, *m_tm), *m_tm);
    if(m_current == m_pivots[m_pass])
      start_pass(m_pass + 1);
  }

  bool equal(const Edge_midpoint_graph_out_edge_iterator& other) const
  {
    return m_pass == other.m_pass && (m_pass == 2 || m_current == other.m_current);
  }

  Edge dereference() const { return Edge(m_pivots[m_pass], m_current); }

  const FaceGraph* m_tm = nullptr;
  halfedge_descriptor m_pivots[2];
  halfedge_descriptor m_current;
  int m_pass = 2;
};

// All edges of the node graph, each adjacency once: for every mesh halfedge `a` and
// every other halfedge `b` with the same target, the pair is listed when `a < b`.
template <class FaceGraph, class Edge>
class Edge_midpoint_graph_edge_iterator
  : public boost::iterator_facade<Edge_midpoint_graph_edge_iterator<FaceGraph, Edge>,
                                  Edge, boost::forward_traversal_tag, Edge>
{
  typedef boost::graph_traits<FaceGraph>                  Graph_traits;
  typedef typename Graph_traits::halfedge_descriptor      halfedge_descriptor;
  typedef typename Graph_traits::halfedge_iterator        halfedge_iterator;

public:
  Edge_midpoint_graph_edge_iterator() = default;

  // `begin == true`: first edge; otherwise the past-the-end iterator.
  Edge_midpoint_graph_edge_iterator(const FaceGraph& tm, bool begin)
    : m_tm(&tm)
  {
    auto range = halfedges(tm);
    m_it = begin ? range.begin() : range.end();
    m_end = range.end();
    if(m_it != m_end)
    {
      m_current = *m_it;
      increment();
    }
  }

private:
  friend class boost::iterator_core_access;

  void increment()
  {
    for(;;)
    {
      m_current = opposite(next(m_current, *m_tm), *m_tm);
      if(m_current == *m_it)
      {
        if(++m_it == m_end)
          return;
        m_current = *m_it;
      }
      else if(*m_it < m_current)
        return;
    }
  }

  bool equal(const Edge_midpoint_graph_edge_iterator& other) const
  {
    return m_it == other.m_it && (m_it == m_end || m_current == other.m_current);
  }

  Edge dereference() const { return Edge(*m_it, m_current); }

  const FaceGraph* m_tm = nullptr;
  halfedge_iterator m_it, m_end;
  halfedge_descriptor m_current;
};

// The `vertex_point` map of the graph: readable, gives the midpoint of a mesh edge.
template <class FaceGraph, class VertexPointMap>
class Edge_midpoint_map
{
public:
  typedef typename boost::graph_traits<FaceGraph>::edge_descriptor key_type;
  typedef typename boost::property_traits<VertexPointMap>::value_type value_type;
  typedef value_type reference;
  typedef boost::readable_property_map_tag category;

  Edge_midpoint_map() = default;
  Edge_midpoint_map(const FaceGraph& tm, VertexPointMap vpm) : m_tm(&tm), m_vpm(vpm) {}

  friend value_type get(const Edge_midpoint_map& map, key_type e)
  {
    typedef typename CGAL::Kernel_traits<value_type>::Kernel Kernel;
    const auto h = halfedge(e, *map.m_tm);
    return Kernel().construct_midpoint_3_object()(get(map.m_vpm, source(h, *map.m_tm)),
                                                  get(map.m_vpm, target(h, *map.m_tm)));
  }

private:
  const FaceGraph* m_tm = nullptr;
  VertexPointMap m_vpm;
};

// CGAL 5.5 declares an internal edge index for every `Polyhedron_3` (its edge descriptor always
// has an `id()` member), even when the halfedges carry no id, and using it does not compile.
template <class FaceGraph>
struct Has_usable_internal_edge_index : std::true_type {};

template <class Gt, class I, template <class, class, class> class HDS, class A>
struct Has_usable_internal_edge_index<CGAL::Polyhedron_3<Gt, I, HDS, A> >
  : std::integral_constant<bool,
      CGAL::internal::Has_member_id<typename CGAL::Polyhedron_3<Gt, I, HDS, A>::Halfedge>::value>
{};

// A `Face_filtered_graph` forwards the edge index of the underlying graph, which is not dense
// over the selected edges (it runs up to the underlying graph's number of edges).
template <class Graph, class FIMap, class VIMap, class HIMap>
struct Has_usable_internal_edge_index<CGAL::Face_filtered_graph<Graph, FIMap, VIMap, HIMap> >
  : std::false_type
{};

// The edge index map of the graph: the one of the named parameters, else CGAL's initialised
// one (`CGAL::get_initialized_edge_index_map()`) ...
template <class FaceGraph, class NamedParameters,
          bool = Has_usable_internal_edge_index<FaceGraph>::value>
struct Edge_index_map_selector
{
  typedef typename CGAL::GetInitializedEdgeIndexMap<FaceGraph, NamedParameters>::const_type type;

  static type index_map(const FaceGraph& tm, const NamedParameters& np)
  {
    return CGAL::get_initialized_edge_index_map(tm, np);
  }
};

// ... or, when the internal one is unusable, the dynamic index CGAL uses for graphs without one.
template <class FaceGraph, class NamedParameters>
struct Edge_index_map_selector<FaceGraph, NamedParameters, false>
{
  typedef typename boost::property_map<FaceGraph,
            CGAL::dynamic_edge_property_t<std::size_t> >::const_type Dynamic_map;
  typedef typename CGAL::internal_np::Lookup_named_param_def<CGAL::internal_np::edge_index_t,
                                                             NamedParameters, Dynamic_map>::type type;

  static type index_map(const FaceGraph& tm, const NamedParameters& np)
  {
    return select(CGAL::parameters::get_parameter(np, CGAL::internal_np::edge_index), tm);
  }

private:
  static type select(const type& map, const FaceGraph&) { return map; }

  static Dynamic_map select(CGAL::internal_np::Param_not_found, const FaceGraph& tm)
  {
    Dynamic_map map = get(CGAL::dynamic_edge_property_t<std::size_t>(), tm);
    std::size_t i = 0;
    for(auto e : edges(tm))
      put(map, e, i++);
    return map;
  }
};

} // namespace internal
} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_INTERNAL_EDGE_MIDPOINT_GRAPH_ITERATORS_H
