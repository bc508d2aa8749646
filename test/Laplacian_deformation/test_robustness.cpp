// The bad-input catalogue (user manual, section "Bad input"): one test per class, named
// C<number>_<class>. Each checks the documented outcome (status and reason, or the reader's
// error), that no NaN or infinity is ever written, and that a failed call leaves every
// coordinate bitwise unchanged and the connectivity as it was.
#include "test_helpers.h"

#include <CGAL/Laplacian_deformation.h>
#include <CGAL/Laplacian_deformation/IO/Botsch08.h>
#include <CGAL/Laplacian_deformation/IO/read_triangle_mesh.h>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace LD = CGAL::Laplacian_deformation;
using namespace Laplacian_deformation_test;

namespace {

typedef Kernel::Point_3 Point_3;
typedef boost::graph_traits<Surface_mesh>::vertex_descriptor vertex_descriptor;
typedef boost::graph_traits<Surface_mesh>::face_descriptor face_descriptor;

template <class R, class W>
using Deformer = LD::Mesh_deformer<Surface_mesh, R, W, CGAL::Default, CGAL::Default, CGAL::Default, CGAL::Sequential_tag>;
typedef Deformer<LD::Edge_based_representation, LD::Cotangent_weights> Edge_cotangent;
typedef Deformer<LD::Edge_based_representation, LD::Uniform_weights> Edge_uniform;
typedef Deformer<LD::Vertex_based_representation, LD::Cotangent_weights> Vertex_cotangent;
typedef Deformer<LD::Vertex_based_representation, LD::Uniform_weights> Vertex_uniform;

// calls f(Deformer*) once per representation x weights combination (the pointer only carries the type)
template <class F>
void for_each_combination(F f)
{
  f(static_cast<Edge_cotangent*>(nullptr));
  f(static_cast<Edge_uniform*>(nullptr));
  f(static_cast<Vertex_cotangent*>(nullptr));
  f(static_cast<Vertex_uniform*>(nullptr));
}

const double nan_value = std::numeric_limits<double>::quiet_NaN();
const double inf_value = std::numeric_limits<double>::infinity();

// every coordinate as its bit pattern, and the connectivity as vertex indices per face
struct Snapshot
{
  std::vector<std::uint64_t> bits;
  std::vector<std::size_t> faces;
  std::size_t vertices = 0, edges = 0;
  explicit Snapshot(const Surface_mesh& m) : vertices(num_vertices(m)), edges(num_edges(m))
  {
    for(vertex_descriptor v : m.vertices())
      for(int c = 0; c < 3; ++c)
      {
        const double x = m.point(v)[c];
        std::uint64_t b;
        std::memcpy(&b, &x, sizeof b);
        bits.push_back(b);
      }
    for(face_descriptor f : m.faces())
    {
      for(vertex_descriptor v : CGAL::vertices_around_face(halfedge(f, m), m))
        faces.push_back(std::size_t(v));
      faces.push_back(std::size_t(-1));
    }
  }
  bool operator==(const Snapshot& o) const
  {
    return bits == o.bits && faces == o.faces && vertices == o.vertices && edges == o.edges;
  }
};

// the number of non-finite coordinates
std::size_t non_finite(const Surface_mesh& m)
{
  std::size_t n = 0;
  for(vertex_descriptor v : m.vertices())
    for(int c = 0; c < 3; ++c)
      n += !std::isfinite(m.point(v)[c]);
  return n;
}

// the documented failure: status, a reason containing `reason`, nothing written
::testing::AssertionResult failed_cleanly(const LD::Deformation_result& r, LD::Deformation_status status,
                                          const std::string& reason, const Snapshot& before, const Surface_mesh& m)
{
  if(r.status != status)
    return ::testing::AssertionFailure() << "status " << r.status << " instead of " << status << " ('" << r.message << "')";
  if(r.message.find(reason) == std::string::npos)
    return ::testing::AssertionFailure() << "reason '" << r.message << "' does not mention '" << reason << "'";
  if(!(Snapshot(m) == before))
    return ::testing::AssertionFailure() << "the mesh changed";
  return ::testing::AssertionSuccess();
}

// success with finite coordinates everywhere
::testing::AssertionResult succeeded_finite(const LD::Deformation_result& r, const Surface_mesh& m)
{
  if(!r)
    return ::testing::AssertionFailure() << "failed: " << r.message;
  if(non_finite(m) != 0)
    return ::testing::AssertionFailure() << non_finite(m) << " non-finite coordinates written";
  return ::testing::AssertionSuccess();
}

// a bumpy 8x8 patch: interior free, border fixed, centre vertex a control
struct Patch
{
  Surface_mesh mesh;
  std::vector<vertex_descriptor> roi;
  vertex_descriptor center;
  explicit Patch(double scale = 1.)
  {
    Soup s = bumpy_plane_soup(8, 0.1);
    for(auto& p : s.points)
      for(double& c : p)
        c *= scale;
    mesh = to_mesh<Surface_mesh>(s);
    for(vertex_descriptor v : mesh.vertices())
      if(!CGAL::is_border(v, mesh))
        roi.push_back(v);
    center = vertex_descriptor(4 * 9 + 4);
  }
  template <class D>
  void select(D& d) const
  {
    d.insert_roi_vertices(roi.begin(), roi.end());
    d.insert_control_vertex(center);
  }
};

Point_3 shifted(const Point_3& p, double dx, double dy, double dz) { return Point_3(p.x() + dx, p.y() + dy, p.z() + dz); }

std::string write_temp(const std::string& name, const std::string& text)
{
  const std::string path = ::testing::TempDir() + "laplacian_robustness_" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// ---------------------------------------------------------------------------------------------
// Meshes

TEST(BadInput, C01_NonTriangleFaces)
{
  // polygon faces are accepted by every combination (manual, "Polygon Meshes"): the quad grid's
  // centre is lifted, the result is finite and the handle on its target
  Surface_mesh m = to_mesh<Surface_mesh>(quad_grid_soup(4, 4));
  Vertex_cotangent d(m);
  for(vertex_descriptor v : vertices(m))
    if(!CGAL::is_border(v, m))
      d.insert_roi_vertex(v);
  d.insert_control_vertex(vertex_descriptor(12));
  d.set_target_position(vertex_descriptor(12), Point_3(2, 2, 1));
  ASSERT_TRUE(d.preprocess()) << d.last_result().message;
  ASSERT_TRUE(d.deform(3, 0)) << d.last_result().message;
  for(vertex_descriptor v : vertices(m))
    EXPECT_TRUE(std::isfinite(m.point(v).x()) && std::isfinite(m.point(v).y()) && std::isfinite(m.point(v).z()));
  EXPECT_EQ(m.point(vertex_descriptor(12)), Point_3(2, 2, 1));
}

TEST(BadInput, C02_NonManifoldVertex)
{
  // two fans (a bow tie) sharing vertex 0
  Surface_mesh m;
  const vertex_descriptor o = m.add_vertex(Point_3(0, 0, 0)), a = m.add_vertex(Point_3(1, 0, 0)),
                          b = m.add_vertex(Point_3(1, 1, 0)), c = m.add_vertex(Point_3(-1, 0, 0)),
                          e = m.add_vertex(Point_3(-1, -1, 0));
  ASSERT_NE(m.add_face(o, a, b), Surface_mesh::null_face());
  ASSERT_NE(m.add_face(o, c, e), Surface_mesh::null_face());
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    D d(m);
    d.insert_roi_vertex(o);
    d.insert_control_vertex(b);
    d.set_target_position(b, Point_3(1, 1, 1));
    const Snapshot before(m);
    EXPECT_TRUE(failed_cleanly(d.deform(2, 0), LD::INVALID_MESH, "non-manifold", before, m));
    // a failed check marks no vertex as checked: the next call refuses again
    EXPECT_TRUE(failed_cleanly(d.deform(2, 0), LD::INVALID_MESH, "non-manifold", before, m));
    EXPECT_FALSE(d.preprocess());
  });
}

// The manifold check covers the vertices the operator is built from (the ROI's neighbourhood), so
// that its cost is the region's: a non-manifold vertex far from the ROI does not stop a deformation;
// once the ROI reaches it, the same deformer refuses.
TEST(BadInput, C02_NonManifoldVertexOutsideTheRegion)
{
  Surface_mesh m = to_mesh<Surface_mesh>(grid_soup(8, 8));
  const vertex_descriptor corner(0);   // grid point (0, 0), on the border
  ASSERT_EQ(m.point(corner), Point_3(0, 0, 0));
  const vertex_descriptor p = m.add_vertex(Point_3(-1, -0.5, 0)), q = m.add_vertex(Point_3(-0.5, -1, 0));
  if(m.add_face(corner, p, q) == Surface_mesh::null_face())
  {
    ASSERT_NE(m.add_face(corner, q, p), Surface_mesh::null_face());
  }
  auto grid = [](int i, int j) { return vertex_descriptor(static_cast<Surface_mesh::size_type>(j * 9 + i)); };
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Surface_mesh copy = m;
    D d(copy);
    for(int j = 4; j < 8; ++j)
      for(int i = 4; i < 8; ++i)
        d.insert_roi_vertex(grid(i, j));
    d.insert_control_vertex(grid(6, 6));
    d.set_target_position(grid(6, 6), Point_3(6, 6, 0.5));
    ASSERT_TRUE(d.deform(2, 0)) << d.last_result().message;
    EXPECT_EQ(copy.point(grid(6, 6)), Point_3(6, 6, 0.5));
    // the ROI grows to the non-manifold corner: refused, the mesh as it was
    for(int j = 0; j < 3; ++j)
      for(int i = 0; i < 3; ++i)
        d.insert_roi_vertex(grid(i, j));
    const Snapshot before(copy);
    EXPECT_TRUE(failed_cleanly(d.deform(2, 0), LD::INVALID_MESH, "non-manifold", before, copy));
  });
}

TEST(BadInput, C03_NonManifoldEdge)
{
  // three triangles on edge (0, 1): not representable as a halfedge mesh; the reader refuses it
  const std::string path = write_temp("nonmanifold_edge.off",
      "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n");
  Surface_mesh m = to_mesh<Surface_mesh>(grid_soup(2, 2));
  const Snapshot before(m);
  std::string error;
  EXPECT_FALSE(LD::IO::read_triangle_mesh(path, m, error));
  EXPECT_NE(error.find("non-manifold"), std::string::npos) << error;
  EXPECT_TRUE(Snapshot(m) == before);
}

// The reader's check of a soup (oriented, manifold edges and vertices) gives CGAL's
// is_polygon_soup_a_polygon_mesh() answer on random soups: pieces of a grid with faces removed
// (boundaries, bowties), flipped (inconsistent orientations), added across the grid (non-manifold
// edges and vertices) or merged into quads, with shuffled vertex ids, faces and first corners.
TEST(BadInput, C03_SoupCheckAgreesWithCgal)
{
  std::mt19937_64 g(20261205);
  std::size_t accepted = 0, refused = 0;
  for(int trial = 0; trial < 20000; ++trial)
  {
    const std::size_t nx = 2 + g() % 4, ny = 2 + g() % 4, n = (nx + 1) * (ny + 1);
    std::vector<std::vector<std::size_t> > faces;
    for(std::size_t j = 0; j < ny; ++j)
      for(std::size_t i = 0; i < nx; ++i)
      {
        const std::size_t a = j * (nx + 1) + i, b = a + 1, c = a + nx + 2, d = a + nx + 1;
        if(g() % 5 == 0)
          faces.push_back({a, b, c, d});   // a quad
        else
        {
          faces.push_back({a, b, c});
          faces.push_back({a, c, d});
        }
      }
    const int kind = int(g() % 6);
    if(kind == 1 || kind == 5)   // remove faces: boundaries, sometimes a vertex with two fans
      for(int k = 0, m = 1 + int(g() % 4); k < m && faces.size() > 1; ++k)
        faces.erase(faces.begin() + std::ptrdiff_t(g() % faces.size()));
    if(kind == 2 || kind == 5)   // flip a face
    {
      std::vector<std::size_t>& f = faces[g() % faces.size()];
      std::reverse(f.begin(), f.end());
    }
    if(kind == 3 || kind == 5)   // add a triangle on three distinct vertices
    {
      std::vector<std::size_t> t;
      while(t.size() < 3)
      {
        const std::size_t v = g() % n;
        if(std::find(t.begin(), t.end(), v) == t.end())
          t.push_back(v);
      }
      faces.push_back(t);
    }
    if(kind == 4)   // two grids sharing one vertex (a bowtie) or glued along a copied face
    {
      const std::size_t size = faces.size();
      for(std::size_t k = 0; k < size; ++k)
      {
        std::vector<std::size_t> f = faces[k];
        for(std::size_t& v : f)
          v = v == 0 ? 0 : v + n;
        faces.push_back(f);
      }
    }
    // shuffled ids, faces and first corners
    const std::size_t points = kind == 4 ? 2 * n : n;
    std::vector<std::size_t> id(points);
    for(std::size_t v = 0; v < points; ++v)
      id[v] = v;
    std::shuffle(id.begin(), id.end(), g);
    for(auto& f : faces)
    {
      for(std::size_t& v : f)
        v = id[v];
      std::rotate(f.begin(), f.begin() + std::ptrdiff_t(g() % f.size()), f.end());
    }
    std::shuffle(faces.begin(), faces.end(), g);
    const bool cgal = CGAL::Polygon_mesh_processing::is_polygon_soup_a_polygon_mesh(faces);
    ASSERT_EQ(LD::IO::internal::is_oriented_manifold_soup(faces, points), cgal) << "trial " << trial << " kind " << kind;
    (cgal ? accepted : refused) += 1;
  }
  // both answers are common
  EXPECT_GT(accepted, 3000u);
  EXPECT_GT(refused, 3000u);
  std::cout << "soups: " << accepted << " oriented manifolds, " << refused << " not" << std::endl;
}

TEST(BadInput, C04_IsolatedVertices)
{
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Patch patch;
    const vertex_descriptor lonely = patch.mesh.add_vertex(Point_3(5, 5, 5));
    {
      // outside the ROI: ignored, never moved
      D d(patch.mesh);
      patch.select(d);
      d.set_target_position(patch.center, shifted(patch.mesh.point(patch.center), 0, 0, 0.2));
      EXPECT_TRUE(succeeded_finite(d.deform(3, 0), patch.mesh));
      EXPECT_EQ(patch.mesh.point(lonely), Point_3(5, 5, 5));
      d.reset();
    }
    {
      // free in the ROI: nothing anchors it
      D d(patch.mesh);
      patch.select(d);
      d.insert_roi_vertex(lonely);
      const Snapshot before(patch.mesh);
      const LD::Deformation_result r = d.deform(3, 0);
      EXPECT_TRUE(failed_cleanly(r, LD::UNANCHORED_REGION, "touches no fixed or control vertex", before, patch.mesh));
      EXPECT_EQ(r.unanchored_size, 1u);
    }
  });
}

TEST(BadInput, C05_ZeroAreaTriangle)
{
  // degenerate_soup: triangle (0, 1, 2) is flat (collinear points) around the free vertex 1
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Surface_mesh m = to_mesh<Surface_mesh>(degenerate_soup());
    D d(m);
    d.insert_roi_vertex(vertex_descriptor(1));
    d.insert_roi_vertex(vertex_descriptor(2));
    d.insert_control_vertex(vertex_descriptor(2));
    d.set_target_position(vertex_descriptor(2), Point_3(2, 0.1, 0.3));
    EXPECT_TRUE(succeeded_finite(d.deform(4, 0), m));
    EXPECT_EQ(m.point(vertex_descriptor(2)), Point_3(2, 0.1, 0.3));
  });
}

TEST(BadInput, C06_NeedleTriangle)
{
  // degenerate_soup: triangle (3, 2, 5) has an angle of 7e-8 rad at vertex 2; vertices 3 and 5 nearly coincide
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Surface_mesh m = to_mesh<Surface_mesh>(degenerate_soup());
    D d(m);
    for(int v : {2, 3, 5})
      d.insert_roi_vertex(vertex_descriptor(v));
    d.insert_control_vertex(vertex_descriptor(3));
    d.set_target_position(vertex_descriptor(3), Point_3(1, 1.2, 0.2));
    EXPECT_TRUE(succeeded_finite(d.deform(4, 0), m));
    EXPECT_LT(std::abs(m.point(vertex_descriptor(5)).z()), 10.);   // bounded, not blown up
  });
}

TEST(BadInput, C07_DuplicatePoints)
{
  // two vertices at the same position: a zero-length edge and two zero-area triangles
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Soup s = bumpy_plane_soup(8, 0.1);
    s.points[4 * 9 + 5] = s.points[4 * 9 + 4];
    Surface_mesh m = to_mesh<Surface_mesh>(s);
    Patch patch;
    D d(m);
    d.insert_roi_vertices(patch.roi.begin(), patch.roi.end());
    d.insert_control_vertex(vertex_descriptor(3 * 9 + 3));
    d.set_target_position(vertex_descriptor(3 * 9 + 3), shifted(m.point(vertex_descriptor(3 * 9 + 3)), 0, 0, 0.2));
    EXPECT_TRUE(succeeded_finite(d.deform(4, 0), m));
  });
}

TEST(BadInput, C08_NanCoordinate)
{
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Patch patch;
    patch.mesh.point(vertex_descriptor(0)) = Point_3(nan_value, 0, 0);      // a fixed vertex
    D d(patch.mesh);
    patch.select(d);
    const Snapshot before(patch.mesh);
    EXPECT_TRUE(failed_cleanly(d.deform(3, 0), LD::NON_FINITE_INPUT, "rest position", before, patch.mesh));
  });
}

TEST(BadInput, C09_InfCoordinate)
{
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Patch patch;
    patch.mesh.point(patch.roi.front()) = Point_3(0, -inf_value, 0);        // a free vertex
    D d(patch.mesh);
    patch.select(d);
    const Snapshot before(patch.mesh);
    EXPECT_FALSE(d.preprocess());
    EXPECT_TRUE(failed_cleanly(d.last_result(), LD::NON_FINITE_INPUT, "rest position", before, patch.mesh));
  });
}

TEST(BadInput, C10_NanTarget)
{
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Patch patch;
    D d(patch.mesh);
    patch.select(d);
    d.set_target_position(patch.center, Point_3(0.5, nan_value, 0));
    const Snapshot before(patch.mesh);
    EXPECT_TRUE(failed_cleanly(d.deform(3, 0), LD::NON_FINITE_INPUT, "target", before, patch.mesh));
    // soft constraints too
    d.set_soft_constraints(1.);
    EXPECT_TRUE(failed_cleanly(d.deform(3, 0), LD::NON_FINITE_INPUT, "target", before, patch.mesh));
  });
}

TEST(BadInput, C11_InfTarget)
{
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Patch patch;
    D d(patch.mesh);
    patch.select(d);
    d.set_target_position(patch.center, shifted(patch.mesh.point(patch.center), 0, 0, 0.1));
    ASSERT_TRUE(succeeded_finite(d.deform(2, 0), patch.mesh));
    // after a success: the deformed pose must survive a bad target
    d.translate(patch.center, Eigen::Vector3d(inf_value, 0, 0));
    const Snapshot before(patch.mesh);
    EXPECT_TRUE(failed_cleanly(d.deform(3, 0), LD::NON_FINITE_INPUT, "target", before, patch.mesh));
  });
}

// deforms the patch scaled by `scale` (target scaled too); returns the positions divided by `scale`
template <class D>
std::vector<Point_3> scaled_result(double scale, bool soft)
{
  Patch patch(scale);
  D d(patch.mesh);
  patch.select(d);
  const Point_3 p = patch.mesh.point(patch.center);
  d.set_target_position(patch.center, Point_3(p.x() + 0.1 * scale, p.y(), p.z() + 0.3 * scale));
  if(soft)
    d.set_soft_constraints(1.);
  const LD::Deformation_result r = d.deform(4, 0);
  EXPECT_TRUE(succeeded_finite(r, patch.mesh)) << "scale " << scale;
  std::vector<Point_3> q;
  for(vertex_descriptor v : patch.mesh.vertices())
    q.push_back(Point_3(patch.mesh.point(v).x() / scale, patch.mesh.point(v).y() / scale, patch.mesh.point(v).z() / scale));
  return q;
}

TEST(BadInput, C12_HugeCoordinates)
{
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    for(bool soft : {false, true})
    {
      const std::vector<Point_3> unit = scaled_result<D>(1., soft);
      EXPECT_TRUE(points_near(scaled_result<D>(1e30, soft), unit, 1e-9));
      EXPECT_TRUE(points_near(scaled_result<D>(3e30, soft), unit, 1e-9));
    }
  });
}

TEST(BadInput, C13_TinyCoordinates)
{
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    for(bool soft : {false, true})
    {
      const std::vector<Point_3> unit = scaled_result<D>(1., soft);
      EXPECT_TRUE(points_near(scaled_result<D>(1e-30, soft), unit, 1e-9));
      EXPECT_TRUE(points_near(scaled_result<D>(3e-30, soft), unit, 1e-9));
    }
  });
}

typedef LD::Mesh_deformer<Surface_mesh, LD::Edge_based_representation, LD::Uniform_weights, LD::Rotation_transform,
                          CGAL::Default, CGAL::Default, CGAL::Sequential_tag> Edge_uniform_rotation;
typedef LD::Mesh_deformer<Surface_mesh, LD::Vertex_based_representation, LD::Uniform_weights, LD::Rotation_transform,
                          CGAL::Default, CGAL::Default, CGAL::Sequential_tag> Vertex_uniform_rotation;

// the patch scaled by `scale`, its centre pulled by (0.1, 0, 0.3) * scale, deform(6, 1e-4)
struct Scaled_run
{
  LD::Deformation_result result;
  std::vector<Point_3> points;     // divided by the scale
  bool unchanged = false;          // the mesh is bitwise as before
};
template <class D>
Scaled_run scaled_run(double scale)
{
  Patch patch(scale);
  const Snapshot before(patch.mesh);
  D d(patch.mesh);
  patch.select(d);
  const Point_3 p = patch.mesh.point(patch.center);
  d.set_target_position(patch.center, Point_3(p.x() + 0.1 * scale, p.y(), p.z() + 0.3 * scale));
  Scaled_run run;
  run.result = d.deform(6, 1e-4);
  run.unchanged = Snapshot(patch.mesh) == before;
  for(vertex_descriptor v : patch.mesh.vertices())
    run.points.push_back(Point_3(patch.mesh.point(v).x() / scale, patch.mesh.point(v).y() / scale,
                                 patch.mesh.point(v).z() / scale));
  return run;
}

// Every decade from 1e-300 to 1e300: either the unit-scale result times the scale (same
// iterations, relative error below 1e-9 of the patch's diagonal) or a documented failure that
// writes nothing. Uniform weights must succeed at every scale (their operator does not depend on
// the scale); cotangent weights scale like 1/scale^2 and vanish (or overflow) far from 1, which
// must be reported as a zero or non-finite operator, never as a success. One test per deformer
// (601 deformations each), so that ctest runs them side by side.
template <class D>
void extreme_scales_sweep(bool uniform, const char* name)
{
  const Scaled_run unit = scaled_run<D>(1.);
  ASSERT_TRUE(unit.result) << unit.result.message;
  ASSERT_GE(unit.result.iterations, 2u);
  const double diagonal = std::sqrt(2.);
  double worst = 0;
  int lowest = 0, highest = 0, successes = 0;
  for(int e = -300; e <= 300; ++e)
  {
    const double scale = std::stod("1e" + std::to_string(e));
    const Scaled_run run = scaled_run<D>(scale);
    if(run.result)
    {
      EXPECT_EQ(run.result.iterations, unit.result.iterations) << name << " scale " << scale;
      double error = 0;
      for(std::size_t i = 0; i < run.points.size(); ++i)
        error = (std::max)(error, internal::point_distance(run.points[i], unit.points[i]) / diagonal);
      EXPECT_LE(error, 1e-9) << name << " scale " << scale;
      worst = (std::max)(worst, error);
      ++successes;
      lowest = (std::min)(lowest, e);
      highest = (std::max)(highest, e);
    }
    else
    {
      EXPECT_FALSE(uniform) << name << " scale " << scale << ": " << run.result.message;
      EXPECT_TRUE(run.unchanged) << name << " scale " << scale;
      const bool zero = run.result.status == LD::UNANCHORED_REGION &&
                        run.result.message.find("Laplacian operator is zero") != std::string::npos;
      const bool not_finite = run.result.status == LD::NON_FINITE_INPUT &&
                              run.result.message.find("Laplacian operator is not finite") != std::string::npos;
      const bool squares = run.result.status == LD::FACTORIZATION_FAILED &&
                           (run.result.message.find("normal matrix overflows") != std::string::npos ||
                            run.result.message.find("normal matrix underflows") != std::string::npos);
      EXPECT_TRUE(zero || not_finite || squares) << name << " scale " << scale << ": status " << run.result.status
                                      << " '" << run.result.message << "'";
    }
  }
  EXPECT_EQ(successes, highest - lowest + 1) << name << ": the successful scales are not one range";
  std::cout << name << ": success from 1e" << lowest << " to 1e" << highest << ", largest relative error "
            << worst << std::endl;
}

TEST(BadInput, C36_ExtremeScalesEdgeUniform)
{
  extreme_scales_sweep<Edge_uniform>(true, "edge, uniform, S*R1");
}
TEST(BadInput, C36_ExtremeScalesVertexUniform)
{
  extreme_scales_sweep<Vertex_uniform>(true, "vertex, uniform, S*R1");
}
TEST(BadInput, C36_ExtremeScalesEdgeUniformRotation)
{
  extreme_scales_sweep<Edge_uniform_rotation>(true, "edge, uniform, rotation");
}
TEST(BadInput, C36_ExtremeScalesVertexUniformRotation)
{
  extreme_scales_sweep<Vertex_uniform_rotation>(true, "vertex, uniform, rotation");
}
TEST(BadInput, C36_ExtremeScalesEdgeCotangent)
{
  extreme_scales_sweep<Edge_cotangent>(false, "edge, cotangent, S*R1");
}
TEST(BadInput, C36_ExtremeScalesVertexCotangent)
{
  extreme_scales_sweep<Vertex_cotangent>(false, "vertex, cotangent, S*R1");
}

// a transform policy whose fit is never finite
struct Nan_transform
{
  Eigen::Matrix3d transform(const LD::Transform_cell&) const { return Eigen::Matrix3d::Constant(nan_value); }
};

TEST(BadInput, C37_NonFiniteTransformFit)
{
  // a fit that is not finite fails the call (it used to be replaced by the identity silently)
  typedef LD::Mesh_deformer<Surface_mesh, LD::Vertex_based_representation, LD::Uniform_weights, Nan_transform,
                            CGAL::Default, CGAL::Default, CGAL::Sequential_tag> D;
  Patch patch;
  D d(patch.mesh);
  patch.select(d);
  d.set_target_position(patch.center, shifted(patch.mesh.point(patch.center), 0, 0, 0.2));
  ASSERT_TRUE(succeeded_finite(d.deform(1, 0), patch.mesh));    // the first iteration uses T = I
  const Snapshot before(patch.mesh);
  EXPECT_TRUE(failed_cleanly(d.deform(2, 0), LD::NON_FINITE_RESULT, "transform fit", before, patch.mesh));
}

// the faces with a vertex in `roi` whose normal turned by more than 90 degrees from `rest`
std::size_t folded_faces(const Surface_mesh& rest, const Surface_mesh& now, const std::vector<vertex_descriptor>& roi)
{
  std::size_t folded = 0;
  for(face_descriptor f : now.faces())
  {
    std::vector<vertex_descriptor> v;
    for(vertex_descriptor w : CGAL::vertices_around_face(halfedge(f, now), now))
      v.push_back(w);
    if(std::none_of(v.begin(), v.end(), [&](vertex_descriptor w) { return std::find(roi.begin(), roi.end(), w) != roi.end(); }))
      continue;
    auto normal = [&](const Surface_mesh& m) { return CGAL::cross_product(m.point(v[1]) - m.point(v[0]), m.point(v[2]) - m.point(v[0])); };
    folded += normal(rest) * normal(now) < 0;
  }
  return folded;
}

TEST(BadInput, C38_FoldedFaces)
{
  // the centre of the patch dragged far sideways, past its neighbours, with a one-ring region of
  // interest: the faces around it fold over; a success with a FOLDED_FACES warning that counts them
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Patch patch;
    const Surface_mesh rest = patch.mesh;
    D d(patch.mesh);
    std::vector<vertex_descriptor> roi{patch.center};
    for(vertex_descriptor w : CGAL::vertices_around_target(halfedge(patch.center, patch.mesh), patch.mesh))
      roi.push_back(w);
    d.insert_roi_vertices(roi.begin(), roi.end());
    d.insert_control_vertex(patch.center);
    ASSERT_TRUE(d.preprocess());
    EXPECT_TRUE(d.last_result().warnings.empty()) << d.last_result().warnings.front().message;
    d.set_target_position(patch.center, shifted(patch.mesh.point(patch.center), 0.4, 0.1, 0));
    const LD::Deformation_result r = d.deform(4, 0);
    EXPECT_TRUE(succeeded_finite(r, patch.mesh));
    const std::size_t expected = folded_faces(rest, patch.mesh, roi);
    EXPECT_GT(expected, 0u);
    ASSERT_NE(r.warning(LD::FOLDED_FACES), nullptr);
    EXPECT_EQ(r.warning(LD::FOLDED_FACES)->count, expected);
    EXPECT_NE(r.warning(LD::FOLDED_FACES)->message.find("turned by more than 90 degrees"), std::string::npos);
    EXPECT_EQ(r.warning(LD::NO_MOTION), nullptr);
    // a small motion folds nothing: no warning at all
    d.reset();
    d.set_target_position(patch.center, shifted(patch.mesh.point(patch.center), 0, 0, 0.02));
    const LD::Deformation_result small = d.deform(4, 0);
    EXPECT_TRUE(succeeded_finite(small, patch.mesh));
    EXPECT_TRUE(small.warnings.empty()) << small.warnings.front().message;
  });
}

TEST(BadInput, C39_HandleTouchesFixedVertices)
{
  // a control next to the fixed border: warned at preprocess() and by every deform(), still a success
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Patch patch;
    D d(patch.mesh);
    d.insert_roi_vertices(patch.roi.begin(), patch.roi.end());
    const vertex_descriptor near_border(1 * 9 + 1), inside(4 * 9 + 4);
    d.insert_control_vertex(near_border);
    d.insert_control_vertex(inside);
    ASSERT_TRUE(d.preprocess());
    ASSERT_NE(d.last_result().warning(LD::HANDLE_TOUCHES_FIXED), nullptr);
    EXPECT_EQ(d.last_result().warning(LD::HANDLE_TOUCHES_FIXED)->count, 1u);
    d.set_target_position(near_border, shifted(patch.mesh.point(near_border), 0, 0, 0.3));
    const LD::Deformation_result r = d.deform(3, 0);
    EXPECT_TRUE(succeeded_finite(r, patch.mesh));
    ASSERT_NE(r.warning(LD::HANDLE_TOUCHES_FIXED), nullptr);
    EXPECT_EQ(r.warning(LD::HANDLE_TOUCHES_FIXED)->count, 1u);
    EXPECT_NE(r.warning(LD::HANDLE_TOUCHES_FIXED)->message.find("adjacent to fixed vertices"), std::string::npos);
    // the default patch's centre control is two rings away from the border: no warning
    Patch other;
    D e(other.mesh);
    other.select(e);
    ASSERT_TRUE(e.preprocess());
    EXPECT_EQ(e.last_result().warning(LD::HANDLE_TOUCHES_FIXED), nullptr);
  });
}

TEST(BadInput, C40_NoMotion)
{
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Patch patch;
    const Snapshot rest(patch.mesh);
    {
      // targets left at their rest positions (a single handle rotated about itself is the same)
      D d(patch.mesh);
      patch.select(d);
      const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));
      const Point_3 c = patch.mesh.point(patch.center);
      d.rotate(patch.center, Eigen::Vector3d(c.x(), c.y(), c.z()), turn);
      const LD::Deformation_result r = d.deform(3, 0);
      EXPECT_TRUE(succeeded_finite(r, patch.mesh));
      ASSERT_NE(r.warning(LD::NO_MOTION), nullptr);
      EXPECT_EQ(r.warning(LD::NO_MOTION)->count, 1u);
      EXPECT_NE(r.warning(LD::NO_MOTION)->message.find("moves nothing"), std::string::npos);
      // a real motion: no such warning
      d.translate(patch.center, Eigen::Vector3d(0, 0, 0.05));
      EXPECT_EQ(d.deform(3, 0).warning(LD::NO_MOTION), nullptr);
      d.reset();
    }
    {
      // no control at all (the border holds the region): the solution is the rest shape
      D d(patch.mesh);
      d.insert_roi_vertices(patch.roi.begin(), patch.roi.end());
      const LD::Deformation_result r = d.deform(2, 0);
      EXPECT_TRUE(succeeded_finite(r, patch.mesh));
      ASSERT_NE(r.warning(LD::NO_MOTION), nullptr);
      EXPECT_EQ(r.warning(LD::NO_MOTION)->count, 0u);
    }
  });
}

TEST(BadInput, C41_ZeroLaplacianOperator)
{
  // every point on one line: each triangle is degenerate, every cotangent weight is zero and the
  // operator vanishes at the free vertices; the status says so (it used to blame a part of the
  // region that "touches no fixed or control vertex", which it does)
  auto check = [](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Soup s = grid_soup(6, 2);
    for(auto& p : s.points)
      p = {{p[0] + 0.37 * p[1], 0., 0.}};
    Surface_mesh m = to_mesh<Surface_mesh>(s);
    D d(m);
    for(vertex_descriptor v : m.vertices())
      if(!CGAL::is_border(v, m))
        d.insert_roi_vertex(v);
    d.insert_control_vertex(vertex_descriptor(7 + 3));
    d.set_target_position(vertex_descriptor(7 + 3), shifted(m.point(vertex_descriptor(7 + 3)), 0, 0, 1));
    const Snapshot before(m);
    EXPECT_TRUE(failed_cleanly(d.deform(2, 0), LD::UNANCHORED_REGION, "the Laplacian operator is zero at 4 free vertices",
                               before, m));
    EXPECT_NE(d.last_result().message.find("every weight of their cells vanishes"), std::string::npos);
  };
  check(static_cast<Edge_cotangent*>(nullptr));
  check(static_cast<Vertex_cotangent*>(nullptr));
}

TEST(BadInput, C14_SeveralComponents)
{
  // ROI and control on the first sphere only: the second one is not touched
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Surface_mesh m = to_mesh<Surface_mesh>(two_components_soup());
    const std::size_t half = num_vertices(m) / 2;
    D d(m);
    for(std::size_t i = 0; i < half; ++i)
      if(m.point(vertex_descriptor(i)).z() > -0.3)
        d.insert_roi_vertex(vertex_descriptor(i));
    d.insert_control_vertex(vertex_descriptor(0));
    d.set_target_position(vertex_descriptor(0), shifted(m.point(vertex_descriptor(0)), 0.2, 0.3, 0));
    Snapshot second(m);
    EXPECT_TRUE(succeeded_finite(d.deform(4, 0), m));
    const Snapshot after(m);
    EXPECT_TRUE(std::equal(after.bits.begin() + std::ptrdiff_t(3 * half), after.bits.end(),
                           second.bits.begin() + std::ptrdiff_t(3 * half)));
    EXPECT_EQ(m.point(vertex_descriptor(0)), d.target_position(vertex_descriptor(0)));
    // a whole component in the ROI without control: unanchored
    D whole(m);
    for(std::size_t i = half; i < num_vertices(m); ++i)
      whole.insert_roi_vertex(vertex_descriptor(i));
    const Snapshot before(m);
    const LD::Deformation_result r = whole.deform(2, 0);
    EXPECT_TRUE(failed_cleanly(r, LD::UNANCHORED_REGION, "touches no fixed or control vertex", before, m));
    EXPECT_EQ(r.unanchored_size, half);
  });
}

// ---------------------------------------------------------------------------------------------
// Selections

TEST(BadInput, C15_EmptyRegionOfInterest)
{
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Patch patch;
    D d(patch.mesh);
    const Snapshot before(patch.mesh);
    EXPECT_FALSE(d.preprocess());
    EXPECT_TRUE(failed_cleanly(d.last_result(), LD::EMPTY_REGION_OF_INTEREST, "empty", before, patch.mesh));
    // emptied after a success: fails, keeps the deformed pose
    patch.select(d);
    d.set_target_position(patch.center, shifted(patch.mesh.point(patch.center), 0, 0, 0.2));
    ASSERT_TRUE(succeeded_finite(d.deform(2, 0), patch.mesh));
    d.clear_roi_vertices();
    const Snapshot deformed(patch.mesh);
    EXPECT_TRUE(failed_cleanly(d.deform(2, 0), LD::EMPTY_REGION_OF_INTEREST, "empty", deformed, patch.mesh));
  });
}

TEST(BadInput, C16_ControlOutsideRegionOfInterest)
{
  // documented: insert_control_vertex() / deform_mesh() add the control to the ROI;
  // set_target_position() on a vertex that is not a control is ignored
  Patch patch;
  const vertex_descriptor outside(2 * 9 + 2);
  std::vector<vertex_descriptor> roi;
  for(vertex_descriptor v : patch.roi)
    if(v != outside)
      roi.push_back(v);
  const Point_3 target = shifted(patch.mesh.point(outside), 0, 0, 0.25);
  const LD::Deformation_result r = LD::deform_mesh(patch.mesh, roi, std::vector<vertex_descriptor>{outside},
                                                   std::vector<Point_3>{target});
  EXPECT_TRUE(succeeded_finite(r, patch.mesh));
  EXPECT_EQ(patch.mesh.point(outside), target);

  Patch other;
  Edge_cotangent d(other.mesh);
  other.select(d);
  const Point_3 rest = other.mesh.point(outside);
  d.erase_roi_vertex(outside);
  d.set_target_position(outside, Point_3(9, 9, 9));         // not a control: ignored
  EXPECT_FALSE(d.is_control_vertex(outside));
  EXPECT_TRUE(succeeded_finite(d.deform(2, 0), other.mesh));
  EXPECT_EQ(other.mesh.point(outside), rest);
}

TEST(BadInput, C17_DescriptorNotInMesh)
{
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Patch patch;
    const vertex_descriptor foreign(std::uint32_t(num_vertices(patch.mesh) + 10));
    for(vertex_descriptor bad : {foreign, Surface_mesh::null_vertex()})
    {
      D d(patch.mesh);
      patch.select(d);
      EXPECT_FALSE(d.insert_roi_vertex(bad));
      EXPECT_FALSE(d.insert_control_vertex(bad));
      EXPECT_FALSE(d.is_roi_vertex(bad));
      EXPECT_FALSE(d.is_control_vertex(bad));
      EXPECT_FALSE(d.erase_roi_vertex(bad));
      d.set_target_position(bad, Point_3(1, 1, 1));
      d.translate(bad, Eigen::Vector3d(1, 1, 1));
      const Snapshot before(patch.mesh);
      EXPECT_TRUE(failed_cleanly(d.deform(2, 0), LD::INVALID_PARAMETER, "not a vertex of the mesh", before, patch.mesh));
      d.clear_roi_vertices();                                // forgets it
      patch.select(d);
      EXPECT_TRUE(succeeded_finite(d.deform(1, 0), patch.mesh));
      d.reset();
    }
  });
  // deform_mesh: the same status
  Patch patch;
  const Snapshot before(patch.mesh);
  const vertex_descriptor foreign(std::uint32_t(num_vertices(patch.mesh) + 1));
  EXPECT_TRUE(failed_cleanly(LD::deform_mesh(patch.mesh, patch.roi, std::vector<vertex_descriptor>{foreign},
                                             std::vector<Point_3>{Point_3(0, 0, 1)}),
                             LD::INVALID_PARAMETER, "not a vertex of the mesh", before, patch.mesh));
}

TEST(BadInput, C18_RegionPartWithoutAnchor)
{
  // the whole closed sphere in the ROI, no control: nothing anchors it
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Surface_mesh m = to_mesh<Surface_mesh>(icosphere_soup(1));
    D d(m);
    d.insert_roi_vertices(m.vertices().begin(), m.vertices().end());
    const Snapshot before(m);
    const LD::Deformation_result r = d.deform(2, 0);
    EXPECT_TRUE(failed_cleanly(r, LD::UNANCHORED_REGION, "singular", before, m));
    EXPECT_EQ(r.unanchored_size, num_vertices(m));
    // one control anchors it
    d.insert_control_vertex(vertex_descriptor(0));
    EXPECT_TRUE(succeeded_finite(d.deform(2, 0), m));
  });
}

TEST(BadInput, C19_EveryVertexAControl)
{
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Patch patch;
    D d(patch.mesh);
    d.insert_control_vertices(patch.mesh.vertices().begin(), patch.mesh.vertices().end());
    std::vector<Point_3> targets;
    for(vertex_descriptor v : patch.mesh.vertices())
    {
      targets.push_back(shifted(patch.mesh.point(v), 0, 0, 0.01 * double(std::size_t(v) % 5)));
      d.set_target_position(v, targets.back());
    }
    EXPECT_TRUE(succeeded_finite(d.deform(3, 0), patch.mesh));
    std::vector<Point_3> now(patch.mesh.points().begin(), patch.mesh.points().end());
    EXPECT_TRUE(points_near(now, targets, 0.));            // hard: exactly at the targets
    d.set_soft_constraints(1.);                             // soft: every vertex pulled, finite
    EXPECT_TRUE(succeeded_finite(d.deform(3, 0), patch.mesh));
    now.assign(patch.mesh.points().begin(), patch.mesh.points().end());
    EXPECT_TRUE(points_near(now, targets, 0.1));
  });
}

TEST(BadInput, C20_TopologyChangedAfterPreprocess)
{
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Patch patch;
    D d(patch.mesh);
    patch.select(d);
    ASSERT_TRUE(d.preprocess());
    patch.mesh.add_vertex(Point_3(7, 7, 7));
    d.set_target_position(patch.center, shifted(patch.mesh.point(patch.center), 0, 0, 0.2));
    const Snapshot before(patch.mesh);
    EXPECT_TRUE(failed_cleanly(d.deform(2, 0), LD::TOPOLOGY_CHANGED, "topology changed", before, patch.mesh));
    EXPECT_FALSE(d.preprocess());
    EXPECT_TRUE(failed_cleanly(d.last_result(), LD::TOPOLOGY_CHANGED, "topology changed", before, patch.mesh));
  });
}

TEST(BadInput, C21_DeformBeforePreprocess)
{
  // documented: deform() preprocesses when needed; same result as preprocess() + deform()
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Patch a, b;
    D da(a.mesh), db(b.mesh);
    a.select(da);
    b.select(db);
    const Point_3 t = shifted(a.mesh.point(a.center), 0.05, 0, 0.2);
    da.set_target_position(a.center, t);
    db.set_target_position(b.center, t);
    ASSERT_TRUE(db.preprocess());
    EXPECT_TRUE(succeeded_finite(da.deform(3, 0), a.mesh));
    EXPECT_TRUE(succeeded_finite(db.deform(3, 0), b.mesh));
    EXPECT_TRUE(Snapshot(a.mesh) == Snapshot(b.mesh));
  });
}

// ---------------------------------------------------------------------------------------------
// Parameters

TEST(BadInput, C22_ZeroIterations)
{
  // documented: success, zero iterations, nothing written
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Patch patch;
    D d(patch.mesh);
    patch.select(d);
    d.set_target_position(patch.center, shifted(patch.mesh.point(patch.center), 0, 0, 0.2));
    const Snapshot before(patch.mesh);
    const LD::Deformation_result r = d.deform(0, 0);
    EXPECT_TRUE(r) << r.message;
    EXPECT_EQ(r.iterations, 0u);
    EXPECT_TRUE(Snapshot(patch.mesh) == before);
  });
}

TEST(BadInput, C23_NegativeOrNanTolerance)
{
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Patch patch;
    D d(patch.mesh);
    patch.select(d);
    d.set_target_position(patch.center, shifted(patch.mesh.point(patch.center), 0, 0, 0.2));
    const Snapshot before(patch.mesh);
    for(double tolerance : {-1e-4, -inf_value, inf_value, nan_value})
      EXPECT_TRUE(failed_cleanly(d.deform(3, tolerance), LD::INVALID_PARAMETER, "tolerance", before, patch.mesh));
    d.set_tolerance(-1);
    EXPECT_TRUE(failed_cleanly(d.deform(), LD::INVALID_PARAMETER, "tolerance", before, patch.mesh));
    d.set_tolerance(inf_value);
    EXPECT_TRUE(failed_cleanly(d.deform(), LD::INVALID_PARAMETER, "non-negative and finite", before, patch.mesh));
  });
}

TEST(BadInput, C24_BadSoftWeight)
{
  // zero, negative, NaN and infinite weights
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Patch patch;
    for(double weight : {0., -1., nan_value, inf_value})
    {
      D d(patch.mesh);
      patch.select(d);
      d.set_target_position(patch.center, shifted(patch.mesh.point(patch.center), 0, 0, 0.2));
      d.set_soft_constraints(weight);
      const Snapshot before(patch.mesh);
      EXPECT_FALSE(d.preprocess());
      EXPECT_TRUE(failed_cleanly(d.last_result(), LD::INVALID_PARAMETER, "soft constraint weight", before, patch.mesh));
      EXPECT_TRUE(failed_cleanly(d.deform(2, 0), LD::INVALID_PARAMETER, "soft constraint weight", before, patch.mesh));
      const LD::Deformation_result r = LD::deform_mesh(patch.mesh, patch.roi, std::vector<vertex_descriptor>{patch.center},
                                                       std::vector<Point_3>{Point_3(0.5, 0.5, 1)},
                                                       LD::parameters::soft_constraint_weight(weight));
      EXPECT_TRUE(failed_cleanly(r, LD::INVALID_PARAMETER, "soft constraint weight", before, patch.mesh));
    }
  });
}

TEST(BadInput, C25_HalfTurnHandleRotation)
{
  // the top ring of a tube rotated by 180 degrees about the tube's axis: the fits meet
  // rotations by pi (det = +1, ambiguous axis); the result is finite, the handle at its targets
  for_each_combination([&](auto* tag) {
    typedef std::remove_pointer_t<decltype(tag)> D;
    Surface_mesh m = to_mesh<Surface_mesh>(cylinder_soup(12, 8, 1., 4.));
    D d(m);
    std::vector<vertex_descriptor> top;
    for(vertex_descriptor v : m.vertices())
    {
      if(m.point(v).z() > 0.1)
        d.insert_roi_vertex(v);
      if(m.point(v).z() > 3.9)
        top.push_back(v);
    }
    d.insert_control_vertices(top.begin(), top.end());
    const Eigen::Quaterniond half_turn(Eigen::AngleAxisd(3.14159265358979323846, Eigen::Vector3d::UnitZ()));
    d.rotate(top.begin(), top.end(), Eigen::Vector3d(0, 0, 4), half_turn);
    const LD::Deformation_result r = d.deform(6, 0);
    EXPECT_TRUE(succeeded_finite(r, m));
    for(vertex_descriptor v : top)
      EXPECT_EQ(m.point(v), d.target_position(v));
    for(double e : r.energies)
      EXPECT_TRUE(std::isfinite(e));
    // a half turn about an axis through the handle (not the tube's): also finite
    d.reset();
    const Eigen::Quaterniond flip(Eigen::AngleAxisd(3.14159265358979323846, Eigen::Vector3d::UnitX()));
    d.rotate(top.begin(), top.end(), Eigen::Vector3d(0, 0, 4), flip);
    EXPECT_TRUE(succeeded_finite(d.deform(6, 0), m));
  });
}

TEST(BadInput, C26_TargetCountMismatch)
{
  Patch patch;
  const Snapshot before(patch.mesh);
  const std::vector<vertex_descriptor> controls{patch.center, vertex_descriptor(3 * 9 + 3)};
  for(std::size_t n : {0u, 1u, 3u})
  {
    const std::vector<Point_3> targets(n, Point_3(0.5, 0.5, 1));
    EXPECT_TRUE(failed_cleanly(LD::deform_mesh(patch.mesh, patch.roi, controls, targets), LD::INVALID_PARAMETER,
                               "one target per control", before, patch.mesh));
  }
}

// ---------------------------------------------------------------------------------------------
// Files: meshes

// reads `text` as a file named `name` into a non-empty mesh; expects a refusal mentioning
// `reason` and the mesh untouched
void expect_refused_mesh(const std::string& name, const std::string& text, const std::string& reason,
                         bool triangles_only = true)
{
  SCOPED_TRACE(name);
  const std::string path = write_temp(name, text);
  Surface_mesh m = to_mesh<Surface_mesh>(grid_soup(2, 2));
  const Snapshot before(m);
  std::string error;
  EXPECT_FALSE(LD::IO::read_triangle_mesh(path, m, error, triangles_only));
  EXPECT_NE(error.find(reason), std::string::npos) << error;
  EXPECT_TRUE(Snapshot(m) == before);
  std::remove(path.c_str());
}

const char* const tetra_off = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";

TEST(BadInput, C27_MalformedOrTruncatedOff)
{
  // the valid file reads
  {
    Surface_mesh m;
    std::string error;
    ASSERT_TRUE(LD::IO::read_triangle_mesh(write_temp("tetra.off", tetra_off), m, error)) << error;
    EXPECT_EQ(num_faces(m), 4u);
  }
  const std::string valid(tetra_off);
  expect_refused_mesh("missing.off", "", "");                                    // empty file
  expect_refused_mesh("header_only.off", "OFF\n", "");
  expect_refused_mesh("truncated_vertices.off", valid.substr(0, 24), "");
  expect_refused_mesh("truncated_faces.off", valid.substr(0, valid.size() - 8), "");
  expect_refused_mesh("garbage.off", "OFF\n4 4 0\n0 0 zero\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n", "");
  expect_refused_mesh("not_off.off", "this is not a mesh\n", "");
  expect_refused_mesh("index_range.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 9\n3 0 3 2\n", "");
  expect_refused_mesh("repeated.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1\n", "");
  expect_refused_mesh("no_face.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n", "no face");
  // the documented specific reasons
  Surface_mesh m;
  std::string error;
  EXPECT_FALSE(LD::IO::read_triangle_mesh(::testing::TempDir() + "no_such_file.off", m, error));
  EXPECT_NE(error.find("cannot open"), std::string::npos) << error;
  EXPECT_EQ(num_vertices(m), 0u);
}

TEST(BadInput, C28_NonFiniteCoordinatesInFile)
{
  expect_refused_mesh("nan.off", "OFF\n4 4 0\nnan 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n", "");
  expect_refused_mesh("inf.obj", "v inf 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n", "");
  expect_refused_mesh("overflow.off", "OFF\n4 4 0\n1e999 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n", "");
}

TEST(BadInput, C29_NonTriangleFacesInFile)
{
  const std::string quad = "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
  expect_refused_mesh("quad.off", quad, "only triangles");
  expect_refused_mesh("segment.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "", false);
  // accepted when polygons are allowed
  Surface_mesh m;
  std::string error;
  EXPECT_TRUE(LD::IO::read_triangle_mesh(write_temp("quad2.off", quad), m, error, false)) << error;
  EXPECT_EQ(num_faces(m), 1u);
}

TEST(BadInput, C30_NonManifoldOrInconsistentFile)
{
  expect_refused_mesh("bowtie.off", "OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n-1 0 0\n-1 -1 0\n3 0 1 2\n3 0 3 4\n", "non-manifold");
  expect_refused_mesh("flipped.off", "OFF\n4 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n3 0 3 2\n", "");
  expect_refused_mesh("inconsistent.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 3 2\n", "orient");
}

TEST(BadInput, C31_MalformedOrTruncatedPly)
{
  const std::string header = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                             "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
  {
    Surface_mesh m;
    std::string error;
    ASSERT_TRUE(LD::IO::read_triangle_mesh(write_temp("tetra.ply", header + body), m, error)) << error;
    EXPECT_EQ(num_faces(m), 4u);
  }
  expect_refused_mesh("truncated.ply", header + body.substr(0, 30), "");
  expect_refused_mesh("header_only.ply", header, "");
  expect_refused_mesh("no_magic.ply", header.substr(4) + body, "");
  expect_refused_mesh("bad_format.ply", "ply\nformat sideways 9.0\nend_header\n" + body, "");
  expect_refused_mesh("index_range.ply", header + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 7\n", "");
  expect_refused_mesh("binary_truncated.ply",
                      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n\x01\x02", "");
}

TEST(BadInput, C32_MalformedOrTruncatedObj)
{
  const std::string valid = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
  {
    Surface_mesh m;
    std::string error;
    ASSERT_TRUE(LD::IO::read_triangle_mesh(write_temp("tetra.obj", valid), m, error)) << error;
    EXPECT_EQ(num_faces(m), 4u);
  }
  expect_refused_mesh("index_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "");
  expect_refused_mesh("zero_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "");
  expect_refused_mesh("garbage.obj", "v 0 0 zero\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "");
  expect_refused_mesh("truncated.obj", valid.substr(0, 40), "");
  expect_refused_mesh("no_vertex.obj", "# nothing\n", "");
  expect_refused_mesh("unknown.stl2", valid, "unsupported file extension");
}

// ---------------------------------------------------------------------------------------------
// Files: Botsch08 selection and transformation

TEST(BadInput, C33_SelectionWithWrongCountOrTokens)
{
  const std::vector<int> previous{2, 1, 0};
  auto refused = [&](const std::string& text, std::size_t expected, const std::string& reason) {
    std::istringstream in(text);
    std::vector<int> status = previous;
    std::string error;
    EXPECT_FALSE(LD::IO::read_botsch08_selection(in, status, error, expected)) << text;
    EXPECT_NE(error.find(reason), std::string::npos) << error;
    EXPECT_EQ(status, previous);                        // nothing written
  };
  refused("0\n1\n2\n", 4, "3 statuses but the mesh has 4");
  refused("0\n1\n2\n2\n1\n", 4, "5 statuses");
  refused("", 4, "0 statuses");
  refused("0\n3\n1\n", 0, "line 2");
  refused("0\n1 1\n", 0, "line 2");
  refused("0\n-1\n", 0, "line 2");
  refused("# c\n0\nx\n", 0, "line 3");
  refused("0\n1.0\n", 0, "line 2");
  refused("0\n\x01\x02\n", 0, "line 2");
  std::istringstream ok("# comment\n0\n\n1\n2\n");
  std::vector<int> status;
  std::string error;
  EXPECT_TRUE(LD::IO::read_botsch08_selection(ok, status, error, 3)) << error;
  EXPECT_EQ(status, (std::vector<int>{0, 1, 2}));
}

TEST(BadInput, C34_TransformNotAffineFourByFour)
{
  const Eigen::Matrix4d previous = 2 * Eigen::Matrix4d::Identity();
  auto refused = [&](const std::string& text, const std::string& reason) {
    std::istringstream in(text);
    Eigen::Matrix4d m = previous;
    std::string error;
    EXPECT_FALSE(LD::IO::read_botsch08_transform(in, m, error)) << text;
    EXPECT_NE(error.find(reason), std::string::npos) << error;
    EXPECT_TRUE(m == previous);                         // nothing written
  };
  refused("1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0\n", "got 15");
  refused("1 0 0\n0 1 0\n0 0 1\n", "got 9");
  refused("", "got 0");
  refused("1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n5\n", "more than 16");
  refused("1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 1 1\n", "last row");
  refused("1 0 0 0\n0 one 0 0\n0 0 1 0\n0 0 0 1\n", "entry 6");
  refused("1 0 0 0\n0 1 0 0\n0 0 1x 0\n0 0 0 1\n", "entry 11");
}

TEST(BadInput, C35_TransformSingularOrNonFinite)
{
  auto refused = [&](const std::string& text, const std::string& reason) {
    std::istringstream in(text);
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    std::string error;
    EXPECT_FALSE(LD::IO::read_botsch08_transform(in, m, error)) << text;
    EXPECT_NE(error.find(reason), std::string::npos) << error;
    EXPECT_TRUE(m == Eigen::Matrix4d::Identity());
  };
  refused("1 0 0 0\n0 0 0 0\n0 0 1 0\n0 0 0 1\n", "singular");
  refused("0 0 0 5\n0 0 0 5\n0 0 0 5\n0 0 0 1\n", "singular");
  refused("1 2 3 0\n2 4 6 0\n0 0 1 0\n0 0 0 1\n", "singular");
  refused("1e-300 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n", "singular");
  refused("nan 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n", "not a finite number");
  refused("1 0 0 inf\n0 1 0 0\n0 0 1 0\n0 0 0 1\n", "not a finite number");
  refused("1 0 0 1e999\n0 1 0 0\n0 0 1 0\n0 0 0 1\n", "not a finite number");
  // a tiny but uniform scale is not singular (relative test)
  std::istringstream in("1e-200 0 0 0\n0 1e-200 0 0\n0 0 1e-200 0\n0 0 0 1\n");
  Eigen::Matrix4d m;
  std::string error;
  EXPECT_TRUE(LD::IO::read_botsch08_transform(in, m, error)) << error;
}

} // namespace
