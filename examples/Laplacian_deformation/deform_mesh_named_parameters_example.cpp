// deform_mesh(): a whole deformation in one call, the policies and knobs given as named
// parameters. Here: vertex-based nodes, the similarity transform, soft constraints, up to 10
// iterations with a tolerance; then the same task with the defaults (edge-based, S*R1, hard).
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/Laplacian_deformation/deform_mesh.h>
#include <CGAL/Laplacian_deformation/Vertex_based_representation.h>
#include <CGAL/Laplacian_deformation/Similarity_transform.h>
#include <CGAL/Laplacian_deformation/Uniform_weights.h>

#include <cstdlib>
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
  const std::string filename = argc > 1 ? argv[1] : "data/bumpy_plane.off";
  Mesh mesh;
  if(!CGAL::IO::read_polygon_mesh(filename, mesh) || !CGAL::is_triangle_mesh(mesh))
  {
    std::cerr << "Cannot read a triangle mesh from " << filename << std::endl;
    return EXIT_FAILURE;
  }

  // ROI: the interior; control: the vertex closest to the middle, lifted by 0.3
  std::vector<vertex_descriptor> roi;
  vertex_descriptor handle = *vertices(mesh).begin();
  const Point_3 middle(0.5, 0.5, 0);
  for(vertex_descriptor v : vertices(mesh))
  {
    if(!CGAL::is_border(v, mesh))
      roi.push_back(v);
    if(CGAL::squared_distance(mesh.point(v), middle) < CGAL::squared_distance(mesh.point(handle), middle))
      handle = v;
  }
  const std::vector<vertex_descriptor> controls = {handle};
  const std::vector<Point_3> targets = {mesh.point(handle) + Kernel::Vector_3(0, 0, 0.3)};

  // Package parameters (in LD::parameters) nest: each takes the rest of the pack as its last argument.
  Mesh soft = mesh;
  const LD::Deformation_result r1 = LD::deform_mesh(soft, roi, controls, targets,
      LD::parameters::representation(LD::Vertex_based_representation(),
      LD::parameters::weight_policy(LD::Uniform_weights(),
      LD::parameters::transform_policy(LD::Similarity_transform(),
      LD::parameters::soft_constraint_weight(10.,
      LD::parameters::tolerance(1e-6, CGAL::parameters::number_of_iterations(10)))))));
  if(!r1)
  {
    std::cerr << "deform_mesh failed: " << r1.message << std::endl;
    return EXIT_FAILURE;
  }
  std::cout << "vertex-based, uniform, similarity, soft: " << r1.iterations << " iterations, handle "
            << r1.max_constraint_residual << " away from its target" << std::endl;

  // The defaults: edge-based, cotangent weights, S*R1, hard constraints, 4 iterations.
  Mesh hard = mesh;
  const LD::Deformation_result r2 = LD::deform_mesh(hard, roi, controls, targets);
  if(!r2)
  {
    std::cerr << "deform_mesh failed: " << r2.message << std::endl;
    return EXIT_FAILURE;
  }
  std::cout << "defaults: " << r2.iterations << " iterations, handle at " << hard.point(handle) << std::endl;

  return CGAL::IO::write_polygon_mesh("named_parameters_soft.off", soft, CGAL::parameters::stream_precision(17)) &&
         CGAL::IO::write_polygon_mesh("named_parameters_default.off", hard, CGAL::parameters::stream_precision(17))
             ? EXIT_SUCCESS : EXIT_FAILURE;
}
