// Archetypes: a representation (with its nodes), a weight policy, a transform policy and a vertex
// point map that provide only what the concepts document (doc/Laplacian_deformation/Concepts)
// and ReadWritePropertyMap require, with every other operation deleted (no copy of the policies
// or the nodes, no default construction of the representation, no comparison or hashing of
// nodes, ranges with nothing but begin/end/++/!=/*). That Mesh_deformer, deform_mesh() and
// laplacian_matrix() compile with them shows the package uses nothing else; the tests check
// that they compute what the equivalent package models compute.
#include "test_helpers.h"

#include <CGAL/Laplacian_deformation.h>

#include <Eigen/SVD>
#include <gtest/gtest.h>

#include <cstddef>
#include <vector>

namespace LD = CGAL::Laplacian_deformation;
using namespace Laplacian_deformation_test;

namespace archetype {

typedef Kernel::Point_3 Point_3;

// DeformationNodes::node_descriptor: default constructible and copyable, nothing more.
class Node
{
public:
  Node() = default;
  explicit Node(std::size_t id) : m_id(id) {}   // for the archetype's own use
  std::size_t id() const { return m_id; }        // for the archetype's own use
private:
  std::size_t m_id = 0;
};

// A range usable in a range-based for, and nothing else.
class Node_range
{
public:
  class iterator
  {
  public:
    explicit iterator(const std::size_t* p) : m_p(p) {}
    Node operator*() const { return Node(*m_p); }
    iterator& operator++() { ++m_p; return *this; }
    bool operator!=(const iterator& other) const { return m_p != other.m_p; }
  private:
    const std::size_t* m_p;
  };
  Node_range(const std::size_t* first, const std::size_t* last) : m_first(first), m_last(last) {}
  iterator begin() const { return iterator(m_first); }
  iterator end() const { return iterator(m_last); }
private:
  const std::size_t* m_first;
  const std::size_t* m_last;
};

// DeformationNodes::Node_graph: only its graph_traits' vertex_descriptor is documented.
struct Node_graph {};

// A model of DeformationNodes with the vertex-based cells (node i = vertex i, one-ring, corner
// triangles), stored in its own arrays.
template <class TriangleMesh, class VertexPointMap>
class Nodes
{
public:
  typedef archetype::Node node_descriptor;
  typedef typename boost::graph_traits<TriangleMesh>::vertex_descriptor vertex_descriptor;
  typedef archetype::Node_graph Node_graph;

  Nodes(const TriangleMesh& tm, VertexPointMap)
  {
    const auto vim = get(boost::vertex_index, tm);
    for(vertex_descriptor v : vertices(tm))
    {
      m_vertices.push_back(v);
      m_ids.push_back(m_ids.size());
    }
    m_start.push_back(0);
    for(vertex_descriptor v : m_vertices)
    {
      for(vertex_descriptor w : CGAL::vertices_around_target(v, tm))
        m_neighbors.push_back(get(vim, w));
      m_start.push_back(m_neighbors.size());
      std::vector<std::array<std::size_t, 2> > fan;
      for(auto h : CGAL::halfedges_around_target(v, tm))
        if(!is_border(h, tm))
          fan.push_back({{get(vim, target(next(h, tm), tm)), get(vim, source(h, tm))}});
      m_fans.push_back(fan);
    }
  }
  Nodes(const Nodes&) = delete;
  Nodes& operator=(const Nodes&) = delete;

  const Node_graph& graph() const { return m_graph; }
  std::size_t number_of_nodes() const { return m_vertices.size(); }
  Node_range nodes() const { return Node_range(m_ids.data(), m_ids.data() + m_ids.size()); }
  std::size_t index(node_descriptor a) const { return a.id(); }
  template <class F>
  void combination(node_descriptor a, F&& f) const { f(m_vertices[a.id()], 1.); }
  Node_range neighbors(node_descriptor a) const
  {
    return Node_range(m_neighbors.data() + m_start[a.id()], m_neighbors.data() + m_start[a.id() + 1]);
  }
  template <class F>
  void fan_triangles(node_descriptor a, F&& f) const
  {
    for(const std::array<std::size_t, 2>& t : m_fans[a.id()])
      f(Node(t[0]), Node(t[1]));
  }

private:
  Node_graph m_graph;
  std::vector<vertex_descriptor> m_vertices;
  std::vector<std::size_t> m_ids, m_start, m_neighbors;
  std::vector<std::vector<std::array<std::size_t, 2> > > m_fans;
};

// DeformationRepresentation: only the nested Nodes; never default-constructed, never copied.
struct Representation
{
  explicit Representation(int) {}
  Representation(const Representation&) = delete;
  Representation& operator=(const Representation&) = delete;
  template <class TriangleMesh, class VertexPointMap>
  using Nodes = archetype::Nodes<TriangleMesh, VertexPointMap>;
};

// DeformationWeightPolicy: default constructible, weights() const; uniform weights computed
// from number_of_neighbors() only.
struct Weights
{
  Weights() = default;
  Weights(const Weights&) = delete;
  Weights& operator=(const Weights&) = delete;
  template <class GeomTraits>
  void weights(const LD::Node_cell<GeomTraits>& cell, std::vector<double>& w) const
  {
    w.assign(cell.number_of_neighbors(), 1. / double(cell.number_of_neighbors()));
  }
};

// DeformationTransformPolicy: default constructible, transform() const; the closest rotation,
// from the documented members of Transform_cell.
struct Transform
{
  Transform() = default;
  Transform(const Transform&) = delete;
  Transform& operator=(const Transform&) = delete;
  Eigen::Matrix3d transform(const LD::Transform_cell& cell) const
  {
    Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
    for(std::size_t i = 0; i < cell.size(); ++i)
      s += cell.weight(i) * cell.current(i) * cell.rest(i).transpose();
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(s, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
    d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1 : 1;
    return svd.matrixU() * d * svd.matrixV().transpose();
  }
};

// ReadWritePropertyMap (not an lvalue map): get() and put() only.
struct Point_map
{
  typedef Surface_mesh::Vertex_index key_type;
  typedef Point_3 value_type;
  typedef Point_3 reference;
  typedef boost::read_write_property_map_tag category;

  explicit Point_map(Surface_mesh& m) : mesh(&m) {}
  friend Point_3 get(const Point_map& map, key_type v) { return map.mesh->point(v); }
  friend void put(const Point_map& map, key_type v, const Point_3& p) { map.mesh->point(v) = p; }

  Surface_mesh* mesh;
};

} // namespace archetype

namespace boost {
template <>
struct graph_traits<archetype::Node_graph>
{
  typedef archetype::Node vertex_descriptor;
};
} // namespace boost

namespace {

typedef Surface_mesh::Vertex_index vertex_descriptor;

struct Task
{
  std::vector<vertex_descriptor> roi, controls;
  std::vector<Kernel::Point_3> targets;
};

// bumpy plane: border fixed, the centre lifted and turned
Task make_task(const Surface_mesh& m)
{
  Task t;
  for(vertex_descriptor v : vertices(m))
  {
    if(CGAL::is_border(v, m))
      continue;
    t.roi.push_back(v);
    const Kernel::Point_3& p = m.point(v);
    if(CGAL::square(p.x() - 0.5) + CGAL::square(p.y() - 0.5) < 0.02)
    {
      t.controls.push_back(v);
      t.targets.push_back(Kernel::Point_3(p.x() + 0.1 * (p.y() - 0.5), p.y() - 0.1 * (p.x() - 0.5), p.z() + 0.3));
    }
  }
  return t;
}

template <class Deformer, class PointMap>
LD::Deformation_result deform(Surface_mesh& m, PointMap vpm, const Task& t)
{
  Deformer d(m, vpm);
  d.insert_roi_vertices(t.roi.begin(), t.roi.end());
  d.insert_control_vertices(t.controls.begin(), t.controls.end());
  for(std::size_t k = 0; k < t.controls.size(); ++k)
    d.set_target_position(t.controls[k], t.targets[k]);
  return d.deform(4, 0.);
}

std::vector<Kernel::Point_3> points(const Surface_mesh& m) { return {m.points().begin(), m.points().end()}; }

Surface_mesh rest_mesh() { return to_mesh<Surface_mesh>(bumpy_plane_soup(10, 0.08)); }

typedef boost::property_map<Surface_mesh, CGAL::vertex_point_t>::type Internal_map;

} // namespace

TEST(Archetypes, MeshDeformerWithArchetypesMatchesVertexBasedUniformRotation)
{
  Surface_mesh reference = rest_mesh(), m = rest_mesh();
  const Task task = make_task(reference);
  const auto expected = deform<LD::Mesh_deformer<Surface_mesh, LD::Vertex_based_representation, LD::Uniform_weights,
                                                 LD::Rotation_transform, CGAL::Default, Internal_map,
                                                 CGAL::Sequential_tag> >(reference, get(CGAL::vertex_point, reference), task);
  ASSERT_TRUE(expected) << expected.message;
  const auto r = deform<LD::Mesh_deformer<Surface_mesh, archetype::Representation, archetype::Weights,
                                          archetype::Transform, CGAL::Default, archetype::Point_map,
                                          CGAL::Parallel_if_available_tag> >(m, archetype::Point_map(m), task);
  ASSERT_TRUE(r) << r.message;
  EXPECT_TRUE(points_near(points(m), points(reference), 1e-12));
  EXPECT_FALSE(points_near(points(m), points(rest_mesh()), 1e-3));   // it did deform
}

TEST(Archetypes, EdgeBasedWithArchetypePoliciesAndPointMap)
{
  Surface_mesh reference = rest_mesh(), m = rest_mesh();
  const Task task = make_task(reference);
  ASSERT_TRUE((deform<LD::Mesh_deformer<Surface_mesh, LD::Edge_based_representation, LD::Uniform_weights,
                                        LD::Rotation_transform, CGAL::Default, Internal_map, CGAL::Sequential_tag> >(
      reference, get(CGAL::vertex_point, reference), task)));
  const auto r = deform<LD::Mesh_deformer<Surface_mesh, LD::Edge_based_representation, archetype::Weights,
                                          archetype::Transform, CGAL::Default, archetype::Point_map,
                                          CGAL::Sequential_tag> >(m, archetype::Point_map(m), task);
  ASSERT_TRUE(r) << r.message;
  EXPECT_TRUE(points_near(points(m), points(reference), 1e-12));
}

TEST(Archetypes, DeformMeshTakesNonCopyablePolicyInstances)
{
  Surface_mesh reference = rest_mesh(), m = rest_mesh();
  const Task task = make_task(reference);
  ASSERT_TRUE(LD::deform_mesh(reference, task.roi, task.controls, task.targets,
                              LD::parameters::representation(LD::Vertex_based_representation(),
                              LD::parameters::weight_policy(LD::Uniform_weights(),
                              LD::parameters::transform_policy(LD::Rotation_transform(),
                              LD::parameters::tolerance(0.))))));
  const archetype::Representation representation(0);
  const archetype::Weights weights;
  const archetype::Transform transform;
  const auto r = LD::deform_mesh(m, task.roi, task.controls, task.targets,
                                 LD::parameters::representation(representation,
                                 LD::parameters::weight_policy(weights,
                                 LD::parameters::transform_policy(transform,
                                 LD::parameters::tolerance(0., CGAL::parameters::vertex_point_map(archetype::Point_map(m)))))));
  ASSERT_TRUE(r) << r.message;
  EXPECT_TRUE(points_near(points(m), points(reference), 1e-12));
}

TEST(Archetypes, LaplacianMatrixWithArchetypes)
{
  const Surface_mesh m = rest_mesh();
  const Eigen::SparseMatrix<double> expected =
      LD::laplacian_matrix(m, LD::Vertex_based_representation(), LD::Uniform_weights());
  const Eigen::SparseMatrix<double> d = LD::laplacian_matrix(m, archetype::Representation(0), archetype::Weights());
  ASSERT_EQ(d.rows(), expected.rows());
  ASSERT_EQ(d.cols(), expected.cols());
  EXPECT_LE((Eigen::MatrixXd(d) - Eigen::MatrixXd(expected)).cwiseAbs().maxCoeff(), 1e-15);
}
