// Tests of laplacian_matrix.h: the one assembly D = L_w P over every representation x weights.
#include "test_helpers.h"

#include <CGAL/Laplacian_deformation/laplacian_matrix.h>
#include <CGAL/Laplacian_deformation/Vertex_based_representation.h>
#include <CGAL/Laplacian_deformation/Edge_based_representation.h>
#include <CGAL/Laplacian_deformation/Uniform_weights.h>
#include <CGAL/Laplacian_deformation/Cotangent_weights.h>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <set>

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

// The row-by-row assembly of D equals the product L_w P it stands for.
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
  };
  check(LD::internal::weighted_stencils(m, LD::Edge_based_representation(), LD::Cotangent_weights(), vpm, vim, Kernel()));
  check(LD::internal::weighted_stencils(m, LD::Vertex_based_representation(), LD::Uniform_weights(), vpm, vim, Kernel()));
}
