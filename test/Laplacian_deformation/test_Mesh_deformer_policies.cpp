// Tests of Mesh_deformer.h: the typed patterns of mesh_deformer_patterns.h for the fixed,
// rotation, similarity and S*R1 transforms (test_Mesh_deformer.cpp instantiates them for the other
// three); policy instances, the run-time policies Any_weights / Any_transform and the ROI's operator.
#include "mesh_deformer_patterns.h"

#include <iterator>
#include <map>

using namespace Mesh_deformer_test;

namespace Mesh_deformer_test {

#ifdef LAPLACIAN_DEFORMATION_TEST_FEWER_COMBINATIONS
// the sanitizer build (scripts/test.d/40-sanitizers.sh): 5 of its 8 combinations (the other three,
// edge-based cotangent principal, R2*S*R1 and anchored S*R1, are in test_Mesh_deformer.cpp): one
// pair each for the vertex-based representation and the uniform weights, and the edge-based
// cotangent rotation and S*R1 (every policy, Fixed and Similarity included, is tested under the
// sanitizers by test_policies_and_solver)
typedef ::testing::Types<
  Config<LD::Vertex_based_representation, LD::Uniform_weights, LD::Fixed_transform>,
  Config<LD::Vertex_based_representation, LD::Cotangent_weights, LD::Scaled_rotation_transform>,
  Config<LD::Edge_based_representation, LD::Uniform_weights, LD::Scaled_rotation_transform>,
  Config<LD::Edge_based_representation, LD::Cotangent_weights, LD::Rotation_transform>,
  Config<LD::Edge_based_representation, LD::Cotangent_weights, LD::Scaled_rotation_transform>>
    First_transforms;
typedef ::testing::Types<
  Config<LD::Vertex_based_representation, LD::Cotangent_weights, LD::Scaled_rotation_transform>,
  Config<LD::Edge_based_representation, LD::Uniform_weights, LD::Scaled_rotation_transform>,
  Config<LD::Edge_based_representation, LD::Cotangent_weights, LD::Rotation_transform>,
  Config<LD::Edge_based_representation, LD::Cotangent_weights, LD::Scaled_rotation_transform>>
    First_rotation_based;
#else
#define LD_TRANSFORMS(R, W)                                                                            \
  Config<R, W, LD::Fixed_transform>, Config<R, W, LD::Rotation_transform>,                                \
  Config<R, W, LD::Similarity_transform>, Config<R, W, LD::Scaled_rotation_transform>
#define LD_ROTATION_BASED(R, W)                                                                        \
  Config<R, W, LD::Rotation_transform>, Config<R, W, LD::Similarity_transform>,                           \
  Config<R, W, LD::Scaled_rotation_transform>
typedef ::testing::Types<
  LD_TRANSFORMS(LD::Vertex_based_representation, LD::Uniform_weights),
  LD_TRANSFORMS(LD::Vertex_based_representation, LD::Cotangent_weights),
  LD_TRANSFORMS(LD::Edge_based_representation, LD::Uniform_weights),
  LD_TRANSFORMS(LD::Edge_based_representation, LD::Cotangent_weights)> First_transforms;
typedef ::testing::Types<
  LD_ROTATION_BASED(LD::Vertex_based_representation, LD::Uniform_weights),
  LD_ROTATION_BASED(LD::Vertex_based_representation, LD::Cotangent_weights),
  LD_ROTATION_BASED(LD::Edge_based_representation, LD::Uniform_weights),
  LD_ROTATION_BASED(LD::Edge_based_representation, LD::Cotangent_weights)> First_rotation_based;
#undef LD_TRANSFORMS
#undef LD_ROTATION_BASED
#endif
INSTANTIATE_TYPED_TEST_SUITE_P(Transforms1to4, EveryCombination, First_transforms);
INSTANTIATE_TYPED_TEST_SUITE_P(Transforms1to4, RotationBased, First_rotation_based);

} // namespace Mesh_deformer_test


namespace {

// stateful policies: cotangent and uniform weights blended by `t`; T = s I
struct Blended_weights
{
  double t = 1.;
  template <class GeomTraits>
  void weights(const LD::Node_cell<GeomTraits>& cell, std::vector<double>& w) const
  {
    std::vector<double> u;
    LD::Cotangent_weights().weights(cell, w);
    LD::Uniform_weights().weights(cell, u);
    for(std::size_t i = 0; i < w.size(); ++i)
      w[i] = t * w[i] + (1 - t) * u[i];
  }
};
struct Scaling_transform
{
  double s = 1.;
  Eigen::Matrix3d transform(const LD::Transform_cell&) const { return s * Eigen::Matrix3d::Identity(); }
};

} // namespace

// A policy instance with a member behaves the same in Mesh_deformer (constructor or setters),
// deform_mesh() and laplacian_matrix().
TEST(PolicyInstances, StatefulPoliciesBehaveTheSameEverywhere)
{
  typedef LD::Mesh_deformer<Surface_mesh, LD::Edge_based_representation, Blended_weights, Scaling_transform> Deformer;
  const Blended_weights w{0.3};
  const Scaling_transform t{1.25};
  Surface_mesh m = bumpy_plane();
  const Task task = patch_task(m);
  std::vector<Point_3> targets;
  for(vertex_descriptor v : task.controls)
    targets.push_back(m.point(v) + Kernel::Vector_3(0, 0.1, 0.3));
  auto select = [&](Deformer& d) {
    d.insert_roi_vertices(task.roi.begin(), task.roi.end());
    d.insert_control_vertices(task.controls.begin(), task.controls.end());
    for(std::size_t i = 0; i < task.controls.size(); ++i)
      d.set_target_position(task.controls[i], targets[i]);
  };
  auto deform = [&](Deformer& d) {
    select(d);
    return d.deform(3, 0.);
  };

  Surface_mesh by_class = m;
  Deformer d(by_class, w, t);
  EXPECT_EQ(d.weight_policy().t, 0.3);
  EXPECT_EQ(d.transform_policy().s, 1.25);
  ASSERT_TRUE(deform(d));

  Surface_mesh by_function = m;
  ASSERT_TRUE(LD::deform_mesh(by_function, task.roi, task.controls, targets,
      LD::parameters::weight_policy(w, LD::parameters::transform_policy(t,
      LD::parameters::tolerance(0., CGAL::parameters::number_of_iterations(3u))))));
  EXPECT_EQ(positions(by_function), positions(by_class));

  // the setters: the same result; the weights rebuild the operator
  Surface_mesh by_setters = m;
  Deformer e(by_setters);
  select(e);
  ASSERT_TRUE(e.preprocess());
  e.set_weight_policy(w);
  e.set_transform_policy(t);
  ASSERT_TRUE(e.deform(3, 0.));
  EXPECT_EQ(positions(by_setters), positions(by_class));
  EXPECT_EQ(e.number_of_factorizations(), 2u);

  // the state matters: the default-constructed policies give another result
  Surface_mesh by_default = m;
  Deformer f(by_default);
  ASSERT_TRUE(deform(f));
  EXPECT_GT(max_distance(positions(by_default), positions(by_class), diagonal(m)), 1e-3);

  // laplacian_matrix() uses the instance: D is linear in the weights
  const Eigen::SparseMatrix<double> blended = LD::laplacian_matrix(m, LD::Edge_based_representation(), w);
  const Eigen::SparseMatrix<double> cot = LD::laplacian_matrix(m, LD::Edge_based_representation(), LD::Cotangent_weights());
  const Eigen::SparseMatrix<double> uni = LD::laplacian_matrix(m, LD::Edge_based_representation(), LD::Uniform_weights());
  const Eigen::MatrixXd expected = 0.3 * Eigen::MatrixXd(cot) + 0.7 * Eigen::MatrixXd(uni);
  EXPECT_LE((Eigen::MatrixXd(blended) - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff());
}

// Any_transform holding Fixed_transform is Fixed_transform for the start; switching the
// transform at run time takes effect at the next iteration without refactoring.
TEST(PolicyInstances, AnyTransformSwitchesAtRunTime)
{
  typedef LD::Mesh_deformer<Surface_mesh, LD::Edge_based_representation, LD::Any_weights, LD::Any_transform> Erased;
  typedef LD::Mesh_deformer<Surface_mesh, LD::Edge_based_representation, LD::Cotangent_weights,
                            LD::Rotation_transform> Static;
  Surface_mesh m = bumpy_plane();
  const Task task = patch_task(m);
  const Eigen::Vector3d c(0.5, 0.5, 0);
  const auto turn = [&](const Eigen::Vector3d& p) { return Eigen::Vector3d(some_rotation() * (p - c) + c); };

  Surface_mesh a = m, b = m;
  Erased e(a, LD::Cotangent_weights(), LD::Fixed_transform());
  e.set_start(LD::ROTATION_START);
  e.insert_roi_vertices(task.roi.begin(), task.roi.end());
  e.insert_control_vertices(task.controls.begin(), task.controls.end());
  for(vertex_descriptor v : task.controls)
    e.set_target_position(v, to_point(turn(positions(m)[std::size_t(v)])));
  ASSERT_TRUE(e.deform(1, 0.));
  EXPECT_EQ(e.number_of_control_groups(), 0u);   // Fixed_transform: no start field
  // then rotation fits, continuing from the solution: as a static Rotation_transform deformer
  // started from the same positions
  e.set_transform_policy(LD::Rotation_transform());
  ASSERT_TRUE(e.deform(2, 0.));
  EXPECT_EQ(e.number_of_factorizations(), 1u);

  Static s(b);
  s.insert_roi_vertices(task.roi.begin(), task.roi.end());
  s.insert_control_vertices(task.controls.begin(), task.controls.end());
  for(vertex_descriptor v : task.controls)
    s.set_target_position(v, to_point(turn(positions(m)[std::size_t(v)])));
  Surface_mesh fixed_once = m;
  Erased first(fixed_once, LD::Cotangent_weights(), LD::Fixed_transform());
  first.insert_roi_vertices(task.roi.begin(), task.roi.end());
  first.insert_control_vertices(task.controls.begin(), task.controls.end());
  for(vertex_descriptor v : task.controls)
    first.set_target_position(v, to_point(turn(positions(m)[std::size_t(v)])));
  ASSERT_TRUE(first.deform(1, 0.));
  for(vertex_descriptor v : vertices(b))
    b.point(v) = fixed_once.point(v);
  ASSERT_TRUE(s.start_from_current_positions());
  ASSERT_TRUE(s.deform(2, 0.));
  EXPECT_EQ(positions(a), positions(b));
}

namespace {

// A representation's nodes without the optional incident_nodes(): Mesh_deformer then builds the
// stencils, weights and operator of the whole mesh (the path of user models that lack it).
template <class Representation>
struct Whole_mesh
{
  template <class TriangleMesh, class VertexPointMap>
  class Nodes : private Representation::template Nodes<TriangleMesh, VertexPointMap>
  {
    typedef typename Representation::template Nodes<TriangleMesh, VertexPointMap> Base;

  public:
    typedef typename Base::Triangle_mesh Triangle_mesh;
    typedef typename Base::Node_graph Node_graph;
    typedef typename Base::node_descriptor node_descriptor;
    typedef typename Base::vertex_descriptor vertex_descriptor;
    Nodes(const TriangleMesh& tm, VertexPointMap vpm) : Base(tm, vpm) {}
    using Base::graph;
    using Base::number_of_nodes;
    using Base::nodes;
    using Base::index;
    using Base::combination;
    using Base::neighbors;
    using Base::fan_triangles;
  };
};

} // namespace

// The operator built for the ROI only (the default with the package's representations) gives
// bitwise the result of the whole mesh's operator: on the dino, for both representations, hard and
// soft controls, the rotation-aware start and the rigidity rows, through a smaller ROI (the
// operator is reused), a larger one (rebuilt) and new targets.
TEST(MeshDeformer, RegionOperatorGivesBitwiseTheWholeMeshResult)
{
  Surface_mesh dino;
  ASSERT_TRUE(read_data_mesh("dino.off", dino)) << data_path("dino.off");
  const vertex_descriptor seed = *std::next(vertices(dino).begin(), 1000);
  auto rings = [&](int k, std::vector<vertex_descriptor>& roi, std::vector<vertex_descriptor>& handle) {
    roi.assign(1, seed);
    handle.assign(1, seed);
    std::map<vertex_descriptor, int> ring{ { seed, 0 } };
    for(std::size_t i = 0; i < roi.size(); ++i)
      for(vertex_descriptor w : CGAL::vertices_around_target(halfedge(roi[i], dino), dino))
        if(ring[roi[i]] < k && ring.emplace(w, ring[roi[i]] + 1).second)
        {
          roi.push_back(w);
          if(ring[w] == 1)
            handle.push_back(w);
        }
  };
  const double diag = diagonal(dino);
  auto compare = [&](auto local_tag, auto whole_tag, const char* what) {
    typedef typename decltype(local_tag)::Deformer Local;
    typedef typename decltype(whole_tag)::Deformer Whole;
    for(int variant = 0; variant < 3; ++variant)
    {
      SCOPED_TRACE(std::string(what) + " variant " + std::to_string(variant));
      Surface_mesh ml = dino, mw = dino;
      Local dl(ml);
      Whole dw(mw);
      std::vector<vertex_descriptor> roi, handle;
      auto run = [&](int k, const Eigen::Vector3d& pull, double angle) {
        rings(k, roi, handle);
        auto setup = [&](auto& d) {
          d.clear_roi_vertices();
          d.insert_roi_vertices(roi.begin(), roi.end());
          d.insert_control_vertices(handle.begin(), handle.end());
          if(variant == 1)
            d.set_soft_constraints(0.5);
          if(variant == 2)
          {
            d.set_start(LD::ROTATION_START);
            d.set_rigidity_weight(0.3);
          }
          d.reset();
          d.rotate(handle.begin(), handle.end(), Eigen::Vector3d(dino.point(seed).x(), dino.point(seed).y(), dino.point(seed).z()),
                   Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ())));
          d.translate(handle.begin(), handle.end(), pull);
          return d.deform(4, 0.);
        };
        const LD::Deformation_result rl = setup(dl), rw = setup(dw);
        ASSERT_TRUE(rl) << rl.message;
        ASSERT_TRUE(rw) << rw.message;
        EXPECT_EQ(positions(ml), positions(mw));        // bitwise
        EXPECT_EQ(rl.energies, rw.energies);
        ASSERT_EQ(dl.row_nodes(), dw.row_nodes());
        for(std::size_t a : dl.row_nodes())
          ASSERT_EQ(dl.node_transform(a), dw.node_transform(a));
        EXPECT_LT(dl.row_nodes().size(), dl.nodes().number_of_nodes() / 4);
      };
      run(10, Eigen::Vector3d(0.05 * diag, 0, 0), 0.6);   // built for 10 rings
      run(6, Eigen::Vector3d(0, 0.03 * diag, 0), -0.4);   // inside: reused
      run(14, Eigen::Vector3d(0, 0, 0.04 * diag), 0.9);   // beyond: rebuilt
    }
  };
  typedef LD::Cotangent_weights C;
  typedef LD::Scaled_rotation_transform T;
  compare(Config<LD::Edge_based_representation, C, T>(), Config<Whole_mesh<LD::Edge_based_representation>, C, T>(), "edge");
  compare(Config<LD::Vertex_based_representation, C, T>(), Config<Whole_mesh<LD::Vertex_based_representation>, C, T>(), "vertex");
}
