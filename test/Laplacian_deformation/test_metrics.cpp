// Tests of metrics.h: zero on the identity, invariance under rigid motions, known values on
// hand-made cases (stretched triangle, folded hinge, uniform scale), ROI restriction.
#include "test_helpers.h"

#include <CGAL/Laplacian_deformation/metrics.h>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include <cmath>
#include <utility>
#include <vector>

namespace LD = CGAL::Laplacian_deformation;
using namespace Laplacian_deformation_test;

namespace {

typedef Kernel::Point_3 Point;
typedef boost::graph_traits<Surface_mesh>::vertex_descriptor vertex_descriptor;

template <class F>
Surface_mesh transformed(const Surface_mesh& rest, F f)
{
  Surface_mesh m = rest;
  for(vertex_descriptor v : vertices(m))
  {
    const Point& p = rest.point(v);
    const Eigen::Vector3d q = f(Eigen::Vector3d(p.x(), p.y(), p.z()));
    m.point(v) = Point(q.x(), q.y(), q.z());
  }
  return m;
}

std::vector<vertex_descriptor> all_vertices(const Surface_mesh& m)
{
  return std::vector<vertex_descriptor>(vertices(m).begin(), vertices(m).end());
}

LD::Deformation_quality quality(const Surface_mesh& rest, const Surface_mesh& deformed)
{
  return LD::deformation_quality(deformed, get(CGAL::vertex_point, rest), all_vertices(rest));
}

void expect_all_zero(const LD::Deformation_quality& q, double tolerance)
{
  EXPECT_NEAR(q.vertex_laplacian_error, 0., tolerance);
  EXPECT_NEAR(q.edge_laplacian_error, 0., tolerance);
  EXPECT_NEAR(q.mean_edge_length_distortion, 0., tolerance);
  EXPECT_NEAR(q.max_edge_length_distortion, 0., tolerance);
  EXPECT_NEAR(q.mean_dihedral_angle_change, 0., 1e3 * tolerance);
  EXPECT_NEAR(q.max_dihedral_angle_change, 0., 1e3 * tolerance);
  EXPECT_NEAR(q.mean_normal_deviation, 0., 1e3 * tolerance);
  EXPECT_NEAR(q.max_normal_deviation, 0., 1e3 * tolerance);
  EXPECT_NEAR(q.arap_energy, 0., tolerance);
}

Eigen::Vector3d rigid(const Eigen::Vector3d& p)
{
  const Eigen::Matrix3d r = Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, 2, -0.5).normalized()).toRotationMatrix();
  return r * p + Eigen::Vector3d(3, -2, 0.5);
}

} // namespace

TEST(Metrics, ZeroOnIdentity)
{
  const Surface_mesh rest = to_mesh<Surface_mesh>(bumpy_plane_soup(8));
  expect_all_zero(quality(rest, rest), 1e-12);
  std::vector<double> field(num_vertices(rest), -1.);
  LD::vertex_distortion_field(rest, get(CGAL::vertex_point, rest),
                              CGAL::make_property_map(field));
  for(double f : field)
    EXPECT_NEAR(f, 0., 1e-12);
}

TEST(Metrics, InvariantUnderRigidMotion)
{
  for(const Surface_mesh& rest : {to_mesh<Surface_mesh>(icosphere_soup(2)), to_mesh<Surface_mesh>(bumpy_plane_soup(8))})
  {
    const Surface_mesh moved = transformed(rest, rigid);
    expect_all_zero(quality(rest, moved), 1e-9);
    std::vector<double> field(num_vertices(rest), -1.);
    LD::vertex_distortion_field(moved, get(CGAL::vertex_point, rest), CGAL::make_property_map(field));
    for(double f : field)
      EXPECT_NEAR(f, 0., 1e-9);
  }
}

TEST(Metrics, UniformScaleKnownValues)
{
  // p' = 2 p: every edge doubles, angles stay, delta' = 2 delta (rest weights), so the relative
  // Laplacian error is |2 delta - delta| / |delta| = 1 and the one-ring error is 1 everywhere.
  const Surface_mesh rest = to_mesh<Surface_mesh>(icosphere_soup(2));
  const Surface_mesh scaled = transformed(rest, [](const Eigen::Vector3d& p) { return Eigen::Vector3d(2 * p); });
  const LD::Deformation_quality q = quality(rest, scaled);
  EXPECT_NEAR(q.mean_edge_length_distortion, 1., 1e-12);
  EXPECT_NEAR(q.max_edge_length_distortion, 1., 1e-12);
  EXPECT_NEAR(q.vertex_laplacian_error, 1., 1e-9);
  EXPECT_NEAR(q.edge_laplacian_error, 1., 1e-9);
  EXPECT_NEAR(q.max_dihedral_angle_change, 0., 1e-6);
  EXPECT_NEAR(q.max_normal_deviation, 0., 1e-6);
  EXPECT_NEAR(q.arap_energy, 1., 1e-9);   // sum w |2e - e|^2 / sum w |e|^2
  std::vector<double> field(num_vertices(rest), -1.);
  LD::vertex_distortion_field(scaled, get(CGAL::vertex_point, rest), CGAL::make_property_map(field));
  for(double f : field)
    EXPECT_NEAR(f, 1., 1e-9);
}

TEST(Metrics, StretchedTriangleEdgeLengths)
{
  Soup s;
  s.points = {{{0., 0., 0.}}, {{1., 0., 0.}}, {{0., 1., 0.}}};
  s.faces = {{0, 1, 2}};
  const Surface_mesh rest = to_mesh<Surface_mesh>(s);
  const Surface_mesh stretched = transformed(rest, [](const Eigen::Vector3d& p) {
    return Eigen::Vector3d(2 * p.x(), p.y(), p.z()); });
  const LD::Deformation_quality q = quality(rest, stretched);
  // edges 1 -> 2 (relative change 1), sqrt(2) -> sqrt(5), 1 -> 1 (0)
  const double diagonal = (std::sqrt(5.) - std::sqrt(2.)) / std::sqrt(2.);
  EXPECT_NEAR(q.max_edge_length_distortion, 1., 1e-12);
  EXPECT_NEAR(q.mean_edge_length_distortion, (1. + diagonal) / 3., 1e-12);
  EXPECT_EQ(q.max_dihedral_angle_change, 0.);    // no interior edge
  EXPECT_NEAR(q.max_normal_deviation, 0., 1e-9); // stays planar
  EXPECT_GT(q.arap_energy, 0.1);
}

TEST(Metrics, FoldedHingeDihedralAngle)
{
  // two triangles sharing the edge (0, 1) on the x axis; the second is folded by 90 degrees
  Soup s;
  s.points = {{{0., 0., 0.}}, {{1., 0., 0.}}, {{0.5, 1., 0.}}, {{0.5, -1., 0.}}};
  s.faces = {{0, 1, 2}, {1, 0, 3}};
  const Surface_mesh rest = to_mesh<Surface_mesh>(s);
  Surface_mesh folded = rest;
  folded.point(vertex_descriptor(3)) = Point(0.5, 0., -1.);
  const LD::Deformation_quality q = quality(rest, folded);
  EXPECT_NEAR(q.max_dihedral_angle_change, 90., 1e-9);
  EXPECT_NEAR(q.mean_dihedral_angle_change, 90., 1e-9);  // the only interior edge
  EXPECT_NEAR(q.max_edge_length_distortion, 0., 1e-12);  // a pure fold keeps the lengths
  EXPECT_GT(q.max_normal_deviation, 10.);
  // the same fold rigidly moved: same values
  const Surface_mesh folded_moved = transformed(folded, rigid);
  const LD::Deformation_quality r = quality(rest, folded_moved);
  EXPECT_NEAR(r.max_dihedral_angle_change, 90., 1e-9);
  EXPECT_NEAR(r.arap_energy, q.arap_energy, 1e-9);
  EXPECT_NEAR(r.max_normal_deviation, q.max_normal_deviation, 1e-9);
  EXPECT_NEAR(r.edge_laplacian_error, q.edge_laplacian_error, 1e-9);
}

TEST(Metrics, OnlyTheRegionOfInterestCounts)
{
  // a 6 x 6 grid whose corner (6, 6) is lifted; the ROI is the opposite corner's vertex
  const Surface_mesh rest = to_mesh<Surface_mesh>(grid_soup(6, 6));
  Surface_mesh lifted = rest;
  lifted.point(vertex_descriptor(48)) = Point(6., 6., 1.);
  const std::vector<vertex_descriptor> far_roi = {vertex_descriptor(0)};
  expect_all_zero(LD::deformation_quality(lifted, get(CGAL::vertex_point, rest), far_roi), 1e-12);
  const std::vector<vertex_descriptor> near_roi = {vertex_descriptor(48)};
  const LD::Deformation_quality q = LD::deformation_quality(lifted, get(CGAL::vertex_point, rest), near_roi);
  EXPECT_GT(q.max_edge_length_distortion, 0.1);
  EXPECT_GT(q.max_dihedral_angle_change, 1.);
  EXPECT_GT(q.vertex_laplacian_error, 0.);
  EXPECT_GT(q.edge_laplacian_error, 0.);
}

TEST(Metrics, ConstraintResidualRelativeToDiagonal)
{
  const Surface_mesh rest = to_mesh<Surface_mesh>(grid_soup(3, 4));  // bounding box 3 x 4: diagonal 5
  std::vector<std::pair<vertex_descriptor, Point> > controls;
  EXPECT_EQ(LD::constraint_residual(rest, get(CGAL::vertex_point, rest), controls), 0.);
  controls.emplace_back(vertex_descriptor(0), Point(0., 0., 0.5));
  controls.emplace_back(vertex_descriptor(1), Point(1., 0., 0.));
  EXPECT_NEAR(LD::constraint_residual(rest, get(CGAL::vertex_point, rest), controls), 0.1, 1e-12);
}
