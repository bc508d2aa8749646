// Tests of laplacian_matrix.h: the one assembly D = L_w P over every representation x weights.
#include "test_helpers.h"

#include <CGAL/Laplacian_deformation/laplacian_matrix.h>
#include <CGAL/Laplacian_deformation/Vertex_based_representation.h>
#include <CGAL/Laplacian_deformation/Edge_based_representation.h>
#include <CGAL/Laplacian_deformation/Uniform_weights.h>
#include <CGAL/Laplacian_deformation/Cotangent_weights.h>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <CGAL/property_map.h>

#include <algorithm>
#include <bitset>
#include <cstdint>
#include <random>
#include <cstring>
#include <set>
#include <stdexcept>
#include <string>

namespace LD = CGAL::Laplacian_deformation;
using namespace Laplacian_deformation_test;

namespace {

template <class Mesh>
Eigen::MatrixXd positions(const Mesh& m)
{
  const auto vim = CGAL::get_initialized_vertex_index_map(m);
  Eigen::MatrixXd p(num_vertices(m), 3);
  for(auto v : vertices(m))
  {
    const auto& q = get(CGAL::vertex_point, m, v);
    p.row(get(vim, v)) << q.x(), q.y(), q.z();
  }
  return p;
}

// Runs `f(representation, weights)` for the four combinations.
template <class F>
void for_each_combination(F f)
{
  f(LD::Vertex_based_representation(), LD::Uniform_weights());
  f(LD::Vertex_based_representation(), LD::Cotangent_weights());
  f(LD::Edge_based_representation(), LD::Uniform_weights());
  f(LD::Edge_based_representation(), LD::Cotangent_weights());
}

template <class Mesh>
class LaplacianMatrix : public ::testing::Test {};
typedef ::testing::Types<Surface_mesh, Polyhedron> Mesh_types;
TYPED_TEST_SUITE(LaplacianMatrix, Mesh_types);

} // namespace

TYPED_TEST(LaplacianMatrix, ConstantFieldIsAnnihilated)
{
  for(const Soup& soup : { icosphere_soup(2), grid_soup(6, 5, 1., 0.15), cylinder_soup(12, 5) })
  {
    const TypeParam m = to_mesh<TypeParam>(soup);
    for_each_combination([&](auto rep, auto weights) {
      const Eigen::SparseMatrix<double> d = LD::laplacian_matrix(m, rep, weights);
      ASSERT_EQ(d.cols(), Eigen::Index(num_vertices(m)));
      const Eigen::VectorXd ones = Eigen::VectorXd::Ones(d.cols());
      const double scale = Eigen::MatrixXd(d).cwiseAbs().sum();
      EXPECT_LE((d * ones).cwiseAbs().maxCoeff(), 1e-14 * scale);
    });
  }
}

TYPED_TEST(LaplacianMatrix, RowCountsAndEdgeStencil)
{
  const TypeParam m = to_mesh<TypeParam>(icosphere_soup(2));
  const Eigen::SparseMatrix<double> dv =
      LD::laplacian_matrix(m, LD::Vertex_based_representation(), LD::Uniform_weights());
  const Eigen::SparseMatrix<double, Eigen::RowMajor> de =
      LD::laplacian_matrix(m, LD::Edge_based_representation(), LD::Uniform_weights());
  EXPECT_EQ(dv.rows(), Eigen::Index(num_vertices(m)));
  EXPECT_EQ(de.rows(), Eigen::Index(num_edges(m)));
  EXPECT_EQ(de.rows(), 3 * dv.rows() - 6);      // closed genus-0 mesh: |E| = 3|V| - 6

  // each edge row touches exactly the closed one-rings of both endpoints
  const auto vim = CGAL::get_initialized_vertex_index_map(m);
  const auto eim = CGAL::get_initialized_edge_index_map(m);
  for(auto e : edges(m))
  {
    std::set<Eigen::Index> expected, actual;
    for(auto v : { source(e, m), target(e, m) })
    {
      expected.insert(get(vim, v));
      for(auto w : CGAL::vertices_around_target(halfedge(v, m), m))
        expected.insert(get(vim, w));
    }
    for(Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(de, get(eim, e)); it; ++it)
      actual.insert(it.col());
    EXPECT_EQ(actual, expected) << "edge " << get(eim, e);
  }
}

TYPED_TEST(LaplacianMatrix, VertexOperatorOfClosedMeshHasRankNMinusOne)
{
  const TypeParam m = to_mesh<TypeParam>(icosphere_soup(1));
  for(int cot = 0; cot < 2; ++cot)
  {
    const Eigen::MatrixXd d = cot ? Eigen::MatrixXd(LD::laplacian_matrix(m, LD::Vertex_based_representation(), LD::Cotangent_weights()))
                                  : Eigen::MatrixXd(LD::laplacian_matrix(m, LD::Vertex_based_representation(), LD::Uniform_weights()));
    Eigen::FullPivLU<Eigen::MatrixXd> lu(d);
    lu.setThreshold(1e-10);
    EXPECT_EQ(lu.rank(), d.rows() - 1) << (cot ? "cotangent" : "uniform");
  }
}

namespace {

// relative Laplacian of every interior node: |delta_a| / sum_b |w_ab| |x_a - x_b|
template <class Mesh, class Rep, class Weights>
std::vector<double> interior_relative_laplacians(const Mesh& m, Rep rep, Weights weights)
{
  typedef typename boost::property_map<Mesh, CGAL::vertex_point_t>::const_type Vpm;
  const Vpm vpm = get(CGAL::vertex_point, m);
  const auto vim = CGAL::get_initialized_vertex_index_map(m);
  const LD::internal::Laplacian_stencils s =
      LD::internal::weighted_stencils(m, rep, weights, vpm, vim, Kernel());
  std::vector<Eigen::Vector3d> x;
  LD::internal::node_positions(s, LD::internal::vertex_positions(m, vpm, vim), x);

  const typename Rep::template Nodes<Mesh, Vpm> nodes(m, vpm);
  std::vector<double> result;
  for(auto a : nodes.nodes())
  {
    bool interior = true;
    nodes.combination(a, [&](auto v, double) { interior = interior && !CGAL::is_border(v, m); });
    if(!interior)
      continue;
    const std::size_t i = nodes.index(a);
    Eigen::Vector3d delta = Eigen::Vector3d::Zero();
    double scale = 0;
    for(std::size_t k = s.neighbor_start[i]; k < s.neighbor_start[i + 1]; ++k)
    {
      delta += s.weight[k] * (x[i] - x[s.neighbor[k]]);
      scale += std::abs(s.weight[k]) * (x[i] - x[s.neighbor[k]]).norm();
    }
    result.push_back(delta.norm() / scale);
  }
  return result;
}

} // namespace

TYPED_TEST(LaplacianMatrix, CotangentLinearPrecisionOnConvexPlanarRings)
{
  for(double perturbation : { 0., 0.15 })
    for(unsigned seed : { 1u, 2u, 3u })
    {
      const TypeParam m = to_mesh<TypeParam>(grid_soup(8, 7, 1., perturbation, seed));
      auto check = [&](auto rep, const char* name) {
        const std::vector<double> r = interior_relative_laplacians(m, rep, LD::Cotangent_weights());
        ASSERT_FALSE(r.empty());
        EXPECT_LE(*std::max_element(r.begin(), r.end()), 1e-12)
            << name << " perturbation " << perturbation << " seed " << seed;
      };
      check(LD::Vertex_based_representation(), "vertex-based");
      check(LD::Edge_based_representation(), "edge-based");
    }
}

TYPED_TEST(LaplacianMatrix, UniformWeightsLackLinearPrecisionOnIrregularGrid)
{
  const TypeParam m = to_mesh<TypeParam>(grid_soup(8, 7, 1., 0.15, 1));
  for(int edge_based = 0; edge_based < 2; ++edge_based)
  {
    const std::vector<double> r = edge_based
        ? interior_relative_laplacians(m, LD::Edge_based_representation(), LD::Uniform_weights())
        : interior_relative_laplacians(m, LD::Vertex_based_representation(), LD::Uniform_weights());
    EXPECT_GT(*std::max_element(r.begin(), r.end()), 1e-3) << (edge_based ? "edge" : "vertex");
  }
}

TYPED_TEST(LaplacianMatrix, DegenerateTrianglesGiveFiniteWeights)
{
  const TypeParam m = to_mesh<TypeParam>(degenerate_soup());
  for_each_combination([&](auto rep, auto weights) {
    const Eigen::SparseMatrix<double> d = LD::laplacian_matrix(m, rep, weights);
    EXPECT_TRUE(Eigen::MatrixXd(d).allFinite());
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(d.cols());
    EXPECT_LE((d * ones).cwiseAbs().maxCoeff(), 1e-9 * Eigen::MatrixXd(d).cwiseAbs().maxCoeff());
  });
}

TEST(LaplacianMatrix, RealMeshEdgeRowsAboutThreeTimesVertexRows)
{
  Surface_mesh m;
  ASSERT_TRUE(read_data_mesh("dino.off", m)) << data_path("dino.off");
  const auto dv = LD::laplacian_matrix(m, LD::Vertex_based_representation(), LD::Cotangent_weights());
  const auto de = LD::laplacian_matrix(m, LD::Edge_based_representation(), LD::Cotangent_weights());
  EXPECT_EQ(de.rows(), Eigen::Index(num_edges(m)));
  EXPECT_NEAR(double(de.rows()) / double(dv.rows()), 3., 0.1);
  EXPECT_GT(de.nonZeros(), 3 * dv.nonZeros());
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(de.cols());
  const Eigen::Map<const Eigen::VectorXd> values(de.valuePtr(), de.nonZeros());
  EXPECT_TRUE(values.allFinite());
  EXPECT_LE((de * ones).cwiseAbs().maxCoeff(), 1e-12 * values.cwiseAbs().sum());
}

// The row-by-row assembly of D equals the product L_w P it stands for, and bitwise the documented
// summation of each entry (its terms in the row's order).
TEST(LaplacianMatrix, DirectAssemblyEqualsProductOfWeightsAndCombinations)
{
  Surface_mesh m;
  ASSERT_TRUE(read_data_mesh("dino.off", m)) << data_path("dino.off");
  typedef boost::property_map<Surface_mesh, CGAL::vertex_point_t>::const_type Vpm;
  const Vpm vpm = get(CGAL::vertex_point, m);
  const auto vim = CGAL::get_initialized_vertex_index_map(m);
  auto check = [&](const LD::internal::Laplacian_stencils& s) {
    std::vector<Eigen::Triplet<double>> t;
    for(std::size_t a = 0; a < s.number_of_nodes; ++a)
    {
      double diagonal = 0;
      for(std::size_t k = s.neighbor_start[a]; k < s.neighbor_start[a + 1]; ++k)
      {
        diagonal += s.weight[k];
        t.emplace_back(int(a), int(s.neighbor[k]), -s.weight[k]);
      }
      t.emplace_back(int(a), int(a), diagonal);
    }
    Eigen::SparseMatrix<double> l(int(s.number_of_nodes), int(s.number_of_nodes));
    l.setFromTriplets(t.begin(), t.end());
    const Eigen::SparseMatrix<double> product = l * LD::internal::combination_matrix(s);
    const Eigen::SparseMatrix<double> d = LD::internal::laplacian_operator(s);
    EXPECT_EQ(d.rows(), product.rows());
    EXPECT_EQ(d.cols(), product.cols());
    EXPECT_LE((d - product).norm(), 1e-14 * product.norm());
    EXPECT_LE(d.nonZeros(), product.nonZeros());
    // bitwise, the documented summation: a row's terms (neighbours, then x_a), stably sorted by
    // vertex, each entry the sum in that order from 0; exact zeros dropped; columns increasing
    const Eigen::SparseMatrix<double, Eigen::RowMajor> by_rows = LD::internal::laplacian_operator(s);
    std::size_t rows_with_merged_terms = 0;
    for(std::size_t a = 0; a < s.number_of_nodes; ++a)
    {
      std::vector<std::pair<std::size_t, double>> terms;
      double diagonal = 0;
      for(std::size_t k = s.neighbor_start[a]; k < s.neighbor_start[a + 1]; ++k)
      {
        diagonal += s.weight[k];
        const std::size_t b = s.neighbor[k];
        for(std::size_t j = s.combination_start[b]; j < s.combination_start[b + 1]; ++j)
          terms.emplace_back(s.combination_vertex[j], -s.weight[k] * s.combination_coefficient[j]);
      }
      if(s.degree(a) > 0)
        for(std::size_t j = s.combination_start[a]; j < s.combination_start[a + 1]; ++j)
          terms.emplace_back(s.combination_vertex[j], diagonal * s.combination_coefficient[j]);
      std::stable_sort(terms.begin(), terms.end(),
                       [](const auto& x, const auto& y) { return x.first < y.first; });
      std::vector<std::pair<std::size_t, double>> expected;
      for(std::size_t i = 0; i < terms.size();)
      {
        double sum = 0.;
        const std::size_t v = terms[i].first;
        for(; i < terms.size() && terms[i].first == v; ++i)
          sum += terms[i].second;
        if(sum != 0)
          expected.emplace_back(v, sum);
      }
      rows_with_merged_terms += expected.size() < terms.size();
      std::vector<std::pair<std::size_t, double>> got;
      for(Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(by_rows, Eigen::Index(a)); it; ++it)
        got.emplace_back(std::size_t(it.col()), it.value());
      EXPECT_EQ(got.size(), expected.size()) << "row " << a;
      for(std::size_t i = 0; i < (std::min)(got.size(), expected.size()); ++i)
      {
        EXPECT_EQ(got[i].first, expected[i].first) << "row " << a;
        EXPECT_EQ(std::memcmp(&got[i].second, &expected[i].second, sizeof(double)), 0) << "row " << a;
      }
    }
    return rows_with_merged_terms;
  };
  const auto edge = LD::internal::weighted_stencils(m, LD::Edge_based_representation(), LD::Cotangent_weights(), vpm, vim, Kernel());
  EXPECT_GT(check(edge), edge.number_of_nodes / 2);   // an edge row's terms share vertices: merged
  check(LD::internal::weighted_stencils(m, LD::Vertex_based_representation(), LD::Uniform_weights(), vpm, vim, Kernel()));
}

// The region-local stencils (what Mesh_deformer builds for a ROI): every row of D that touches the
// region is there, bitwise equal to the whole-mesh operator's row (same columns, same values), with
// the same node positions; the other rows are empty or do not touch the region.
TYPED_TEST(LaplacianMatrix, RegionStencilsEqualWholeMeshRowsBitwise)
{
  namespace LDI = CGAL::Laplacian_deformation::internal;
  const Soup soups[] = { icosphere_soup(3), grid_soup(9, 7, 1., 0.2), cylinder_soup(14, 6), mixed_polygon_soup(6, 5) };
  for(const Soup& soup : soups)
  {
    const TypeParam m = to_mesh<TypeParam>(soup);
    const auto vim = CGAL::get_initialized_vertex_index_map(m);
    const std::size_t n = num_vertices(m);
    std::vector<Eigen::Vector3d> p(n);
    for(auto v : vertices(m))
    {
      const auto& q = get(CGAL::vertex_point, m, v);
      p[get(vim, v)] = Eigen::Vector3d(q.x(), q.y(), q.z());
    }
    std::vector<typename boost::graph_traits<TypeParam>::vertex_descriptor> all(vertices(m).begin(), vertices(m).end());
    // regions: one vertex, a band of vertices by index (several components on some meshes), every vertex
    std::vector<std::vector<typename boost::graph_traits<TypeParam>::vertex_descriptor>> regions;
    regions.push_back({ all[n / 2] });
    regions.emplace_back();
    for(auto v : all)
      if(get(vim, v) % 7 < 2 || get(vim, v) < n / 5)
        regions.back().push_back(v);
    regions.push_back(all);
    for_each_combination([&](auto rep, auto weights) {
      typedef typename decltype(rep)::template Nodes<TypeParam, typename boost::property_map<TypeParam, CGAL::vertex_point_t>::const_type> Nodes;
      const Nodes nodes(m, get(CGAL::vertex_point, m));
      static_assert(LDI::has_incident_nodes<Nodes>::value, "the package's nodes have incident_nodes()");
      LDI::Laplacian_stencils full = LDI::laplacian_stencils(nodes, n, vim);
      std::vector<Eigen::Vector3d> x_full, x_near;
      LDI::node_positions(full, p, x_full);
      LDI::compute_weights(full, x_full, weights, Kernel());
      const Eigen::SparseMatrix<double, Eigen::RowMajor> d_full = LDI::laplacian_operator(full);
      for(const auto& region : regions)
      {
        std::vector<char> in_region(n, 0);
        for(auto v : region)
          in_region[get(vim, v)] = 1;
        auto touches = [&](const Eigen::SparseMatrix<double, Eigen::RowMajor>& d, Eigen::Index r) {
          for(Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(d, r); it; ++it)
            if(in_region[std::size_t(it.col())])
              return true;
          return false;
        };
        LDI::Laplacian_stencils near = LDI::laplacian_stencils_near(nodes, n, vim, region);
        ASSERT_EQ(near.global_node.size(), near.number_of_nodes);
        ASSERT_TRUE(std::is_sorted(near.global_node.begin(), near.global_node.end()));
        LDI::node_positions(near, p, x_near);
        LDI::compute_weights(near, x_near, weights, Kernel());
        const Eigen::SparseMatrix<double, Eigen::RowMajor> d_near = LDI::laplacian_operator(near);
        std::size_t touching_near = 0, touching_full = 0;
        for(Eigen::Index r = 0; r < d_full.rows(); ++r)
          touching_full += touches(d_full, r);
        for(std::size_t a = 0; a < near.number_of_nodes; ++a)
        {
          const std::size_t g = near.global_node[a];
          ASSERT_EQ(x_near[a], x_full[g]);
          if(!touches(d_near, Eigen::Index(a)))
            continue;
          ++touching_near;
          ASSERT_EQ(near.degree(a), full.degree(g));
          for(std::size_t k = 0; k < near.degree(a); ++k)
          {
            ASSERT_EQ(near.global_node[near.neighbor[near.neighbor_start[a] + k]], full.neighbor[full.neighbor_start[g] + k]);
            ASSERT_EQ(near.weight[near.neighbor_start[a] + k], full.weight[full.neighbor_start[g] + k]);
          }
          Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(d_near, Eigen::Index(a)), jt(d_full, Eigen::Index(g));
          for(; it && jt; ++it, ++jt)
          {
            ASSERT_EQ(it.col(), jt.col());
            ASSERT_EQ(it.value(), jt.value());     // bitwise
          }
          EXPECT_FALSE(it || jt) << "row " << g << " has another number of entries";
        }
        EXPECT_EQ(touching_near, touching_full);
        EXPECT_GT(touching_near, 0u);
        if(region.size() == 1 && full.number_of_nodes > 500)
        {
          EXPECT_LT(near.number_of_nodes, full.number_of_nodes / 2);   // local: far fewer nodes
        }
      }
    });
  }
}

// The stencils hold 32-bit indices; a mesh whose node count does not fit is refused with
// std::length_error before anything proportional to it is allocated.
namespace {
struct Too_many_nodes
{
  typedef int node_descriptor;
  typedef int vertex_descriptor;
  std::size_t number_of_nodes() const { return std::size_t(1) << 33; }
  std::vector<int> nodes() const { return {}; }   // never walked: the size is refused first
  std::size_t index(node_descriptor a) const { return std::size_t(a); }
  std::vector<int> neighbors(node_descriptor) const { return {}; }
  template <class F> void combination(node_descriptor a, F&& f) const { f(a, 1.); }
  template <class F> void incident_nodes(vertex_descriptor v, F&& f) const { f(v); }
  template <class F> void fan_triangles(node_descriptor, F&&) const {}
};
} // namespace

TEST(LaplacianStencils, IndicesAre32BitAndOversizedMeshesAreRefused)
{
  static_assert(sizeof(CGAL::Laplacian_deformation::internal::Stencil_index) == 4, "32-bit stencil indices");
  const std::vector<int> region{0, 1};
  const CGAL::Identity_property_map<int> identity;
  try
  {
    CGAL::Laplacian_deformation::internal::laplacian_stencils_near(Too_many_nodes(), 2, identity, region);
    FAIL() << "no exception";
  }
  catch(const std::length_error& e)
  {
    EXPECT_NE(std::string(e.what()).find("32-bit"), std::string::npos) << e.what();
  }
}

// The assembly on TBB's threads (stencils, operator, delta = D p_rest: each in two passes that
// count then write in place) gives the sequential arrays bit for bit, on a mesh large enough for
// many blocks, for the whole mesh and for regions: a large one (the walk over every node), and two
// small ones (the walk from the region, in blocks of 1024; the smaller one also finds its local
// indices by bit ranks, the larger one has several blocks in the walk's first two phases).
TEST(LaplacianStencils, ParallelAssemblyEqualsSequentialBitwise)
{
  namespace LDI = CGAL::Laplacian_deformation::internal;
  const Surface_mesh m = to_mesh<Surface_mesh>(icosphere_soup(6));
  const auto vim = CGAL::get_initialized_vertex_index_map(m);
  const std::size_t n = num_vertices(m);
  ASSERT_GT(n, 40000u);
  std::vector<Eigen::Vector3d> p(n);
  for(auto v : vertices(m))
  {
    const auto& q = get(CGAL::vertex_point, m, v);
    p[get(vim, v)] = Eigen::Vector3d(q.x(), q.y(), q.z());
  }
  std::vector<boost::graph_traits<Surface_mesh>::vertex_descriptor> region, small, smaller;
  for(auto v : vertices(m))
  {
    const std::size_t i = get(vim, v);
    if(i % 3 != 0 || i < n / 4)
      region.push_back(v);
    if(i >= n / 3 && i < n / 3 + 2048)
      small.push_back(v);
    if(i >= n / 2 && i < n / 2 + 400)
      smaller.push_back(v);
  }
  ASSERT_LT(16 * small.size(), n);   // the walk from the region
  auto same_stencils = [](const LDI::Laplacian_stencils& a, const LDI::Laplacian_stencils& b) {
    EXPECT_EQ(a.number_of_nodes, b.number_of_nodes);
    EXPECT_EQ(a.combination_start, b.combination_start);
    EXPECT_EQ(a.combination_vertex, b.combination_vertex);
    EXPECT_EQ(a.combination_coefficient, b.combination_coefficient);
    EXPECT_EQ(a.neighbor_start, b.neighbor_start);
    EXPECT_EQ(a.neighbor, b.neighbor);
    EXPECT_EQ(a.fan_start, b.fan_start);
    EXPECT_EQ(a.fan, b.fan);
    EXPECT_EQ(a.global_node, b.global_node);
  };
  auto same_operator = [](const Eigen::SparseMatrix<double, Eigen::RowMajor>& a,
                          const Eigen::SparseMatrix<double, Eigen::RowMajor>& b) {
    ASSERT_EQ(a.rows(), b.rows());
    ASSERT_EQ(a.nonZeros(), b.nonZeros());
    EXPECT_TRUE(std::equal(a.outerIndexPtr(), a.outerIndexPtr() + a.rows() + 1, b.outerIndexPtr()));
    EXPECT_TRUE(std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(), b.innerIndexPtr()));
    EXPECT_TRUE(std::equal(a.valuePtr(), a.valuePtr() + a.nonZeros(), b.valuePtr()));   // bitwise
  };
  auto check = [&](auto rep) {
    typedef typename decltype(rep)::template Nodes<Surface_mesh, boost::property_map<Surface_mesh, CGAL::vertex_point_t>::const_type> Nodes;
    const Nodes nodes(m, get(CGAL::vertex_point, m));
    for(int local = 0; local < 4; ++local)
    {
      const auto& r = local == 1 ? region : local == 2 ? small : smaller;
      SCOPED_TRACE("region " + std::to_string(local) + " (0: the whole mesh)");
      LDI::Laplacian_stencils s[2];
      for(int parallel = 0; parallel < 2; ++parallel)
        s[parallel] = local ? LDI::laplacian_stencils_near(nodes, n, vim, r, parallel == 1)
                            : LDI::laplacian_stencils(nodes, n, vim, parallel == 1);
      same_stencils(s[0], s[1]);
      EXPECT_GT(s[0].fan.size(), 0u);
      if(local >= 2)
      {
        EXPECT_LT(s[0].number_of_nodes, nodes.number_of_nodes() / 4);   // only the region's neighbourhood
      }
      std::vector<Eigen::Vector3d> x;
      LDI::node_positions(s[0], p, x);
      LDI::compute_weights(s[0], x, LD::Cotangent_weights(), Kernel());
      const Eigen::SparseMatrix<double, Eigen::RowMajor> d = LDI::laplacian_operator(s[0]);
      same_operator(d, LDI::laplacian_operator(s[0], true));
      EXPECT_GT(d.nonZeros(), Eigen::Index(4 * s[0].number_of_nodes / 3));
      const Eigen::MatrixX3d delta = LDI::operator_times_positions(d, p);
      EXPECT_TRUE(delta == LDI::operator_times_positions(d, p, true));
      EXPECT_GT(delta.norm(), 0.);
    }
  };
  check(LD::Vertex_based_representation());
  check(LD::Edge_based_representation());
}

// The two helpers of the region walk: the radix sort by node index gives std::sort's order (keys
// distinct, up to 2^32), and the bit count is std::bitset's on every kind of word.
TEST(LaplacianStencils, RadixSortAndBitCountHelpers)
{
  namespace LDI = CGAL::Laplacian_deformation::internal;
  std::mt19937_64 random(7);
  for(std::size_t bound : {std::size_t(1), std::size_t(2), std::size_t(255), std::size_t(256), std::size_t(257),
                           std::size_t(70000), std::size_t(1) << 24, std::size_t(1) << 32})
  {
    std::set<std::size_t> keys;
    const std::size_t count = (std::min)(bound, std::size_t(5000));
    while(keys.size() < count)
      keys.insert(std::size_t(random() % bound));
    std::vector<std::pair<std::size_t, int>> entries;
    for(std::size_t k : keys)
      entries.emplace_back(k, int(k % 1000));
    std::shuffle(entries.begin(), entries.end(), random);
    std::vector<std::pair<std::size_t, int>> expected = entries;
    std::sort(expected.begin(), expected.end());
    LDI::sort_by_index(entries, bound);
    EXPECT_EQ(entries, expected) << "bound " << bound;
  }
  std::vector<std::uint64_t> words = {0, 1, ~std::uint64_t(0), std::uint64_t(1) << 63, 0x5555555555555555ull,
                                      0xaaaaaaaaaaaaaaaaull, 0x8000000000000001ull};
  for(int k = 0; k < 1000; ++k)
    words.push_back(random() & random());
  for(std::uint64_t w : words)
    EXPECT_EQ(LDI::population_count(w), std::bitset<64>(w).count()) << w;
}
