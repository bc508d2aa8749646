// Consumer of the installed package: deforms a small grid (border fixed, centre lifted) with the
// default policies (edge-based, cotangent, S*R1) and checks the result; exit status 0 on success.
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/generators.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/Laplacian_deformation/deform_mesh.h>
#ifdef INSTALL_CONSUMER_USES_CHOLMOD
#include <CGAL/Laplacian_deformation/Cholmod_solver_traits.h>
#endif

#include <cmath>
#include <iostream>
#include <vector>

typedef CGAL::Simple_cartesian<double>      Kernel;
typedef Kernel::Point_3                     Point_3;
typedef CGAL::Surface_mesh<Point_3>         Mesh;
typedef Mesh::Vertex_index                  Vertex;
namespace LD = CGAL::Laplacian_deformation;

int main()
{
  Mesh mesh;
  CGAL::make_grid(10, 10, mesh, true);         // 11 x 11 vertices on z = 0, x and y in [0, 10]
  std::vector<Vertex> roi, controls;
  std::vector<Point_3> targets;
  for(Vertex v : vertices(mesh))
  {
    if(CGAL::is_border(v, mesh))
      continue;
    roi.push_back(v);
    const Point_3& p = mesh.point(v);
    if(p.x() == 5 && p.y() == 5)
    {
      controls.push_back(v);
      targets.push_back(Point_3(5, 5, 3));
    }
  }
#ifdef INSTALL_CONSUMER_USES_CHOLMOD
  const auto np = CGAL::parameters::sparse_linear_solver(LD::Cholmod_solver_traits());
  const char* solver = "CHOLMOD";
#else
  const auto np = CGAL::parameters::default_values();
  const char* solver = "default";
#endif
  const LD::Deformation_result result = LD::deform_mesh(mesh, roi, controls, targets, np);
  if(!result)
  {
    std::cerr << "deform_mesh failed: " << result.message << std::endl;
    return 1;
  }
  // the handle is at its target, the border stays on z = 0, every free vertex rose below it
  int errors = 0;
  if(CGAL::squared_distance(mesh.point(controls.front()), targets.front()) > 1e-20)
    ++errors;
  for(Vertex v : vertices(mesh))
  {
    const double z = mesh.point(v).z();
    if(!std::isfinite(z) || (CGAL::is_border(v, mesh) ? z != 0 : !(z > 0 && z <= 3 + 1e-9)))
      ++errors;
  }
  std::cout << "install_consumer (" << solver << " solver): " << result.iterations << " iterations, "
            << errors << " errors" << std::endl;
  return errors == 0 ? 0 : 1;
}
