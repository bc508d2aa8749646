// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_TEST_MESH_DEFORMER_PATTERNS_H
#define CGAL_LAPLACIAN_DEFORMATION_TEST_MESH_DEFORMER_PATTERNS_H

// The typed test patterns of Mesh_deformer (DESIGN section 6) and their helpers: every
// representation x weights x transform combination (EveryCombination) and every rotation-fitting
// one (RotationBased). Each of test_Mesh_deformer.cpp and test_Mesh_deformer_policies.cpp
// instantiates them for its share of the transforms, so that the two halves of the engine's
// instantiations compile in parallel (the typed suites are most of the test build's time).
#include "test_helpers.h"

#include <CGAL/Laplacian_deformation.h>
#include <CGAL/Laplacian_deformation/IO/Botsch08.h>

#include <CGAL/Polygon_mesh_processing/bbox.h>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <type_traits>
#include <vector>

namespace Mesh_deformer_test {

namespace LD = CGAL::Laplacian_deformation;
using namespace Laplacian_deformation_test;

typedef Kernel::Point_3 Point_3;
typedef boost::graph_traits<Surface_mesh>::vertex_descriptor vertex_descriptor;

template <class R, class W, class T>
struct Config
{
  typedef R Representation;
  typedef W Weights;
  typedef T Transform;
  typedef LD::Mesh_deformer<Surface_mesh, R, W, T, CGAL::Default, CGAL::Default, CGAL::Sequential_tag> Deformer;
};

// positions as Eigen vectors, by vertex index
inline std::vector<Eigen::Vector3d> positions(const Surface_mesh& m)
{
  std::vector<Eigen::Vector3d> p;
  for(vertex_descriptor v : vertices(m))
    p.emplace_back(m.point(v).x(), m.point(v).y(), m.point(v).z());
  return p;
}

inline double diagonal(const Surface_mesh& m)
{
  const CGAL::Bbox_3 b = CGAL::Polygon_mesh_processing::bbox(m);
  return std::sqrt(CGAL::square(b.xmax() - b.xmin()) + CGAL::square(b.ymax() - b.ymin()) +
                   CGAL::square(b.zmax() - b.zmin()));
}

// the largest distance between two position sets, relative to `scale`
inline double max_distance(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b, double scale)
{
  double d = 0;
  for(std::size_t i = 0; i < a.size(); ++i)
    d = (std::max)(d, (a[i] - b[i]).norm());
  return d / scale;
}

inline Point_3 to_point(const Eigen::Vector3d& p) { return Point_3(p.x(), p.y(), p.z()); }

inline Surface_mesh bumpy_sphere()
{
  Soup s = icosphere_soup(2);
  for(auto& p : s.points)
  {
    const double r = 1. + 0.08 * std::sin(3 * p[0]) * std::cos(2 * p[1]) + 0.05 * std::sin(4 * p[2]);
    for(double& c : p)
      c *= r;
  }
  return to_mesh<Surface_mesh>(s);
}

inline Surface_mesh bumpy_plane() { return to_mesh<Surface_mesh>(bumpy_plane_soup(12, 0.08)); }

// A deformation task: ROI, controls and a map from rest to target positions.
struct Task
{
  std::vector<vertex_descriptor> roi, controls;
};

// closed mesh: the whole mesh is the ROI, every 7th vertex a control
inline Task spread_controls(const Surface_mesh& m)
{
  Task t;
  for(vertex_descriptor v : vertices(m))
  {
    t.roi.push_back(v);
    if(std::size_t(v) % 7 == 0)
      t.controls.push_back(v);
  }
  return t;
}

// open patch: interior vertices free, border fixed, vertices near the centre are controls
inline Task patch_task(const Surface_mesh& m)
{
  Task t;
  for(vertex_descriptor v : vertices(m))
  {
    if(CGAL::is_border(v, m))
      continue;
    t.roi.push_back(v);
    const Point_3& p = m.point(v);
    if(CGAL::square(p.x() - 0.5) + CGAL::square(p.y() - 0.5) < 0.02)
      t.controls.push_back(v);
  }
  return t;
}

template <class Deformer, class Map>
LD::Deformation_result run(Surface_mesh& m, const Task& t, Map target_of, unsigned int iterations,
                           double tolerance = 0.)
{
  Deformer d(m);
  d.insert_roi_vertices(t.roi.begin(), t.roi.end());
  d.insert_control_vertices(t.controls.begin(), t.controls.end());
  for(vertex_descriptor v : t.controls)
    d.set_target_position(v, to_point(target_of(positions(m)[std::size_t(v)])));
  return d.deform(iterations, tolerance);
}

inline Eigen::Matrix3d some_rotation()
{
  return Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
}

// Starts at `start(rest)`, with targets at the same map of the rest positions, iterates once.
template <class Deformer, class Map>
double fixed_point_defect(Map start)
{
  Surface_mesh m = bumpy_sphere();
  const auto rest = positions(m);
  const Task task = spread_controls(m);
  Deformer d(m);
  d.insert_roi_vertices(task.roi.begin(), task.roi.end());
  d.insert_control_vertices(task.controls.begin(), task.controls.end());
  for(vertex_descriptor v : task.controls)
    d.set_target_position(v, to_point(start(rest[std::size_t(v)])));
  EXPECT_TRUE(d.preprocess());
  std::vector<Eigen::Vector3d> expected;
  for(vertex_descriptor v : vertices(m))
  {
    expected.push_back(start(rest[std::size_t(v)]));
    m.point(v) = to_point(expected.back());
  }
  EXPECT_TRUE(d.start_from_current_positions());
  const auto r = d.deform(1, 0.);
  EXPECT_TRUE(r) << r.message;
  return max_distance(positions(m), expected, diagonal(m));
}

// the controls within `radius` of `c`
inline std::vector<vertex_descriptor> controls_near(const Surface_mesh& m, const Eigen::Vector3d& c, double radius)
{
  std::vector<vertex_descriptor> out;
  for(vertex_descriptor v : vertices(m))
    if((positions(m)[std::size_t(v)] - c).norm() < radius)
      out.push_back(v);
  return out;
}

// ---- The cactus task (Any policies against static ones) -------------------------------------

// the cactus task of the data folder (CGAL's cactus with its Botsch08 selection and transform)
struct Cactus
{
  Surface_mesh mesh;
  std::vector<vertex_descriptor> roi, handles;
  std::vector<Point_3> targets;
};

inline bool read_cactus(Cactus& c)
{
  if(!read_data_mesh("cactus.off", c.mesh))
    return false;
  std::vector<int> status;
  Eigen::Matrix4d t;
  std::string error;
  std::ifstream s(data_path("cactus.sel")), d(data_path("cactus.def"));
  if(!LD::IO::read_botsch08_selection(s, status, error, num_vertices(c.mesh)) ||
     !LD::IO::read_botsch08_transform(d, t, error))
    return false;
  for(vertex_descriptor v : vertices(c.mesh))
    if(status[std::size_t(v)] == LD::IO::BOTSCH08_REGION_OF_INTEREST)
      c.roi.push_back(v);
    else if(status[std::size_t(v)] == LD::IO::BOTSCH08_HANDLE)
    {
      c.handles.push_back(v);
      const Point_3& p = c.mesh.point(v);
      const Eigen::Vector4d q = t * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.);
      c.targets.emplace_back(q.x(), q.y(), q.z());
    }
  return true;
}

// deforms a copy of the cactus with `d` (built on `m`), 4 iterations of deform(1, 0) from `start`
template <class Deformer>
LD::Deformation_result deform_cactus(Deformer& d, Surface_mesh& m, const Cactus& c, LD::Deformation_start start)
{
  d.set_start(start);
  d.insert_roi_vertices(c.roi.begin(), c.roi.end());
  d.insert_control_vertices(c.handles.begin(), c.handles.end());
  for(std::size_t i = 0; i < c.handles.size(); ++i)
    d.set_target_position(c.handles[i], c.targets[i]);
  LD::Deformation_result r;
  for(int k = 0; k < 4 && (k == 0 || r); ++k)
    r = d.deform(1, 0.);
  (void)m;
  return r;
}


// ---- Every representation x weights x transform ----------------------------------------------

template <class C>
class EveryCombination : public ::testing::Test {};
TYPED_TEST_SUITE_P(EveryCombination);

TYPED_TEST_P(EveryCombination, NothingMovesWhenTargetsAreRest)
{
  Surface_mesh m = bumpy_plane();
  const auto rest = positions(m);
  const auto r = run<typename TypeParam::Deformer>(m, patch_task(m), [](const Eigen::Vector3d& p) { return p; }, 4);
  ASSERT_TRUE(r) << r.message;
  EXPECT_LE(max_distance(positions(m), rest, diagonal(m)), 1e-12);
}

TYPED_TEST_P(EveryCombination, TranslationAndUniformScaleInvariance)
{
  Surface_mesh m = bumpy_plane();
  const Task task = patch_task(m);
  const auto pull = [](const Eigen::Vector3d& p) { return Eigen::Vector3d(p + Eigen::Vector3d(0.05, -0.1, 0.3)); };
  ASSERT_TRUE(run<typename TypeParam::Deformer>(m, task, pull, 4));
  const auto reference = positions(m);

  for(double s : { 1., 1e3, 1e-3 })
  {
    const Eigen::Vector3d shift(10., -20., 5.);
    auto similar = [&](const Eigen::Vector3d& p) { return Eigen::Vector3d(s * p + shift); };
    Surface_mesh moved = bumpy_plane();
    for(vertex_descriptor v : vertices(moved))
      moved.point(v) = to_point(similar(positions(bumpy_plane())[std::size_t(v)]));
    const auto r = run<typename TypeParam::Deformer>(moved, task,
        [&](const Eigen::Vector3d& p) { return similar(pull((p - shift) / s)); }, 4);
    ASSERT_TRUE(r) << r.message;
    std::vector<Eigen::Vector3d> expected;
    for(const auto& p : reference)
      expected.push_back(similar(p));
    // The principal frame of a cell whose two tangential rest eigenvalues coincide (regular
    // grids) is defined by round-off only, so that policy is invariant only to about 1e-6.
    const double bound =
        std::is_same<typename TypeParam::Transform, LD::Principal_scaled_rotation_transform>::value ? 1e-5 : 1e-9;
    EXPECT_LE(max_distance(positions(moved), expected, s * diagonal(m)), bound) << "scale " << s;
  }
}

TYPED_TEST_P(EveryCombination, HardConstraintsAreMetAndFailuresLeaveTheMeshUnchanged)
{
  Surface_mesh m = bumpy_plane();
  const Task task = patch_task(m);
  typename TypeParam::Deformer d(m);
  d.insert_roi_vertices(task.roi.begin(), task.roi.end());
  d.insert_control_vertices(task.controls.begin(), task.controls.end());
  d.translate(task.controls.begin(), task.controls.end(), Eigen::Vector3d(0, 0, 0.4));
  const auto r = d.deform(3, 0.);
  ASSERT_TRUE(r) << r.message;
  // Fixed_transform stops after the second iteration, whose change is exactly zero
  EXPECT_EQ(r.iterations, (std::is_same<typename TypeParam::Transform, LD::Fixed_transform>::value ? 2u : 3u));
  EXPECT_EQ(r.energies.size(), r.iterations);
  for(vertex_descriptor v : task.controls)
    EXPECT_LE(std::sqrt(CGAL::squared_distance(m.point(v), d.target_position(v))), 1e-10 * diagonal(m));

  // a NaN target: clear error, nothing written
  const auto before = positions(m);
  d.set_target_position(task.controls.front(), Point_3(std::nan(""), 0, 0));
  const auto failed = d.deform(1, 0.);
  EXPECT_EQ(failed.status, LD::NON_FINITE_INPUT);
  EXPECT_EQ(positions(m), before);
}

TYPED_TEST_P(EveryCombination, PureTranslationGivesBitwiseTheIdentityStart)
{
  for(int by_rotate_api = 0; by_rotate_api < 2; ++by_rotate_api)
  {
    Surface_mesh a = bumpy_plane(), b = bumpy_plane();
    const Task task = patch_task(a);
    const auto rest = positions(a);
    std::vector<Eigen::Vector3d> results[2];
    Surface_mesh* meshes[2] = { &a, &b };
    for(int k = 0; k < 2; ++k)
    {
      typename TypeParam::Deformer d(*meshes[k]);
      d.set_start(k == 0 ? LD::IDENTITY_START : LD::ROTATION_START);
      d.insert_roi_vertices(task.roi.begin(), task.roi.end());
      d.insert_control_vertices(task.controls.begin(), task.controls.end());
      if(by_rotate_api)
        d.translate(task.controls.begin(), task.controls.end(), Eigen::Vector3d(0.1, -0.05, 0.3));
      else   // targets set one by one: the start fits each group's rotation (none) to them
        for(vertex_descriptor v : task.controls)
          d.set_target_position(v, to_point(rest[std::size_t(v)] + Eigen::Vector3d(0.1, -0.05, 0.3)));
      ASSERT_TRUE(d.deform(3, 0.));
      results[k] = positions(*meshes[k]);
    }
    EXPECT_EQ(results[0], results[1]);
  }
}

// The type-erased path (Any_weights, Any_transform: one deformer type per representation) gives
// bitwise the static one, for every representation x weights x transform and both starts.
TYPED_TEST_P(EveryCombination, AnyPoliciesEqualTheStaticOnesBitwiseOnTheCactus)
{
  typedef typename TypeParam::Representation R;
  typedef LD::Mesh_deformer<Surface_mesh, R, LD::Any_weights, LD::Any_transform, CGAL::Default, CGAL::Default,
                            CGAL::Sequential_tag> Erased;
  Cactus c;
  ASSERT_TRUE(read_cactus(c)) << "the cactus task is missing from " << LAPLACIAN_DEFORMATION_DATA_DIR;
  for(LD::Deformation_start start : { LD::IDENTITY_START, LD::ROTATION_START })
  {
    Surface_mesh a = c.mesh, b = c.mesh;
    typename TypeParam::Deformer s(a);
    Erased e(b, LD::Any_weights(typename TypeParam::Weights()), LD::Any_transform(typename TypeParam::Transform()));
    ASSERT_TRUE(e.weight_policy().template holds<typename TypeParam::Weights>());
    ASSERT_TRUE(e.transform_policy().template holds<typename TypeParam::Transform>());
    const LD::Deformation_result rs = deform_cactus(s, a, c, start), re = deform_cactus(e, b, c, start);
    ASSERT_TRUE(rs) << rs.message;
    ASSERT_TRUE(re) << re.message;
    EXPECT_EQ(rs.energies, re.energies) << "start " << int(start);
    EXPECT_EQ(s.number_of_control_groups(), e.number_of_control_groups());
    std::size_t differing = 0;
    for(vertex_descriptor v : vertices(a))
      differing += a.point(v) != b.point(v);
    EXPECT_EQ(differing, 0u) << "start " << int(start);
    for(std::size_t a_index : s.row_nodes())
      ASSERT_EQ(s.node_transform(a_index), e.node_transform(a_index));
  }
  // laplacian_matrix() with an Any_weights: the same operator
  const Eigen::SparseMatrix<double> ls = LD::laplacian_matrix(c.mesh, R(), typename TypeParam::Weights()),
                                    le = LD::laplacian_matrix(c.mesh, R(), LD::Any_weights(typename TypeParam::Weights()));
  EXPECT_EQ(ls.nonZeros(), le.nonZeros());
  EXPECT_EQ(Eigen::MatrixXd(ls), Eigen::MatrixXd(le));
}

REGISTER_TYPED_TEST_SUITE_P(EveryCombination, NothingMovesWhenTargetsAreRest, TranslationAndUniformScaleInvariance,
                            HardConstraintsAreMetAndFailuresLeaveTheMeshUnchanged,
                            PureTranslationGivesBitwiseTheIdentityStart,
                            AnyPoliciesEqualTheStaticOnesBitwiseOnTheCactus);

// ---- Every rotation-fitting transform (all but Fixed) -----------------------------------------

template <class C>
class RotationBased : public ::testing::Test {};
TYPED_TEST_SUITE_P(RotationBased);

TYPED_TEST_P(RotationBased, RigidMotionIsAFixedPoint)
{
  const Eigen::Matrix3d g = some_rotation();
  const double defect = fixed_point_defect<typename TypeParam::Deformer>(
      [&](const Eigen::Vector3d& p) { return Eigen::Vector3d(g * p + Eigen::Vector3d(1, 2, 3)); });
  EXPECT_LE(defect, 1e-10);
}

TYPED_TEST_P(RotationBased, PropagatedStartGivesTheRigidMotionInOneSolve)
{
  // ROI = the whole closed mesh (no fixed vertex), two control patches moved by one rigid motion
  const Eigen::Matrix3d g = some_rotation();
  const Eigen::Vector3d t(1, 2, 3);
  Surface_mesh m = bumpy_sphere();
  const auto rest = positions(m);
  std::vector<vertex_descriptor> controls = controls_near(m, Eigen::Vector3d(0, 0, 1), 0.45);
  for(vertex_descriptor v : controls_near(m, Eigen::Vector3d(0, 0, -1), 0.45))
    controls.push_back(v);
  typename TypeParam::Deformer d(m);
  d.set_start(LD::ROTATION_START);
  d.insert_roi_vertices(vertices(m).begin(), vertices(m).end());
  d.insert_control_vertices(controls.begin(), controls.end());
  for(vertex_descriptor v : controls)
    d.set_target_position(v, to_point(g * rest[std::size_t(v)] + t));
  ASSERT_TRUE(d.preprocess());
  EXPECT_EQ(d.number_of_control_groups(), 2u);
  const auto r = d.deform(1, 0.);
  ASSERT_TRUE(r) << r.message;
  std::vector<Eigen::Vector3d> expected;
  for(const auto& p : rest)
    expected.push_back(g * p + t);
  EXPECT_LE(max_distance(positions(m), expected, diagonal(m)), 1e-10);

  // the identity start does not reach it in one solve
  Surface_mesh n = bumpy_sphere();
  typename TypeParam::Deformer e(n);
  e.set_start(LD::IDENTITY_START);
  e.insert_roi_vertices(vertices(n).begin(), vertices(n).end());
  e.insert_control_vertices(controls.begin(), controls.end());
  for(vertex_descriptor v : controls)
    e.set_target_position(v, to_point(g * rest[std::size_t(v)] + t));
  ASSERT_TRUE(e.deform(1, 0.));
  EXPECT_GT(max_distance(positions(n), expected, diagonal(n)), 1e-3);
}

REGISTER_TYPED_TEST_SUITE_P(RotationBased, RigidMotionIsAFixedPoint, PropagatedStartGivesTheRigidMotionInOneSolve);

} // namespace Mesh_deformer_test

#endif // CGAL_LAPLACIAN_DEFORMATION_TEST_MESH_DEFORMER_PATTERNS_H
