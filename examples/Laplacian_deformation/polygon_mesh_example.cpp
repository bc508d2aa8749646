// Laplacian deformation of a quad mesh (no triangulation): lift the middle of a 12 x 12 quad grid
// whose border stays fixed, edge-based, once with uniform and once with cotangent weights
// (see the user manual's section "Polygon Meshes" for how cells and fans are built on polygons).
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/generators.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/Laplacian_deformation/deform_mesh.h>
#include <CGAL/Laplacian_deformation/Uniform_weights.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

typedef CGAL::Simple_cartesian<double>                          Kernel;
typedef Kernel::Point_3                                         Point_3;
typedef CGAL::Surface_mesh<Point_3>                             Mesh;
typedef boost::graph_traits<Mesh>::vertex_descriptor            vertex_descriptor;
namespace LD = CGAL::Laplacian_deformation;

template <class Weights>
bool lift(const Mesh& quads, const std::string& name)
{
  Mesh mesh = quads;
  std::vector<vertex_descriptor> roi, handles;
  std::vector<Point_3> targets;
  for(vertex_descriptor v : vertices(mesh))
  {
    if(CGAL::is_border(v, mesh))
      continue;                                   // the border stays fixed
    roi.push_back(v);
    const Point_3& p = mesh.point(v);
    if(CGAL::squared_distance(p, Point_3(6, 6, 0)) <= 1)
    {
      handles.push_back(v);                       // the centre and its four neighbours
      targets.push_back(p + Kernel::Vector_3(0, 0, 4));
    }
  }
  const LD::Deformation_result result = LD::deform_mesh(mesh, roi, handles, targets,
      LD::parameters::weight_policy(Weights(), LD::parameters::representation(LD::Edge_based_representation())));
  if(!result)
  {
    std::cerr << name << ": " << result.message << std::endl;
    return false;
  }
  std::cout << name << ": " << result.iterations << " iterations, point between centre and border at "
            << mesh.point(*std::find_if(vertices(mesh).begin(), vertices(mesh).end(), [&](vertex_descriptor v) {
                 return quads.point(v) == Point_3(6, 3, 0); }))
            << std::endl;
  return CGAL::IO::write_polygon_mesh("polygon_mesh_" + name + ".off", mesh, CGAL::parameters::stream_precision(17));
}

int main()
{
  Mesh quads;
  CGAL::make_grid(12, 12, quads);                 // 12 x 12 quads on z = 0, not triangulated
  std::cout << "triangle mesh: " << std::boolalpha << CGAL::is_triangle_mesh(quads) << std::endl;
  if(!lift<LD::Uniform_weights>(quads, "uniform") || !lift<LD::Cotangent_weights>(quads, "cotangent"))
    return EXIT_FAILURE;
  return EXIT_SUCCESS;
}
