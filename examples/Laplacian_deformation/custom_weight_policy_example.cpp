// A user-written weight policy: inverse-distance weights, normalised to sum to one, a model of
// the concept DeformationWeightPolicy. The policy is a template argument of Mesh_deformer; the
// representation, the transforms, the constraints and the solve are unchanged.
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/Laplacian_deformation/Mesh_deformer.h>
#include <CGAL/Laplacian_deformation/Node_cell.h>
#include <CGAL/Laplacian_deformation/laplacian_matrix.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

typedef CGAL::Simple_cartesian<double>                 Kernel;
typedef Kernel::Point_3                                Point_3;
typedef CGAL::Surface_mesh<Point_3>                    Mesh;
typedef boost::graph_traits<Mesh>::vertex_descriptor   vertex_descriptor;
namespace LD = CGAL::Laplacian_deformation;

// The policy sees one node's rest cell (its centre, its neighbours, its fan triangles) and
// fills one weight per neighbour. It is default-constructible (it could also have parameters as
// members: the deformer uses the instance it is given); the package calls it once per node when
// it builds the Laplacian operator.
struct Inverse_distance_weights
{
  template <class GeomTraits>
  void weights(const LD::Node_cell<GeomTraits>& cell, std::vector<double>& w) const
  {
    w.assign(cell.number_of_neighbors(), 0.);
    double sum = 0;
    for(std::size_t i = 0; i < w.size(); ++i)
      sum += w[i] = 1. / (std::sqrt(CGAL::to_double(CGAL::squared_distance(cell.center(), cell.neighbor(i)))) + 1e-12);
    for(double& x : w)
      x /= sum;
  }
};

// edge-based nodes (the default), the user's weights, the other policies by default
typedef LD::Mesh_deformer<Mesh, LD::Edge_based_representation, Inverse_distance_weights> Mesh_deformer;

int main(int argc, char** argv)
{
  const std::string filename = argc > 1 ? argv[1] : "data/bumpy_plane.off";
  Mesh mesh;
  if(!CGAL::IO::read_polygon_mesh(filename, mesh) || !CGAL::is_triangle_mesh(mesh))
  {
    std::cerr << "Cannot read a triangle mesh from " << filename << std::endl;
    return EXIT_FAILURE;
  }

  // The operator D with these weights: each row sums to zero (the weights sum to one per node).
  const auto d = LD::laplacian_matrix(mesh, LD::Edge_based_representation(), Inverse_distance_weights());
  const Eigen::VectorXd row_sums = d * Eigen::VectorXd::Ones(d.cols());
  const double largest_row_sum = row_sums.cwiseAbs().maxCoeff();
  std::cout << "D: " << d.rows() << " x " << d.cols() << ", largest |row sum| " << largest_row_sum << std::endl;

  Mesh_deformer deformer(mesh);
  vertex_descriptor handle = *vertices(mesh).begin();
  const Point_3 middle(0.5, 0.5, 0);
  for(vertex_descriptor v : vertices(mesh))
  {
    if(!CGAL::is_border(v, mesh))
      deformer.insert_roi_vertex(v);
    if(CGAL::squared_distance(mesh.point(v), middle) < CGAL::squared_distance(mesh.point(handle), middle))
      handle = v;
  }
  deformer.insert_control_vertex(handle);
  deformer.translate(handle, Kernel::Vector_3(0, 0, 0.3));
  const LD::Deformation_result result = deformer.deform(4, 0.);   // preprocesses on the first call
  if(!result)
  {
    std::cerr << "deform failed: " << result.message << std::endl;
    return EXIT_FAILURE;
  }
  std::cout << "inverse-distance weights: " << result.iterations << " iterations, energy " << result.energy
            << ", handle at " << mesh.point(handle) << std::endl;
  if(largest_row_sum > 1e-9)
    return EXIT_FAILURE;
  return CGAL::IO::write_polygon_mesh("custom_weights_deformed.off", mesh, CGAL::parameters::stream_precision(17))
             ? EXIT_SUCCESS : EXIT_FAILURE;
}
