// Reading a deformation task in the Botsch08 format of CGAL's deform_mesh_for_botsch08_format
// example (for instance its cactus): a selection (.sel, one status per vertex: 0 fixed,
// 1 region of interest, 2 handle) and a 4x4 affine handle transformation (.def).
//   usage: botsch08_example MESH SEL DEF
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/Laplacian_deformation/Mesh_deformer.h>
#include <CGAL/Laplacian_deformation/IO/Botsch08.h>

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

typedef CGAL::Simple_cartesian<double>                 Kernel;
typedef Kernel::Point_3                                Point_3;
typedef CGAL::Surface_mesh<Point_3>                    Mesh;
typedef boost::graph_traits<Mesh>::vertex_descriptor   vertex_descriptor;
namespace LD = CGAL::Laplacian_deformation;

int main(int argc, char** argv)
{
  if(argc != 4)
  {
    std::cerr << "usage: " << argv[0] << " MESH SEL DEF" << std::endl;
    return EXIT_FAILURE;
  }
  Mesh mesh;
  if(!CGAL::IO::read_polygon_mesh(argv[1], mesh) || !CGAL::is_triangle_mesh(mesh))
  {
    std::cerr << "Cannot read a triangle mesh from " << argv[1] << std::endl;
    return EXIT_FAILURE;
  }

  // The readers explain what is wrong (with the line number for a selection) instead of guessing.
  std::vector<int> status;
  Eigen::Matrix4d transform;
  std::string error;
  std::ifstream sel(argv[2]), def(argv[3]);
  if(!LD::IO::read_botsch08_selection(sel, status, error, num_vertices(mesh)))
  {
    std::cerr << argv[2] << ": " << error << std::endl;
    return EXIT_FAILURE;
  }
  if(!LD::IO::read_botsch08_transform(def, transform, error))
  {
    std::cerr << argv[3] << ": " << error << std::endl;
    return EXIT_FAILURE;
  }

  // statuses are in the mesh's vertex order
  LD::Mesh_deformer<Mesh> deformer(mesh);
  std::vector<vertex_descriptor> handles;
  for(vertex_descriptor v : vertices(mesh))
  {
    if(status[v] == LD::IO::BOTSCH08_REGION_OF_INTEREST)
      deformer.insert_roi_vertex(v);
    else if(status[v] == LD::IO::BOTSCH08_HANDLE)
      handles.push_back(v);
  }
  deformer.insert_control_vertices(handles.begin(), handles.end());
  std::cout << deformer.roi_vertices().size() << " ROI vertices, " << handles.size() << " handles" << std::endl;

  // the targets: the transformation applied to the rest positions of the handles
  for(vertex_descriptor v : handles)
  {
    const Point_3& p = mesh.point(v);
    const Eigen::Vector4d q = transform * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.);
    deformer.set_target_position(v, Point_3(q.x(), q.y(), q.z()));
  }
  const LD::Deformation_result result = deformer.deform(4, 0.);
  if(!result)
  {
    std::cerr << "deform failed: " << result.message << std::endl;
    return EXIT_FAILURE;
  }
  std::cout << result.iterations << " iterations, energy " << result.energy << std::endl;

  // The writers produce files the readers (and CGAL's example) accept: here the task itself.
  std::ofstream sel_out("botsch08_task.sel"), def_out("botsch08_task.def");
  if(!LD::IO::write_botsch08_selection(sel_out, status) || !LD::IO::write_botsch08_transform(def_out, transform))
    return EXIT_FAILURE;
  return CGAL::IO::write_polygon_mesh("botsch08_deformed.off", mesh, CGAL::parameters::stream_precision(17))
             ? EXIT_SUCCESS : EXIT_FAILURE;
}
