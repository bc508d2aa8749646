// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

// Run-time tests of Edge_midpoint_graph: counts, orientation of out-edges, edge(u, v, g),
// property maps and unchanged BGL algorithms (breadth_first_search, connected_components,
// dijkstra_shortest_paths), over Surface_mesh and Polyhedron_3 with ids.

#include "test_helpers.h"

#include <CGAL/Laplacian_deformation/Edge_midpoint_graph.h>

#include <boost/graph/breadth_first_search.hpp>
#include <boost/graph/connected_components.hpp>
#include <boost/graph/dijkstra_shortest_paths.hpp>
#include <boost/property_map/property_map.hpp>

#include <cmath>
#include <cstddef>
#include <iostream>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <unordered_set>
#include <vector>

namespace {

using namespace Laplacian_deformation_test;

template <class Mesh>
using Graph = CGAL::Laplacian_deformation::Edge_midpoint_graph<Mesh>;

template <class Mesh>
class EdgeMidpointGraph : public ::testing::Test {};

typedef ::testing::Types<Surface_mesh, Polyhedron> Face_graphs;
TYPED_TEST_SUITE(EdgeMidpointGraph, Face_graphs);

// true when the mesh edges `a` and `b` are distinct and share an end vertex
template <class Mesh>
bool share_a_vertex(typename boost::graph_traits<Mesh>::edge_descriptor a,
                    typename boost::graph_traits<Mesh>::edge_descriptor b, const Mesh& tm)
{
  if(a == b)
    return false;
  const auto ha = halfedge(a, tm), hb = halfedge(b, tm);
  return source(ha, tm) == source(hb, tm) || source(ha, tm) == target(hb, tm) ||
         target(ha, tm) == source(hb, tm) || target(ha, tm) == target(hb, tm);
}

template <class Mesh>
std::size_t expected_num_edges(const Mesh& tm)
{
  std::size_t n = 0;
  for(auto v : vertices(tm))
  {
    const std::size_t d = degree(v, tm);
    n += d * (d - 1) / 2;
  }
  return n;
}

// Checks every count of the graph against the mesh and against its own ranges.
template <class G>
void expect_counts_match(const G& g)
{
  typedef boost::graph_traits<G> Traits;
  typedef typename G::Face_graph Mesh;
  const Mesh& tm = g.face_graph();

  const std::size_t n = num_vertices(g);
  EXPECT_EQ(n, std::size_t(num_edges(tm)));
  EXPECT_EQ(n, std::size_t(std::distance(vertices(g).begin(), vertices(g).end())));

  const std::size_t m = num_edges(g);
  EXPECT_EQ(m, expected_num_edges(tm));
  EXPECT_EQ(m, std::size_t(std::distance(edges(g).begin(), edges(g).end())));

  // each adjacency is listed once by edges(g), whatever the orientation (== / < / hash)
  std::set<typename Traits::edge_descriptor> ordered;
  std::unordered_set<typename Traits::edge_descriptor> hashed;
  for(auto e : edges(g))
  {
    EXPECT_TRUE(share_a_vertex(source(e, g), target(e, g), tm));
    ordered.insert(e);
    hashed.insert(e);
  }
  EXPECT_EQ(m, ordered.size());
  EXPECT_EQ(m, hashed.size());

  // out-degrees sum to twice the number of edges; the index is dense
  std::size_t degree_sum = 0;
  std::vector<bool> index_seen(n, false);
  const auto index = get(boost::vertex_index, g);
  for(auto u : vertices(g))
  {
    const std::size_t d = out_degree(u, g);
    EXPECT_EQ(d, std::size_t(std::distance(out_edges(u, g).begin(), out_edges(u, g).end())));
    EXPECT_EQ(d, std::size_t(std::distance(adjacent_vertices(u, g).begin(), adjacent_vertices(u, g).end())));
    EXPECT_EQ(d, std::size_t(degree(u, g)));
    degree_sum += d;
    const std::size_t i = get(index, u);
    ASSERT_LT(i, n);
    EXPECT_FALSE(index_seen[i]) << "index " << i << " given twice";
    index_seen[i] = true;
    EXPECT_EQ(i, std::size_t(get(boost::vertex_index, g, u)));
  }
  EXPECT_EQ(degree_sum, 2 * m);
}

template <class Mesh>
void expect_counts_match(const Soup& soup)
{
  const Mesh tm = to_mesh<Mesh>(soup);
  ASSERT_TRUE(CGAL::is_valid_polygon_mesh(tm));
  expect_counts_match(Graph<Mesh>(tm));
}

// Reads a real mesh and checks its counts; prints them.
template <class Mesh>
void expect_real_mesh_counts_match(const std::string& file_name)
{
  Mesh tm;
  ASSERT_TRUE(read_data_mesh(file_name, tm))
    << "cannot read " << data_path(file_name) << " (run scripts/setup.sh to unpack the real meshes)";
  const Graph<Mesh> g(tm);
  expect_counts_match(g);
  std::cout << "[          ] " << file_name << ": " << num_vertices(tm) << " mesh vertices, "
            << num_edges(tm) << " mesh edges -> Edge_midpoint_graph with " << num_vertices(g)
            << " vertices and " << num_edges(g) << " edges" << std::endl;
}

// Edge weight of the graph: the distance between the two midpoints.
template <class G>
class Midpoint_distance_map
{
public:
  typedef typename boost::graph_traits<G>::edge_descriptor key_type;
  typedef double value_type;
  typedef double reference;
  typedef boost::readable_property_map_tag category;

  explicit Midpoint_distance_map(const G& g) : m_g(&g) {}

  friend double get(const Midpoint_distance_map& map, const key_type& e)
  {
    const auto midpoint = get(CGAL::vertex_point, *map.m_g);
    return std::sqrt(CGAL::to_double(CGAL::squared_distance(get(midpoint, source(e, *map.m_g)),
                                                            get(midpoint, target(e, *map.m_g)))));
  }

private:
  const G* m_g;
};

template <class G>
std::size_t number_of_components(const G& g)
{
  std::vector<std::size_t> component(num_vertices(g));
  return boost::connected_components(
    g, boost::make_iterator_property_map(component.begin(), get(boost::vertex_index, g)));
}

} // namespace

TYPED_TEST(EdgeMidpointGraph, CountsMatchMesh)
{
  {
    SCOPED_TRACE("icosphere (closed)");
    expect_counts_match<TypeParam>(icosphere_soup(2));
  }
  {
    SCOPED_TRACE("grid (boundary)");
    expect_counts_match<TypeParam>(grid_soup(5, 4, 1., 0.2));
  }
  {
    SCOPED_TRACE("cylinder (two boundary loops)");
    expect_counts_match<TypeParam>(cylinder_soup(8, 3));
  }
  {
    SCOPED_TRACE("quad grid (not a triangle mesh)");
    expect_counts_match<TypeParam>(quad_grid_soup(4, 3));
  }
  {
    SCOPED_TRACE("degenerate triangles");
    expect_counts_match<TypeParam>(degenerate_soup());
  }
}

TYPED_TEST(EdgeMidpointGraph, CountsMatchRealMeshes)
{
  {
    SCOPED_TRACE("dino.off");
    expect_real_mesh_counts_match<TypeParam>("dino.off");
  }
  {
    SCOPED_TRACE("armadillo.off");
    expect_real_mesh_counts_match<TypeParam>("armadillo.off");
  }
}

TYPED_TEST(EdgeMidpointGraph, OutEdgesStartAtTheirVertex)
{
  const TypeParam tm = to_mesh<TypeParam>(cylinder_soup(6, 2));
  const Graph<TypeParam> g(tm);
  for(auto u : vertices(g))
  {
    std::set<typename boost::graph_traits<TypeParam>::edge_descriptor> targets;
    auto adjacent = adjacent_vertices(u, g).begin();
    for(auto e : out_edges(u, g))
    {
      const auto v = target(e, g);
      EXPECT_EQ(source(e, g), u);
      EXPECT_TRUE(share_a_vertex(u, v, tm));
      EXPECT_EQ(*adjacent++, v);
      EXPECT_TRUE(targets.insert(v).second) << "parallel edge";

      // the same edge seen from v: equal and same hash, but oriented from v
      bool found = false;
      for(auto back : out_edges(v, g))
        if(target(back, g) == u)
        {
          found = true;
          EXPECT_EQ(source(back, g), v);
          EXPECT_EQ(back, e);
          EXPECT_FALSE(back != e);
          EXPECT_FALSE(back < e || e < back);
          EXPECT_EQ(hash_value(back), hash_value(e));
          EXPECT_EQ(std::hash<typename boost::graph_traits<Graph<TypeParam> >::edge_descriptor>()(back),
                    std::hash<typename boost::graph_traits<Graph<TypeParam> >::edge_descriptor>()(e));
        }
      EXPECT_TRUE(found) << "adjacency is not symmetric";
    }
    // the targets are exactly the mesh edges sharing a vertex with u
    std::size_t sharing = 0;
    for(auto v : vertices(g))
      sharing += share_a_vertex(u, v, tm) ? 1 : 0;
    EXPECT_EQ(sharing, targets.size());
  }
}

TYPED_TEST(EdgeMidpointGraph, EdgeFindsAdjacencies)
{
  const TypeParam tm = to_mesh<TypeParam>(icosphere_soup(1));
  const Graph<TypeParam> g(tm);
  std::size_t adjacent = 0, rejected = 0;
  for(auto u : vertices(g))
  {
    EXPECT_FALSE(edge(u, u, g).second);
    for(auto v : vertices(g))
    {
      const auto result = edge(u, v, g);
      EXPECT_EQ(result.second, share_a_vertex(u, v, tm));
      if(result.second)
      {
        ++adjacent;
        EXPECT_EQ(source(result.first, g), u);
        EXPECT_EQ(target(result.first, g), v);
      }
      else
        ++rejected;
    }
  }
  EXPECT_EQ(adjacent, 2 * num_edges(g));
  EXPECT_GT(rejected, std::size_t(0));
}

TYPED_TEST(EdgeMidpointGraph, PropertyMapsGiveMidpointsAndMeshIndices)
{
  const TypeParam tm = to_mesh<TypeParam>(bumpy_plane_soup(4));
  const Graph<TypeParam> g(tm);
  const auto midpoint = get(CGAL::vertex_point, g);
  const auto mesh_index = CGAL::get_initialized_edge_index_map(tm);
  const auto vpm = get(CGAL::vertex_point, tm);
  for(auto u : vertices(g))
  {
    const auto h = halfedge(u, tm);
    const Kernel::Point_3 expected = CGAL::midpoint(get(vpm, source(h, tm)), get(vpm, target(h, tm)));
    EXPECT_EQ(get(midpoint, u), expected);
    EXPECT_EQ(get(CGAL::vertex_point, g, u), expected);
    EXPECT_EQ(get(boost::vertex_index, g, u), get(mesh_index, u));
  }
}

TYPED_TEST(EdgeMidpointGraph, NamedParametersAreUsed)
{
  typedef typename boost::graph_traits<TypeParam>::vertex_descriptor vertex_descriptor;
  typedef typename boost::graph_traits<TypeParam>::edge_descriptor edge_descriptor;
  const TypeParam tm = to_mesh<TypeParam>(grid_soup(3, 3));

  // points lifted to z = 1, and edges indexed in reverse order
  std::map<vertex_descriptor, Kernel::Point_3> points;
  for(auto v : vertices(tm))
    points[v] = get(CGAL::vertex_point, tm, v) + Kernel::Vector_3(0, 0, 1);
  std::map<edge_descriptor, std::size_t> indices;
  std::size_t i = num_edges(tm);
  for(auto e : edges(tm))
    indices[e] = --i;

  const auto g = CGAL::Laplacian_deformation::make_edge_midpoint_graph(
    tm, CGAL::parameters::vertex_point_map(boost::make_assoc_property_map(points))
                         .edge_index_map(boost::make_assoc_property_map(indices)));
  expect_counts_match(g);
  for(auto u : vertices(g))
  {
    EXPECT_EQ(get(boost::vertex_index, g, u), indices[u]);
    EXPECT_EQ(get(CGAL::vertex_point, g, u).z(), 1.);
  }
}

TYPED_TEST(EdgeMidpointGraph, BreadthFirstSearchReachesAllNodes)
{
  const TypeParam tm = to_mesh<TypeParam>(cylinder_soup(8, 4));
  const Graph<TypeParam> g(tm);
  const auto index = get(boost::vertex_index, g);
  const std::size_t unreached = (std::numeric_limits<std::size_t>::max)();
  std::vector<std::size_t> hops(num_vertices(g), unreached);
  const auto start = *vertices(g).begin();
  hops[get(index, start)] = 0;
  auto hop_map = boost::make_iterator_property_map(hops.begin(), index);
  boost::breadth_first_search(
    g, start, boost::visitor(boost::make_bfs_visitor(boost::record_distances(hop_map, boost::on_tree_edge()))));

  for(auto u : vertices(g))
    EXPECT_NE(hops[get(index, u)], unreached) << "node " << get(index, u) << " not reached";
  for(auto e : edges(g))
  {
    const std::size_t a = hops[get(index, source(e, g))], b = hops[get(index, target(e, g))];
    EXPECT_LE((a > b ? a - b : b - a), std::size_t(1));
  }
}

TYPED_TEST(EdgeMidpointGraph, ConnectedComponentsMatchMesh)
{
  const TypeParam two = to_mesh<TypeParam>(two_components_soup());
  EXPECT_EQ(number_of_components(Graph<TypeParam>(two)), std::size_t(2));
  const TypeParam sphere = to_mesh<TypeParam>(icosphere_soup(2));
  EXPECT_EQ(number_of_components(Graph<TypeParam>(sphere)), std::size_t(1));
}

TYPED_TEST(EdgeMidpointGraph, DijkstraDistancesAreConsistent)
{
  const Soup soups[] = {icosphere_soup(2), grid_soup(6, 5, 0.5)};
  for(int k = 0; k < 2; ++k)
  {
    SCOPED_TRACE(k == 0 ? "icosphere" : "flat grid");
    const TypeParam tm = to_mesh<TypeParam>(soups[k]);
    const Graph<TypeParam> g(tm);
    const auto index = get(boost::vertex_index, g);
    const Midpoint_distance_map<Graph<TypeParam> > weight(g);
    std::vector<double> distance(num_vertices(g));
    const auto start = *std::next(vertices(g).begin(), num_vertices(g) / 2);
    boost::dijkstra_shortest_paths(
      g, start, boost::weight_map(weight).distance_map(boost::make_iterator_property_map(distance.begin(), index)));

    EXPECT_EQ(distance[get(index, start)], 0.);
    const double tolerance = 1e-12;
    for(auto e : edges(g))
    {
      const double a = distance[get(index, source(e, g))], b = distance[get(index, target(e, g))];
      EXPECT_LE(a, b + get(weight, e) + tolerance);
      EXPECT_LE(b, a + get(weight, e) + tolerance);
    }
    if(k == 1) // on a flat mesh no path between midpoints is shorter than the straight segment
    {
      const auto midpoint = get(CGAL::vertex_point, g);
      for(auto u : vertices(g))
        EXPECT_GE(distance[get(index, u)] + tolerance,
                  std::sqrt(CGAL::squared_distance(get(midpoint, u), get(midpoint, start))));
    }
  }
}

TEST(EdgeMidpointGraphWithoutIds, UsesDynamicEdgeIndex)
{
  typedef CGAL::Polyhedron_3<Kernel> Polyhedron_without_ids;
  const Polyhedron_without_ids tm = to_mesh<Polyhedron_without_ids>(two_components_soup());
  const Graph<Polyhedron_without_ids> g(tm);
  expect_counts_match(g);
  EXPECT_EQ(number_of_components(g), std::size_t(2));
}
