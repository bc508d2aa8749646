// Vertex-based versus edge-based deformation: the same task (lift the middle of a bumpy plane
// whose border is fixed) with both representations, everything else equal (cotangent weights,
// S*R1, 4 iterations). The edge-based one evaluates the Laplacian coordinates at about three
// times as many points (one per edge) for the same unknowns (the vertex positions).
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/Laplacian_deformation/Mesh_deformer.h>
#include <CGAL/Laplacian_deformation/Vertex_based_representation.h>
#include <CGAL/Laplacian_deformation/Edge_based_representation.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>

typedef CGAL::Simple_cartesian<double>                 Kernel;
typedef Kernel::Point_3                                Point_3;
typedef CGAL::Surface_mesh<Point_3>                    Mesh;
typedef boost::graph_traits<Mesh>::vertex_descriptor   vertex_descriptor;
namespace LD = CGAL::Laplacian_deformation;

// mean relative change of the edge lengths
double mean_edge_length_change(const Mesh& rest, const Mesh& deformed)
{
  double sum = 0;
  for(auto e : edges(rest))
  {
    const vertex_descriptor a = source(e, rest), b = target(e, rest);
    const double l0 = std::sqrt(CGAL::squared_distance(rest.point(a), rest.point(b)));
    const double l1 = std::sqrt(CGAL::squared_distance(deformed.point(a), deformed.point(b)));
    sum += std::abs(l1 - l0) / l0;
  }
  return sum / double(num_edges(rest));
}

// Deforms a copy of `rest` with the representation `Representation`; the rest is the same code.
template <class Representation>
bool deform(const Mesh& rest, vertex_descriptor handle, const std::string& name)
{
  Mesh mesh = rest;
  LD::Mesh_deformer<Mesh, Representation> deformer(mesh);
  for(vertex_descriptor v : vertices(mesh))
    if(!CGAL::is_border(v, mesh))
      deformer.insert_roi_vertex(v);
  deformer.insert_control_vertex(handle);
  if(!deformer.preprocess())
  {
    std::cerr << name << ": " << deformer.last_result().message << std::endl;
    return false;
  }
  deformer.translate(handle, Kernel::Vector_3(0, 0, 0.3));
  const LD::Deformation_result result = deformer.deform(4, 0.);
  if(!result)
  {
    std::cerr << name << ": " << result.message << std::endl;
    return false;
  }
  std::cout << name << ": " << deformer.row_nodes().size() << " rows (nodes) for "
            << num_vertices(mesh) << " vertices, energy " << result.energy
            << ", mean edge-length change " << mean_edge_length_change(rest, mesh) << std::endl;
  return CGAL::IO::write_polygon_mesh(name + ".off", mesh, CGAL::parameters::stream_precision(17));
}

int main(int argc, char** argv)
{
  const std::string filename = argc > 1 ? argv[1] : "data/bumpy_plane.off";
  Mesh mesh;
  if(!CGAL::IO::read_polygon_mesh(filename, mesh) || !CGAL::is_triangle_mesh(mesh))
  {
    std::cerr << "Cannot read a triangle mesh from " << filename << std::endl;
    return EXIT_FAILURE;
  }
  // the handle: the vertex closest to the middle of the plane
  const Point_3 middle(0.5, 0.5, 0);
  vertex_descriptor handle = *vertices(mesh).begin();
  for(vertex_descriptor v : vertices(mesh))
    if(CGAL::squared_distance(mesh.point(v), middle) < CGAL::squared_distance(mesh.point(handle), middle))
      handle = v;

  if(!deform<LD::Vertex_based_representation>(mesh, handle, "vertex_based") ||
     !deform<LD::Edge_based_representation>(mesh, handle, "edge_based"))
    return EXIT_FAILURE;
  std::cout << "wrote vertex_based.off and edge_based.off" << std::endl;
  return EXIT_SUCCESS;
}
