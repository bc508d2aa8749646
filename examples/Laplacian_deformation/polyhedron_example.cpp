// Deforming a CGAL::Polyhedron_3: Mesh_deformer works on any FaceGraph with triangle faces.
// With Polyhedron_items_with_id_3 the vertex and edge indices are the items' ids, which must be
// initialised (set_halfedgeds_items_id) before the deformer is constructed.
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/Polyhedron_items_with_id_3.h>
#include <CGAL/boost/graph/graph_traits_Polyhedron_3.h>
#include <CGAL/boost/graph/properties_Polyhedron_3.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/Laplacian_deformation/Mesh_deformer.h>

#include <cstdlib>
#include <iostream>
#include <string>

typedef CGAL::Simple_cartesian<double>                                 Kernel;
typedef Kernel::Point_3                                                Point_3;
typedef CGAL::Polyhedron_3<Kernel, CGAL::Polyhedron_items_with_id_3>   Polyhedron;
typedef boost::graph_traits<Polyhedron>::vertex_descriptor             vertex_descriptor;
typedef CGAL::Laplacian_deformation::Mesh_deformer<Polyhedron>         Mesh_deformer;

int main(int argc, char** argv)
{
  const std::string filename = argc > 1 ? argv[1] : "data/bumpy_plane.off";
  Polyhedron polyhedron;
  if(!CGAL::IO::read_polygon_mesh(filename, polyhedron) || !CGAL::is_triangle_mesh(polyhedron))
  {
    std::cerr << "Cannot read a triangle mesh from " << filename << std::endl;
    return EXIT_FAILURE;
  }
  CGAL::set_halfedgeds_items_id(polyhedron);   // ids 0..n-1 for vertices, halfedges, faces

  Mesh_deformer deformer(polyhedron);
  vertex_descriptor handle = *vertices(polyhedron).begin();
  const Point_3 middle(0.5, 0.5, 0);
  for(vertex_descriptor v : vertices(polyhedron))
  {
    if(!CGAL::is_border(v, polyhedron))
      deformer.insert_roi_vertex(v);
    if(CGAL::squared_distance(v->point(), middle) < CGAL::squared_distance(handle->point(), middle))
      handle = v;
  }
  deformer.insert_control_vertex(handle);
  if(!deformer.preprocess())
  {
    std::cerr << "preprocess failed: " << deformer.last_result().message << std::endl;
    return EXIT_FAILURE;
  }
  // two poses from the same factorisation: lift, then push down (no refactoring in between)
  deformer.translate(handle, Kernel::Vector_3(0, 0, 0.3));
  if(!deformer.deform(4, 0.))
    return EXIT_FAILURE;
  std::cout << "lifted: handle at " << handle->point() << std::endl;
  deformer.translate(handle, Kernel::Vector_3(0, 0, -0.5));
  if(!deformer.deform(4, 0.))
    return EXIT_FAILURE;
  std::cout << "pushed down: handle at " << handle->point() << ", " << deformer.number_of_factorizations()
            << " factorisation" << std::endl;
  return CGAL::IO::write_polygon_mesh("polyhedron_deformed.off", polyhedron, CGAL::parameters::stream_precision(17))
             ? EXIT_SUCCESS : EXIT_FAILURE;
}
