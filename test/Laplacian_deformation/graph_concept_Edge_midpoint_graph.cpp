// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

// Compile-time check that Edge_midpoint_graph models the BGL concepts it claims, over the two
// FaceGraph models used by the tests (and a Polyhedron_3 without ids, whose edge index is a
// dynamic property map).

#include "test_helpers.h"

#include <CGAL/Laplacian_deformation/Edge_midpoint_graph.h>

#include <boost/concept/assert.hpp>
#include <boost/graph/graph_concepts.hpp>

#include <type_traits>

namespace {

typedef CGAL::Polyhedron_3<Laplacian_deformation_test::Kernel> Polyhedron_without_ids;

template <class Mesh>
struct Check_concepts
{
  typedef CGAL::Laplacian_deformation::Edge_midpoint_graph<Mesh> Graph;
  typedef typename boost::graph_traits<Graph>::vertex_descriptor vertex_descriptor;
  typedef typename boost::graph_traits<Graph>::edge_descriptor edge_descriptor;

  BOOST_CONCEPT_ASSERT((boost::VertexListGraphConcept<Graph>));
  BOOST_CONCEPT_ASSERT((boost::IncidenceGraphConcept<Graph>));
  BOOST_CONCEPT_ASSERT((boost::AdjacencyGraphConcept<Graph>));
  BOOST_CONCEPT_ASSERT((boost::EdgeListGraphConcept<Graph>));
  BOOST_CONCEPT_ASSERT((boost::ReadablePropertyGraphConcept<Graph, vertex_descriptor, boost::vertex_index_t>));
  BOOST_CONCEPT_ASSERT((boost::ReadablePropertyGraphConcept<Graph, vertex_descriptor, boost::vertex_point_t>));

  static_assert(std::is_same<typename boost::graph_traits<Graph>::directed_category, boost::undirected_tag>::value,
                "Edge_midpoint_graph must be undirected");
  static_assert(std::is_same<vertex_descriptor, typename boost::graph_traits<Mesh>::edge_descriptor>::value,
                "the nodes must be the mesh edges");
  static_assert(std::is_same<typename boost::graph_traits<const Graph>::edge_descriptor, edge_descriptor>::value,
                "graph_traits of the const graph must agree");
};

template struct Check_concepts<Laplacian_deformation_test::Surface_mesh>;
template struct Check_concepts<Laplacian_deformation_test::Polyhedron>;
template struct Check_concepts<Polyhedron_without_ids>;

template <class Mesh>
bool is_undirected()
{
  typedef CGAL::Laplacian_deformation::Edge_midpoint_graph<Mesh> Graph;
  return std::is_convertible<typename boost::graph_traits<Graph>::directed_category,
                             boost::undirected_tag>::value &&
         std::is_convertible<typename boost::graph_traits<Graph>::traversal_category,
                             boost::edge_list_graph_tag>::value;
}

} // namespace

TEST(EdgeMidpointGraphConcept, IsUndirectedEdgeListGraph)
{
  EXPECT_TRUE(is_undirected<Laplacian_deformation_test::Surface_mesh>());
  EXPECT_TRUE(is_undirected<Laplacian_deformation_test::Polyhedron>());
  EXPECT_TRUE(is_undirected<Polyhedron_without_ids>());
}
