// Genericity: the same deformation task on every FaceGraph model and point map the package
// supports, with both representations, agrees with the Surface_mesh<Simple_cartesian<double>>
// result. Edge-based runs go through Mesh_deformer, vertex-based ones through deform_mesh(), so
// both entry points see every model.
#include "test_helpers.h"

#include <CGAL/Laplacian_deformation.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/boost/graph/Face_filtered_graph.h>

#ifdef LAPLACIAN_DEFORMATION_HAS_OPENMESH
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <CGAL/boost/graph/graph_traits_TriMesh_ArrayKernelT.h>
#endif

#include <boost/property_map/property_map.hpp>

#include <gtest/gtest.h>

#include <array>
#include <iostream>
#include <cmath>
#include <limits>
#include <memory>
#include <set>
#include <type_traits>
#include <vector>

namespace LD = CGAL::Laplacian_deformation;
using namespace Laplacian_deformation_test;

namespace {

typedef std::array<double, 3> Coordinates;

// The deformation task, by point index of `patch`: a bumpy patch whose border is fixed, whose
// centre is rotated and lifted. `host` is a larger bumpy plane that contains `patch` (for the
// Face_filtered_graph model); patch point i is host point host_index[i].
struct Problem
{
  Soup patch, host;
  std::vector<std::size_t> host_index, roi, controls;
  std::vector<Coordinates> targets;
};

const Problem& problem()
{
  static const Problem p = [] {
    const int n = 16, first = 3, last = 13;      // host: 16 x 16 cells, patch: cells [3, 13)^2
    Problem q;
    q.host = bumpy_plane_soup(n, 0.08);
    std::vector<long> patch_index(q.host.points.size(), -1);
    for(int j = first; j <= last; ++j)
      for(int i = first; i <= last; ++i)
      {
        const std::size_t h = std::size_t(j) * std::size_t(n + 1) + std::size_t(i);
        patch_index[h] = long(q.patch.points.size());
        q.host_index.push_back(h);
        q.patch.points.push_back(q.host.points[h]);
        if(i != first && i != last && j != first && j != last)
          q.roi.push_back(q.patch.points.size() - 1);
      }
    for(const auto& f : q.host.faces)
    {
      std::vector<std::size_t> g;
      for(std::size_t h : f)
        if(patch_index[h] >= 0)
          g.push_back(std::size_t(patch_index[h]));
      if(g.size() == f.size())
        q.patch.faces.push_back(g);
    }
    // controls near the centre: rotated by 0.5 rad about an oblique axis, lifted by 0.15
    const double c = std::cos(0.5), s = std::sin(0.5);
    for(std::size_t k : q.roi)
    {
      const Coordinates& p = q.patch.points[k];
      const double x = p[0] - 0.5, y = p[1] - 0.5, z = p[2];
      if(x * x + y * y > 0.012)
        continue;
      q.controls.push_back(k);
      q.targets.push_back({{0.5 + c * x - s * z, 0.5 + y, 0.15 + s * x + c * z}});   // about the y axis
    }
    return q;
  }();
  return p;
}

double patch_diagonal()
{
  Coordinates lo{{HUGE_VAL, HUGE_VAL, HUGE_VAL}}, hi{{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}};
  for(const Coordinates& p : problem().patch.points)
    for(int k = 0; k < 3; ++k)
    {
      lo[k] = (std::min)(lo[k], p[k]);
      hi[k] = (std::max)(hi[k], p[k]);
    }
  return std::sqrt(CGAL::square(hi[0] - lo[0]) + CGAL::square(hi[1] - lo[1]) + CGAL::square(hi[2] - lo[2]));
}

template <class Point>
Coordinates coordinates(const Point& p)
{
  return {{CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}};
}

template <class Point>
Point make_point(const Coordinates& c)
{
  typedef typename CGAL::Kernel_traits<Point>::Kernel::FT FT;
  return Point(FT(c[0]), FT(c[1]), FT(c[2]));
}

// ---------------------------------------------------------------------------------------------
// Models. Each one owns its mesh, names the vertex of every patch point (`by_index`), and gives
// the graph and the point map the deformer works on. `tolerance` bounds the distance to the
// reference, relative to the patch diagonal.

// A mesh type whose vertices, after conversion from the soup, come in the soup's order.
template <class Mesh>
struct Plain_model
{
  typedef Mesh Graph;
  typedef typename boost::property_map<Mesh, CGAL::vertex_point_t>::type Vertex_point_map;
  typedef typename boost::graph_traits<Mesh>::vertex_descriptor vertex_descriptor;
  static constexpr double tolerance = 1e-10;

  Plain_model() : mesh(to_mesh<Mesh>(problem().patch))
  {
    for(vertex_descriptor v : vertices(mesh))
      by_index.push_back(v);
  }
  Graph& graph() { return mesh; }
  Vertex_point_map point_map() { return get(CGAL::vertex_point, mesh); }
  ::testing::AssertionResult untouched_outside() const { return ::testing::AssertionSuccess(); }

  Mesh mesh;
  std::vector<vertex_descriptor> by_index;
};

typedef CGAL::Simple_cartesian<float> Float_kernel;
typedef CGAL::Exact_predicates_inexact_constructions_kernel Epick;

struct Surface_mesh_double : Plain_model<Surface_mesh> {};
struct Surface_mesh_epick : Plain_model<CGAL::Surface_mesh<Epick::Point_3> > {};
struct Polyhedron_with_ids : Plain_model<Polyhedron> {};
// without ids: every index map (vertices, edges) is a dynamic one
struct Polyhedron_without_ids : Plain_model<CGAL::Polyhedron_3<Kernel> > {};

// Points rounded to float on input and on output (the deformation itself runs in double, the
// weights in float). Measured distance to the reference: 5.0e-8 of the diagonal (edge-based) and
// 5.3e-8 (vertex-based), below one float epsilon (1.2e-7); the bound is 1e-6 (about 8 epsilons).
struct Surface_mesh_float : Plain_model<CGAL::Surface_mesh<Float_kernel::Point_3> >
{
  static constexpr double tolerance = 1e-6;
};

// The patch as a Face_filtered_graph of the larger host mesh: the same deformation, and the host
// vertices outside the patch untouched.
struct Filtered_patch
{
  typedef CGAL::Face_filtered_graph<Surface_mesh> Graph;
  typedef boost::property_map<Graph, CGAL::vertex_point_t>::type Vertex_point_map;
  typedef boost::graph_traits<Graph>::vertex_descriptor vertex_descriptor;
  static constexpr double tolerance = 1e-10;

  Filtered_patch() : host(to_mesh<Surface_mesh>(problem().host))
  {
    std::vector<Surface_mesh::Vertex_index> host_vertices(vertices(host).begin(), vertices(host).end());
    std::set<Surface_mesh::Vertex_index> in_patch;
    for(std::size_t h : problem().host_index)
    {
      by_index.push_back(host_vertices[h]);
      in_patch.insert(host_vertices[h]);
    }
    std::vector<Surface_mesh::Face_index> selected;
    for(Surface_mesh::Face_index f : faces(host))
    {
      bool inside = true;
      for(Surface_mesh::Vertex_index v : CGAL::vertices_around_face(halfedge(f, host), host))
        inside = inside && in_patch.count(v) > 0;
      if(inside)
        selected.push_back(f);
    }
    filtered.reset(new Graph(host, selected));
    host_rest.assign(host.points().begin(), host.points().end());
  }
  Graph& graph() { return *filtered; }
  Vertex_point_map point_map() { return get(CGAL::vertex_point, *filtered); }
  ::testing::AssertionResult untouched_outside() const
  {
    for(Surface_mesh::Vertex_index v : vertices(host))
      if(!filtered->is_in_cc(v) && !(host.point(v) == host_rest[std::size_t(v)]))
        return ::testing::AssertionFailure() << "host vertex " << std::size_t(v) << " outside the patch moved";
    return ::testing::AssertionSuccess();
  }

  Surface_mesh host;
  std::vector<Kernel::Point_3> host_rest;
  std::unique_ptr<Graph> filtered;
  std::vector<vertex_descriptor> by_index;
};

// Positions kept in a std::vector indexed by the vertex index; the mesh's own points hold
// other values (three times the rest positions) and must be neither read nor written.
struct Vector_point_map
{
  typedef Surface_mesh Graph;
  typedef boost::property_map<Surface_mesh, boost::vertex_index_t>::const_type Index_map;
  typedef boost::iterator_property_map<std::vector<Kernel::Point_3>::iterator, Index_map,
                                       Kernel::Point_3, Kernel::Point_3&> Vertex_point_map;
  typedef Surface_mesh::Vertex_index vertex_descriptor;
  static constexpr double tolerance = 1e-10;

  Vector_point_map() : mesh(to_mesh<Surface_mesh>(problem().patch))
  {
    for(vertex_descriptor v : vertices(mesh))
    {
      by_index.push_back(v);
      positions.push_back(mesh.point(v));
      mesh.point(v) = Kernel::Point_3(3 * mesh.point(v).x(), 3 * mesh.point(v).y(), 3 * mesh.point(v).z());
    }
    decoy = std::vector<Kernel::Point_3>(mesh.points().begin(), mesh.points().end());
  }
  Graph& graph() { return mesh; }
  Vertex_point_map point_map() { return Vertex_point_map(positions.begin(), get(boost::vertex_index, mesh)); }
  ::testing::AssertionResult untouched_outside() const
  {
    if(std::vector<Kernel::Point_3>(mesh.points().begin(), mesh.points().end()) != decoy)
      return ::testing::AssertionFailure() << "the mesh's own points were written";
    return ::testing::AssertionSuccess();
  }

  Surface_mesh mesh;
  std::vector<Kernel::Point_3> positions, decoy;
  std::vector<vertex_descriptor> by_index;
};

#ifdef LAPLACIAN_DEFORMATION_HAS_OPENMESH
struct Double_traits : public OpenMesh::DefaultTraits
{
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
typedef OpenMesh::TriMesh_ArrayKernelT<Double_traits> Open_mesh;

// OpenMesh's TriMesh (double points) through CGAL's graph traits. The mesh is built with
// OpenMesh's own API (exact doubles); CGAL 5.5's point map (OM_point_pmap) reads points as
// Epick points but writes them through float, so the result is the reference rounded to float:
// measured 8.3e-9 of the diagonal with both representations (coordinates below 1, whose float
// rounding is at most 3e-8); the bound is 1e-7.
struct Open_mesh_model
{
  typedef Open_mesh Graph;
  typedef boost::property_map<Open_mesh, CGAL::vertex_point_t>::type Vertex_point_map;
  typedef boost::graph_traits<Open_mesh>::vertex_descriptor vertex_descriptor;
  static constexpr double tolerance = 1e-7;

  Open_mesh_model()
  {
    std::vector<Open_mesh::VertexHandle> handles;
    for(const Coordinates& p : problem().patch.points)
      handles.push_back(mesh.add_vertex(Open_mesh::Point(p[0], p[1], p[2])));
    for(const auto& f : problem().patch.faces)
    {
      std::vector<Open_mesh::VertexHandle> face;
      for(std::size_t k : f)
        face.push_back(handles[k]);
      mesh.add_face(face);
    }
    for(vertex_descriptor v : vertices(mesh))
      by_index.push_back(v);
  }
  Graph& graph() { return mesh; }
  Vertex_point_map point_map() { return get(CGAL::vertex_point, mesh); }
  ::testing::AssertionResult untouched_outside() const { return ::testing::AssertionSuccess(); }

  Open_mesh mesh;
  std::vector<vertex_descriptor> by_index;
};
#endif

// ---------------------------------------------------------------------------------------------

template <class Model>
std::vector<Coordinates> current_positions(Model& m)
{
  std::vector<Coordinates> p;
  const auto vpm = m.point_map();
  for(const auto& v : m.by_index)
    p.push_back(coordinates(get(vpm, v)));
  return p;
}

template <class Model>
std::vector<typename Model::vertex_descriptor> vertices_of(const Model& m, const std::vector<std::size_t>& indices)
{
  std::vector<typename Model::vertex_descriptor> v;
  for(std::size_t k : indices)
    v.push_back(m.by_index[k]);
  return v;
}

template <class Model>
std::vector<typename boost::property_traits<typename Model::Vertex_point_map>::value_type> targets()
{
  std::vector<typename boost::property_traits<typename Model::Vertex_point_map>::value_type> t;
  for(const Coordinates& c : problem().targets)
    t.push_back(make_point<typename boost::property_traits<typename Model::Vertex_point_map>::value_type>(c));
  return t;
}

// edge-based, cotangent, S*R1, 4 iterations: through the class
template <class Model>
LD::Deformation_result deform_edge_based(Model& m)
{
  typedef LD::Mesh_deformer<typename Model::Graph, LD::Edge_based_representation, CGAL::Default, CGAL::Default,
                            CGAL::Default, typename Model::Vertex_point_map> Deformer;
  Deformer d(m.graph(), m.point_map());
  const auto roi = vertices_of(m, problem().roi), controls = vertices_of(m, problem().controls);
  const auto t = targets<Model>();
  d.insert_roi_vertices(roi.begin(), roi.end());
  d.insert_control_vertices(controls.begin(), controls.end());
  for(std::size_t k = 0; k < controls.size(); ++k)
    d.set_target_position(controls[k], t[k]);
  return d.deform(4, 0.);
}

// vertex-based, cotangent, S*R1, 4 iterations: through the function
template <class Model>
LD::Deformation_result deform_vertex_based(Model& m)
{
  return LD::deform_mesh(m.graph(), vertices_of(m, problem().roi), vertices_of(m, problem().controls),
                         targets<Model>(),
                         LD::parameters::representation(LD::Vertex_based_representation(),
                           LD::parameters::tolerance(0., CGAL::parameters::vertex_point_map(m.point_map())
                                                             .number_of_iterations(4u))));
}

// The reference: Surface_mesh<Simple_cartesian<double>>.
template <bool edge_based>
const std::vector<Coordinates>& reference()
{
  static const std::vector<Coordinates> r = [] {
    Surface_mesh_double m;
    const LD::Deformation_result result = edge_based ? deform_edge_based(m) : deform_vertex_based(m);
    EXPECT_TRUE(result) << result.message;
    return current_positions(m);
  }();
  return r;
}

template <class Model, bool edge_based>
void check_model()
{
  Model m;
  ASSERT_EQ(m.by_index.size(), problem().patch.points.size());
  ASSERT_EQ(std::size_t(num_vertices(m.graph())), problem().patch.points.size());
  // the vertices are in the soup's order, with its positions (up to float rounding)
  ASSERT_TRUE(points_near(current_positions(m), problem().patch.points, 1e-7));

  const LD::Deformation_result r = edge_based ? deform_edge_based(m) : deform_vertex_based(m);
  ASSERT_TRUE(r) << r.message;
  EXPECT_EQ(r.iterations, 4u);
  const double bound = Model::tolerance * patch_diagonal();
  const auto result = current_positions(m);
  const auto& expected = reference<edge_based>();
  double distance = 0;
  for(std::size_t i = 0; i < result.size(); ++i)
    distance = (std::max)(distance, internal::point_distance(result[i], expected[i]));
  std::cout << "  largest distance to the Surface_mesh<double> result: " << distance / patch_diagonal()
            << " of the diagonal (bound " << Model::tolerance << ")" << std::endl;
  EXPECT_TRUE(points_near(result, expected, bound));
  EXPECT_TRUE(m.untouched_outside());

  // the result is a real deformation: the controls reached their targets (to float rounding)
  const auto p = current_positions(m);
  for(std::size_t k = 0; k < problem().controls.size(); ++k)
    EXPECT_LE(internal::point_distance(p[problem().controls[k]], problem().targets[k]), 1e-6);
}

template <class Model>
class GenericModels : public ::testing::Test {};

typedef ::testing::Types<Surface_mesh_double, Surface_mesh_float, Surface_mesh_epick, Polyhedron_with_ids,
                         Polyhedron_without_ids, Filtered_patch, Vector_point_map
#ifdef LAPLACIAN_DEFORMATION_HAS_OPENMESH
                         , Open_mesh_model
#endif
                         > Models;
TYPED_TEST_SUITE(GenericModels, Models);

} // namespace

TYPED_TEST(GenericModels, EdgeBasedAgreesWithSurfaceMeshDouble) { check_model<TypeParam, true>(); }
TYPED_TEST(GenericModels, VertexBasedAgreesWithSurfaceMeshDouble) { check_model<TypeParam, false>(); }

// A vertex of another mesh of the same type is refused, and nothing is written into either mesh.
// Polyhedron_3's descriptors are handles: every vertex of the other polyhedron is foreign (with
// ids, the other's vertex 0 has id 0; without ids, the index map returns 0 for an unknown key:
// both used to be taken for this mesh's vertex 0, and deform() then wrote into the other mesh).
// Surface_mesh's and OpenMesh's descriptors are indices: a vertex of the other mesh is foreign
// when its index is beyond this mesh's vertices.
template <class Model>
class ForeignVertices : public ::testing::Test {};
typedef ::testing::Types<Surface_mesh_double, Polyhedron_with_ids, Polyhedron_without_ids
#ifdef LAPLACIAN_DEFORMATION_HAS_OPENMESH
                         , Open_mesh_model
#endif
                         > Foreign_vertex_models;
TYPED_TEST_SUITE(ForeignVertices, Foreign_vertex_models);

template <class Graph> struct Handle_descriptors : std::false_type {};
template <class Gt, class I, template <class, class, class> class HDS, class A>
struct Handle_descriptors<CGAL::Polyhedron_3<Gt, I, HDS, A> > : std::true_type {};

TYPED_TEST(ForeignVertices, AreRefused)
{
  typedef TypeParam Model;
  typedef typename Model::vertex_descriptor vertex_descriptor;
  typedef LD::Mesh_deformer<typename Model::Graph, LD::Edge_based_representation, CGAL::Default, CGAL::Default,
                            CGAL::Default, typename Model::Vertex_point_map> Deformer;
  Model mesh, other;
  std::vector<vertex_descriptor> foreign;
  if constexpr(Handle_descriptors<typename Model::Graph>::value)
    foreign = {other.by_index.front(), other.by_index[problem().roi.front()], other.by_index.back()};
  else
  {
    // an isolated vertex beyond the first mesh's vertices
    typedef typename boost::property_traits<typename Model::Vertex_point_map>::value_type Point;
    foreign.push_back(add_vertex(other.graph()));
    put(other.point_map(), foreign.back(), make_point<Point>({{0.5, 0.5, 1.}}));
  }
  const std::vector<Coordinates> mesh_before = current_positions(mesh), other_before = current_positions(other);
  const auto roi = vertices_of(mesh, problem().roi), controls = vertices_of(mesh, problem().controls);
  const auto t = targets<Model>();
  for(vertex_descriptor bad : foreign)
  {
    Deformer d(mesh.graph(), mesh.point_map());
    d.insert_roi_vertices(roi.begin(), roi.end());
    d.insert_control_vertices(controls.begin(), controls.end());
    for(std::size_t k = 0; k < controls.size(); ++k)
      d.set_target_position(controls[k], t[k]);
    EXPECT_FALSE(d.insert_roi_vertex(bad));
    EXPECT_FALSE(d.insert_control_vertex(bad));
    EXPECT_FALSE(d.is_roi_vertex(bad));
    EXPECT_FALSE(d.is_control_vertex(bad));
    EXPECT_FALSE(d.erase_roi_vertex(bad));
    d.set_target_position(bad, t[0]);                     // ignored
    const LD::Deformation_result r = d.deform(2, 0.);
    EXPECT_EQ(r.status, LD::INVALID_PARAMETER) << r.message;
    EXPECT_NE(r.message.find("not a vertex of the mesh"), std::string::npos) << r.message;
    EXPECT_EQ(current_positions(mesh), mesh_before);
    EXPECT_EQ(current_positions(other), other_before);
    // without the foreign vertex: a success that writes only into this mesh
    d.clear_roi_vertices();
    d.insert_roi_vertices(roi.begin(), roi.end());
    d.insert_control_vertices(controls.begin(), controls.end());
    EXPECT_TRUE(d.deform(1, 0.)) << d.last_result().message;
    EXPECT_EQ(current_positions(other), other_before);
    d.reset();
  }
}

TEST(GenericModels, TheTaskMovesTheMeshAndTheRepresentationsDiffer)
{
  const auto& e = reference<true>();
  const auto& v = reference<false>();
  double moved = 0, differ = 0;
  for(std::size_t i = 0; i < e.size(); ++i)
  {
    moved = (std::max)(moved, internal::point_distance(e[i], problem().patch.points[i]));
    differ = (std::max)(differ, internal::point_distance(e[i], v[i]));
  }
  EXPECT_GT(moved, 0.1);
  EXPECT_GT(differ, 1e-3 * patch_diagonal());
}

// Minimal meshes over the supported mesh types: an empty mesh, vertices without faces, a single
// triangle, a tetrahedron. Each call either succeeds with a right answer or fails with a status
// and leaves the mesh exactly as it was.
namespace {

template <class Graph>
class MinimalMeshes : public ::testing::Test {};
typedef ::testing::Types<Surface_mesh, CGAL::Surface_mesh<Float_kernel::Point_3>, Polyhedron,
                         CGAL::Polyhedron_3<Kernel> > Minimal_mesh_graphs;
TYPED_TEST_SUITE(MinimalMeshes, Minimal_mesh_graphs);

template <class Graph>
std::vector<Coordinates> graph_positions(const Graph& g)
{
  std::vector<Coordinates> p;
  for(auto v : vertices(g))
  {
    const auto& q = get(CGAL::vertex_point, g, v);
    p.push_back({{CGAL::to_double(q.x()), CGAL::to_double(q.y()), CGAL::to_double(q.z())}});
  }
  return p;
}

} // namespace

TYPED_TEST(MinimalMeshes, SucceedRightOrFailCleanly)
{
  typedef TypeParam Graph;
  typedef typename boost::graph_traits<Graph>::vertex_descriptor vertex_descriptor;
  typedef typename boost::property_traits<typename boost::property_map<Graph, CGAL::vertex_point_t>::type>::value_type Point;
  typedef LD::Mesh_deformer<Graph> Deformer;

  {   // empty mesh: nothing to deform
    Graph g;
    Deformer d(g);
    EXPECT_EQ(d.deform(1, 0.).status, LD::EMPTY_REGION_OF_INTEREST);
    EXPECT_EQ(num_vertices(g), 0u);
  }
  {   // three vertices without faces: no Laplacian row touches them
    Soup s;
    s.points = {{{0, 0, 0}}, {{1, 0, 0}}, {{0, 1, 0}}};
    Graph g = to_mesh<Graph>(s);
    if(num_vertices(g) == 0)            // polygon_soup_to_polygon_mesh drops unused points: add them
      for(const auto& p : s.points)
        put(CGAL::vertex_point, g, add_vertex(g), Point(p[0], p[1], p[2]));
    internal::set_ids(g);
    const auto before = graph_positions(g);
    Deformer d(g);
    std::vector<vertex_descriptor> all(vertices(g).begin(), vertices(g).end());
    d.insert_roi_vertices(all.begin(), all.end());
    d.insert_control_vertex(all.front());
    d.set_target_position(all.front(), Point(0, 0, 1));
    const LD::Deformation_result r = d.deform(2, 0.);
    EXPECT_FALSE(r) << "three isolated vertices cannot be deformed";
    EXPECT_FALSE(r.message.empty());
    EXPECT_EQ(graph_positions(g), before);
  }
  for(int closed = 0; closed < 2; ++closed)
  {   // a single triangle, a tetrahedron: ROI = every vertex; translating every control moves the
      // whole (unanchored but for the controls) mesh rigidly, or the call fails cleanly
    Soup s;
    s.points = {{{0, 0, 0}}, {{1, 0, 0}}, {{0, 1, 0}}, {{0.2, 0.3, 1}}};
    if(closed)
      s.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
    else
    {
      s.points.pop_back();
      s.faces = {{0, 1, 2}};
    }
    Graph g = to_mesh<Graph>(s);
    ASSERT_EQ(num_vertices(g), s.points.size());
    const auto before = graph_positions(g);
    Deformer d(g);
    std::vector<vertex_descriptor> all(vertices(g).begin(), vertices(g).end());
    d.insert_roi_vertices(all.begin(), all.end());
    d.insert_control_vertex(all[0]);
    d.insert_control_vertex(all[1]);
    d.translate(all.begin(), all.begin() + 2, Eigen::Vector3d(0.1, 0.2, 0.3));
    const LD::Deformation_result r = d.deform(3, 0.);
    const auto after = graph_positions(g);
    if(r)
      for(std::size_t i = 0; i < after.size(); ++i)
        for(int k = 0; k < 3; ++k)
          EXPECT_NEAR(after[i][std::size_t(k)], before[i][std::size_t(k)] + 0.1 * (k + 1), 1e-6)
              << (closed ? "tetrahedron" : "triangle") << " vertex " << i;
    else
    {
      EXPECT_FALSE(r.message.empty());
      EXPECT_EQ(after, before);
    }
    std::cout << "[measured] " << (closed ? "tetrahedron" : "single triangle") << ": "
              << (r ? std::string("success, moved rigidly") : "refused: " + r.message) << std::endl;
  }
}

// Every decade from 1e-300 to 1e300 on every mesh type: the scaled unit result (1e-9 relative; 1e-5
// for the float kernel, whose coordinates round to 24 bits) or a clean failure that writes nothing.
TYPED_TEST(MinimalMeshes, EveryScaleMatchesOrFailsCleanly)
{
  typedef TypeParam Graph;
  typedef typename boost::graph_traits<Graph>::vertex_descriptor vertex_descriptor;
  typedef typename boost::property_traits<typename boost::property_map<Graph, CGAL::vertex_point_t>::type>::value_type Point;
  const bool is_float = std::is_same<typename CGAL::Kernel_traits<Point>::Kernel::FT, float>::value;
  std::vector<Coordinates> unit;
  std::size_t succeeded = 0, refused = 0;
  double worst = 0;
  for(int e = 0; e <= 600; ++e)
  {
    const int decade = e == 0 ? 0 : e <= 300 ? e : 300 - e;          // 0 first: the unit result
    const double scale = std::pow(10., decade);
    Soup s = bumpy_plane_soup(6, 0.1);
    for(auto& p : s.points)
      for(double& c : p)
        c *= scale;
    Graph g = to_mesh<Graph>(s);
    const auto before = graph_positions(g);
    LD::Mesh_deformer<Graph> d(g);
    std::vector<vertex_descriptor> roi, controls;
    for(vertex_descriptor v : vertices(g))
      if(!CGAL::is_border(v, g))
      {
        roi.push_back(v);
        if(roi.size() == 12)
          controls.push_back(v);
      }
    d.insert_roi_vertices(roi.begin(), roi.end());
    d.insert_control_vertices(controls.begin(), controls.end());
    d.translate(controls.begin(), controls.end(), Eigen::Vector3d(0.1 * scale, 0, 0.2 * scale));
    const LD::Deformation_result r = d.deform(3, 0.);
    if(decade == 0)
    {
      ASSERT_TRUE(r) << r.message;
      unit = graph_positions(g);
      continue;
    }
    if(!r)
    {
      ++refused;
      EXPECT_FALSE(r.message.empty());
      EXPECT_EQ(graph_positions(g), before) << "scale 1e" << decade;
      continue;
    }
    ++succeeded;
    const auto after = graph_positions(g);
    // float coordinates below FLT_MIN are subnormal: the input itself is then no scaled copy of the
    // unit mesh (a few bits left), so only a finite result is required there
    if(is_float && scale * 1e-3 < double(std::numeric_limits<float>::min()))
    {
      for(const Coordinates& c : after)
        EXPECT_TRUE(std::isfinite(c[0]) && std::isfinite(c[1]) && std::isfinite(c[2])) << "scale 1e" << decade;
      continue;
    }
    double error = 0;
    for(std::size_t i = 0; i < after.size(); ++i)
      for(std::size_t k = 0; k < 3; ++k)
        error = (std::max)(error, std::abs(after[i][k] / scale - unit[i][k]));
    worst = (std::max)(worst, error);
    EXPECT_LE(error, is_float ? 1e-5 : 1e-9) << "scale 1e" << decade;
  }
  std::cout << "[measured] decades 1e-300..1e300 (cotangent, edge-based S*R1): " << succeeded << " succeed (largest "
            << "error " << worst << " of the unit size), " << refused << " refused cleanly" << std::endl;
  EXPECT_GT(succeeded, is_float ? 10u : 100u);
}
