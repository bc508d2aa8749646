// Basic edge-based Laplacian deformation: pull the middle of a bumpy plane upwards while its
// border stays fixed, with the package defaults (edge-based nodes, cotangent weights, S*R1).
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/Laplacian_deformation/Mesh_deformer.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>

#include <cstdlib>
#include <iostream>

typedef CGAL::Simple_cartesian<double>                          Kernel;
typedef Kernel::Point_3                                         Point_3;
typedef CGAL::Surface_mesh<Point_3>                             Mesh;
typedef boost::graph_traits<Mesh>::vertex_descriptor            vertex_descriptor;
typedef CGAL::Laplacian_deformation::Mesh_deformer<Mesh>        Mesh_deformer;

int main(int argc, char** argv)
{
  const std::string filename = argc > 1 ? argv[1] : "data/bumpy_plane.off";
  Mesh mesh;
  if(!CGAL::IO::read_polygon_mesh(filename, mesh) || is_empty(mesh))   // polygon faces are fine too
  {
    std::cerr << "Cannot read a mesh from " << filename << std::endl;
    return EXIT_FAILURE;
  }

  // The deformer keeps a reference to the mesh; the current positions are the rest positions.
  Mesh_deformer deformer(mesh);

  // Region of interest: every vertex not on the border (border vertices stay fixed).
  // Control vertex: the vertex closest to the centre of the bounding box.
  const CGAL::Bbox_3 box = CGAL::Polygon_mesh_processing::bbox(mesh);
  const Point_3 centre((box.xmin() + box.xmax()) / 2, (box.ymin() + box.ymax()) / 2, box.zmin());
  vertex_descriptor handle = *vertices(mesh).begin();
  for(vertex_descriptor v : vertices(mesh))
  {
    if(!CGAL::is_border(v, mesh))
      deformer.insert_roi_vertex(v);
    if(CGAL::squared_distance(mesh.point(v), centre) < CGAL::squared_distance(mesh.point(handle), centre))
      handle = v;
  }
  deformer.insert_control_vertex(handle);

  // preprocess() factors the system once; moving targets afterwards never refactors it.
  if(!deformer.preprocess())
  {
    std::cerr << "preprocess failed: " << deformer.last_result().message << std::endl;
    return EXIT_FAILURE;
  }

  // Lift the handle by a third of the plane's width and run the paper's 4 iterations.
  deformer.translate(handle, Kernel::Vector_3(0, 0, (box.xmax() - box.xmin()) / 3));
  const CGAL::Laplacian_deformation::Deformation_result result = deformer.deform(4, 0.);
  if(!result)
  {
    std::cerr << "deform failed: " << result.message << std::endl;
    return EXIT_FAILURE;
  }
  std::cout << "iterations: " << result.iterations << ", energy: " << result.energy
            << ", handle at " << mesh.point(handle) << std::endl;

  if(!CGAL::IO::write_polygon_mesh("basic_edge_based_deformed.off", mesh, CGAL::parameters::stream_precision(17)))
    return EXIT_FAILURE;
  std::cout << "wrote basic_edge_based_deformed.off" << std::endl;
  return EXIT_SUCCESS;
}
