// Polygon meshes (faces of any degree): both representations, both weight policies, on a quad
// grid and on a planar mesh mixing triangles, quads and pentagons (test_helpers.h). The rules
// are those of the user manual's section "Polygon Meshes".
#include "test_helpers.h"

#include <CGAL/Laplacian_deformation.h>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace LD = CGAL::Laplacian_deformation;
using namespace Laplacian_deformation_test;

namespace {

typedef Kernel::Point_3 Point_3;
typedef boost::graph_traits<Surface_mesh>::vertex_descriptor vertex_descriptor;
typedef boost::property_map<Surface_mesh, CGAL::vertex_point_t>::const_type Const_point_map;

// interior points moved in x and y by at most `amount` (faces stay convex for amount < 0.25)
Soup perturbed(Soup s, double amount, unsigned seed)
{
  std::mt19937 generator(seed);
  std::uniform_real_distribution<double> offset(-amount, amount);
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for(const auto& p : s.points)
  {
    lo = (std::min)({lo, p[0], p[1]});
    hi = (std::max)({hi, p[0], p[1]});
  }
  for(auto& p : s.points)
    if(p[0] > lo && p[0] < hi && p[1] > lo && p[1] < hi)
    {
      p[0] += offset(generator);
      p[1] += offset(generator);
    }
  return s;
}

// the meshes of this file, with at least one face of degree 4 (and 5 for the mixed one)
std::vector<std::pair<std::string, Surface_mesh> > polygon_meshes()
{
  std::vector<std::pair<std::string, Surface_mesh> > m;
  m.emplace_back("quad grid", to_mesh<Surface_mesh>(quad_grid_soup(8, 7)));
  m.emplace_back("perturbed quad grid", to_mesh<Surface_mesh>(perturbed(quad_grid_soup(8, 7), 0.15, 1)));
  m.emplace_back("mixed tri/quad/pentagon", to_mesh<Surface_mesh>(mixed_polygon_soup(8, 7)));
  return m;
}

template <class Rep>
LD::internal::Laplacian_stencils stencils(const Surface_mesh& m, Rep rep)
{
  return LD::internal::weighted_stencils(m, rep, LD::Cotangent_weights(), get(CGAL::vertex_point, m),
                                         get(boost::vertex_index, m), Kernel());
}

// whether every vertex combined into node a is interior
template <class Rep>
std::vector<char> interior_nodes(const Surface_mesh& m, Rep)
{
  const typename Rep::template Nodes<Surface_mesh, Const_point_map> nodes(m, get(CGAL::vertex_point, m));
  std::vector<char> interior(nodes.number_of_nodes(), 1);
  for(auto a : nodes.nodes())
    nodes.combination(a, [&](vertex_descriptor v, double) {
      if(CGAL::is_border(v, m))
        interior[nodes.index(a)] = 0;
    });
  return interior;
}

// relative Laplacian |delta_a| / sum_b |w_ab| |x_a - x_b| of every interior node
template <class Rep, class Weights>
std::vector<double> interior_relative_laplacians(const Surface_mesh& m, Rep rep, Weights weights)
{
  const auto vpm = get(CGAL::vertex_point, m);
  const auto vim = get(boost::vertex_index, m);
  const LD::internal::Laplacian_stencils s = LD::internal::weighted_stencils(m, rep, weights, vpm, vim, Kernel());
  std::vector<Eigen::Vector3d> x;
  LD::internal::node_positions(s, LD::internal::vertex_positions(m, vpm, vim), x);
  const std::vector<char> interior = interior_nodes(m, rep);
  std::vector<double> r;
  for(std::size_t a = 0; a < s.number_of_nodes; ++a)
  {
    if(!interior[a])
      continue;
    Eigen::Vector3d delta = Eigen::Vector3d::Zero();
    double scale = 0;
    for(std::size_t k = s.neighbor_start[a]; k < s.neighbor_start[a + 1]; ++k)
    {
      delta += s.weight[k] * (x[a] - x[s.neighbor[k]]);
      scale += std::abs(s.weight[k]) * (x[a] - x[s.neighbor[k]]).norm();
    }
    r.push_back(delta.norm() / scale);
  }
  return r;
}

template <class Rep>
void expect_closed_fans(const Surface_mesh& m, Rep rep, const std::string& name)
{
  const LD::internal::Laplacian_stencils s = stencils(m, rep);
  const std::vector<char> interior = interior_nodes(m, rep);
  std::size_t checked = 0;
  for(std::size_t a = 0; a < s.number_of_nodes; ++a)
  {
    std::vector<int> count(s.degree(a), 0);
    for(std::size_t t = s.fan_start[a]; t < s.fan_start[a + 1]; ++t)
    {
      ASSERT_LT(s.fan[t][0], count.size());
      ASSERT_LT(s.fan[t][1], count.size());
      ++count[s.fan[t][0]];
      ++count[s.fan[t][1]];
    }
    for(std::size_t b = 0; b < count.size(); ++b)
    {
      if(interior[a])
        EXPECT_EQ(count[b], 2) << name << ": spoke " << b << " of interior node " << a;
      else
        EXPECT_TRUE(count[b] == 1 || count[b] == 2) << name << ": spoke " << b << " of node " << a;
    }
    if(interior[a])
    {
      EXPECT_EQ(s.fan_start[a + 1] - s.fan_start[a], s.degree(a)) << name << ": node " << a;
      ++checked;
    }
  }
  EXPECT_GT(checked, 10u) << name;
}

// ROI: every interior vertex; controls: the interior vertices nearest to the centre
struct Task
{
  std::vector<vertex_descriptor> roi, controls;
};

Task centre_task(const Surface_mesh& m)
{
  Task t;
  CGAL::Bbox_3 box;
  for(vertex_descriptor v : vertices(m))
    box += m.point(v).bbox();
  const Point_3 centre((box.xmin() + box.xmax()) / 2, (box.ymin() + box.ymax()) / 2, 0);
  for(vertex_descriptor v : vertices(m))
    if(!CGAL::is_border(v, m))
    {
      t.roi.push_back(v);
      if(CGAL::squared_distance(m.point(v), centre) < 2.3)
        t.controls.push_back(v);
    }
  return t;
}

template <class Rep, class Weights>
void check_deformations(const std::string& name)
{
  typedef LD::Mesh_deformer<Surface_mesh, Rep, Weights, LD::Scaled_rotation_transform, CGAL::Default,
                            CGAL::Default, CGAL::Sequential_tag> Deformer;
  for(auto& [mesh_name, rest_mesh] : polygon_meshes())
  {
    SCOPED_TRACE(name + " on the " + mesh_name);
    const Task task = centre_task(rest_mesh);
    ASSERT_GE(task.controls.size(), 2u);

    // targets at the rest positions: nothing moves
    {
      Surface_mesh m = rest_mesh;
      Deformer d(m);
      d.insert_roi_vertices(task.roi.begin(), task.roi.end());
      d.insert_control_vertices(task.controls.begin(), task.controls.end());
      const auto r = d.deform(4, 0.);
      ASSERT_TRUE(r) << r.message;
      for(vertex_descriptor v : vertices(m))
        EXPECT_LE(std::sqrt(CGAL::squared_distance(m.point(v), rest_mesh.point(v))), 1e-12);
    }

    // the centre lifted by 2: the controls reach their targets, the border stays, the ROI
    // follows smoothly (monotone in the distance to the centre along the lift), all finite
    Surface_mesh m = rest_mesh;
    Deformer d(m);
    d.insert_roi_vertices(task.roi.begin(), task.roi.end());
    d.insert_control_vertices(task.controls.begin(), task.controls.end());
    ASSERT_TRUE(d.preprocess()) << d.last_result().message;
    d.translate(task.controls.begin(), task.controls.end(), Kernel::Vector_3(0, 0, 2));
    const auto r = d.deform(4, 0.);
    ASSERT_TRUE(r) << r.message;
    EXPECT_EQ(r.iterations, 4u);
    for(vertex_descriptor v : task.controls)
      EXPECT_LE(std::sqrt(CGAL::squared_distance(m.point(v), d.target_position(v))), 1e-10);
    double lowest_free = HUGE_VAL;
    for(vertex_descriptor v : vertices(m))
    {
      const Point_3& p = m.point(v);
      ASSERT_TRUE(std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()));
      if(CGAL::is_border(v, m))
        EXPECT_EQ(p, rest_mesh.point(v));
      else if(!d.is_control_vertex(v))
        lowest_free = (std::min)(lowest_free, p.z());
    }
    // every free vertex is lifted, none above the handle
    EXPECT_GT(lowest_free, 0.);
    for(vertex_descriptor v : task.roi)
      EXPECT_LE(m.point(v).z(), 2. + 1e-9);
  }
}

} // namespace

TEST(PolygonMeshes, FansAreClosedOnPolygonFaces)
{
  for(const auto& [name, m] : polygon_meshes())
  {
    ASSERT_FALSE(CGAL::is_triangle_mesh(m)) << name;
    expect_closed_fans(m, LD::Vertex_based_representation(), name + ", vertex-based");
    expect_closed_fans(m, LD::Edge_based_representation(), name + ", edge-based");
  }
}

TEST(PolygonMeshes, MixedMeshHasTrianglesQuadsAndPentagons)
{
  const Surface_mesh m = to_mesh<Surface_mesh>(mixed_polygon_soup(8, 7));
  std::vector<int> count(6, 0);
  for(auto f : faces(m))
    ++count[std::min<std::size_t>(degree(f, m), 5)];
  EXPECT_GT(count[3], 0);
  EXPECT_GT(count[4], 0);
  EXPECT_GT(count[5], 0);
  EXPECT_TRUE(CGAL::is_valid_polygon_mesh(m));
}

TEST(PolygonMeshes, CotangentLinearPrecisionOnConvexPlanarPolygonMeshes)
{
  std::vector<std::pair<std::string, Surface_mesh> > meshes = polygon_meshes();
  for(unsigned seed : { 2u, 3u })
    meshes.emplace_back("perturbed quad grid, seed " + std::to_string(seed),
                        to_mesh<Surface_mesh>(perturbed(quad_grid_soup(8, 7), 0.2, seed)));
  meshes.emplace_back("perturbed mixed mesh", to_mesh<Surface_mesh>(perturbed(mixed_polygon_soup(8, 7), 0.1, 4)));
  for(const auto& [name, m] : meshes)
  {
    auto check = [&, &name = name, &m = m](auto rep, const char* rep_name) {
      const std::vector<double> r = interior_relative_laplacians(m, rep, LD::Cotangent_weights());
      ASSERT_GT(r.size(), 10u);
      EXPECT_LE(*std::max_element(r.begin(), r.end()), 1e-12) << rep_name << " on the " << name;
    };
    check(LD::Vertex_based_representation(), "vertex-based");
    check(LD::Edge_based_representation(), "edge-based");
  }
}

TEST(PolygonMeshes, UniformWeightsLackLinearPrecisionOnIrregularPolygonMeshes)
{
  for(const Soup& s : { perturbed(quad_grid_soup(8, 7), 0.15, 1), mixed_polygon_soup(8, 7) })
  {
    const Surface_mesh m = to_mesh<Surface_mesh>(s);
    for(int edge_based = 0; edge_based < 2; ++edge_based)
    {
      const std::vector<double> r = edge_based
          ? interior_relative_laplacians(m, LD::Edge_based_representation(), LD::Uniform_weights())
          : interior_relative_laplacians(m, LD::Vertex_based_representation(), LD::Uniform_weights());
      EXPECT_GT(*std::max_element(r.begin(), r.end()), 1e-3) << (edge_based ? "edge" : "vertex");
    }
  }
}

TEST(PolygonMeshes, EdgeBasedUniformDeforms)
{
  check_deformations<LD::Edge_based_representation, LD::Uniform_weights>("edge-based, uniform");
}
TEST(PolygonMeshes, EdgeBasedCotangentDeforms)
{
  check_deformations<LD::Edge_based_representation, LD::Cotangent_weights>("edge-based, cotangent");
}
TEST(PolygonMeshes, VertexBasedUniformDeforms)
{
  check_deformations<LD::Vertex_based_representation, LD::Uniform_weights>("vertex-based, uniform");
}
TEST(PolygonMeshes, VertexBasedCotangentDeforms)
{
  check_deformations<LD::Vertex_based_representation, LD::Cotangent_weights>("vertex-based, cotangent");
}

namespace {

// every 7th vertex a control, the whole mesh the ROI, all constraints moved by one rigid motion;
// starts at the rigidly moved mesh and iterates once: returns the largest distance to it
template <class Deformer>
double rigid_motion_defect(const Surface_mesh& rest)
{
  const Eigen::Matrix3d g = Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  auto move = [&](const Point_3& p) {
    const Eigen::Vector3d q = g * Eigen::Vector3d(p.x(), p.y(), p.z()) + Eigen::Vector3d(1, 2, 3);
    return Point_3(q.x(), q.y(), q.z());
  };
  Surface_mesh m = rest;
  Deformer d(m);
  for(vertex_descriptor v : vertices(m))
  {
    d.insert_roi_vertex(v);
    if(std::size_t(v) % 7 == 0)
      d.insert_control_vertex(v);
  }
  for(vertex_descriptor v : vertices(m))
    if(d.is_control_vertex(v))
      d.set_target_position(v, move(rest.point(v)));
  EXPECT_TRUE(d.preprocess()) << d.last_result().message;
  for(vertex_descriptor v : vertices(m))
    m.point(v) = move(rest.point(v));
  EXPECT_TRUE(d.start_from_current_positions());
  const auto r = d.deform(1, 0.);
  EXPECT_TRUE(r) << r.message;
  double defect = 0;
  for(vertex_descriptor v : vertices(m))
    defect = (std::max)(defect, std::sqrt(CGAL::squared_distance(m.point(v), move(rest.point(v)))));
  return defect;
}

} // namespace

TEST(PolygonMeshes, RigidMotionIsAFixedPointOnTheMixedMesh)
{
  const Surface_mesh rest = to_mesh<Surface_mesh>(mixed_polygon_soup(8, 7));
  typedef LD::Mesh_deformer<Surface_mesh, LD::Edge_based_representation, LD::Uniform_weights,
                            LD::Rotation_transform, CGAL::Default, CGAL::Default, CGAL::Sequential_tag> Edge_uniform;
  typedef LD::Mesh_deformer<Surface_mesh, LD::Vertex_based_representation, LD::Cotangent_weights,
                            LD::Rotation_transform, CGAL::Default, CGAL::Default, CGAL::Sequential_tag> Vertex_cotangent;
  EXPECT_LE(rigid_motion_defect<Edge_uniform>(rest), 1e-10);
  EXPECT_LE(rigid_motion_defect<Vertex_cotangent>(rest), 1e-10);
}
