// A region of interest found on the edge-midpoint graph: boost::breadth_first_search over
// Edge_midpoint_graph (whose vertices are the mesh edges, adjacent when they share a mesh vertex)
// gives the hop distance of every edge from a start edge. The ROI is the endpoints of the edges
// at most k hops away; the handle is the start edge (both endpoints), lifted and turned.
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/Laplacian_deformation/Mesh_deformer.h>
#include <CGAL/Laplacian_deformation/Edge_midpoint_graph.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>

#include <boost/graph/breadth_first_search.hpp>
#include <boost/graph/visitors.hpp>
#include <boost/property_map/property_map.hpp>

#include <Eigen/Geometry>

#include <cstdlib>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

typedef CGAL::Simple_cartesian<double>                 Kernel;
typedef Kernel::Point_3                                Point_3;
typedef CGAL::Surface_mesh<Point_3>                    Mesh;
typedef boost::graph_traits<Mesh>::vertex_descriptor   vertex_descriptor;
typedef boost::graph_traits<Mesh>::edge_descriptor     edge_descriptor;
namespace LD = CGAL::Laplacian_deformation;

int main(int argc, char** argv)
{
  const std::string filename = argc > 1 ? argv[1] : "data/bumpy_plane.off";
  const std::size_t k = argc > 2 ? std::stoul(argv[2]) : 6;
  Mesh mesh;
  if(!CGAL::IO::read_polygon_mesh(filename, mesh) || !CGAL::is_triangle_mesh(mesh))
  {
    std::cerr << "Cannot read a triangle mesh from " << filename << std::endl;
    return EXIT_FAILURE;
  }

  // The graph view: its vertex_descriptor is the mesh's edge_descriptor, its vertex index the
  // mesh's edge index, and get(CGAL::vertex_point, g) gives the midpoints.
  const auto g = LD::make_edge_midpoint_graph(mesh);
  const auto index = get(boost::vertex_index, g);
  const auto midpoint = get(CGAL::vertex_point, g);

  // start at the edge whose midpoint is closest to the middle of the model
  const CGAL::Bbox_3 box = CGAL::Polygon_mesh_processing::bbox(mesh);
  const Point_3 middle((box.xmin() + box.xmax()) / 2, (box.ymin() + box.ymax()) / 2, (box.zmin() + box.zmax()) / 2);
  edge_descriptor start = *vertices(g).begin();
  for(edge_descriptor e : vertices(g))
    if(CGAL::squared_distance(get(midpoint, e), middle) < CGAL::squared_distance(get(midpoint, start), middle))
      start = e;

  // hop distances from the start edge
  std::vector<std::size_t> hops(num_vertices(g), std::numeric_limits<std::size_t>::max());
  hops[get(index, start)] = 0;
  auto hop_map = boost::make_iterator_property_map(hops.begin(), index);
  boost::breadth_first_search(g, start,
      boost::visitor(boost::make_bfs_visitor(boost::record_distances(hop_map, boost::on_tree_edge())))
      .vertex_index_map(index));

  LD::Mesh_deformer<Mesh> deformer(mesh);
  std::size_t roi_edges = 0;
  for(edge_descriptor e : vertices(g))
    if(hops[get(index, e)] <= k)
    {
      deformer.insert_roi_vertex(source(e, mesh));
      deformer.insert_roi_vertex(target(e, mesh));
      ++roi_edges;
    }
  const vertex_descriptor handles[] = {source(start, mesh), target(start, mesh)};
  deformer.insert_control_vertices(std::begin(handles), std::end(handles));
  std::cout << roi_edges << " edges within " << k << " hops: " << deformer.roi_vertices().size()
            << " ROI vertices of " << num_vertices(mesh) << std::endl;

  // lift the handle edge and turn it by 30 degrees about the vertical through its midpoint
  const Point_3 c = get(midpoint, start);
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(30. * 3.14159265358979323846 / 180., Eigen::Vector3d::UnitZ()));
  deformer.rotate(std::begin(handles), std::end(handles), Eigen::Vector3d(c.x(), c.y(), c.z()), turn);
  const double lift = (box.xmax() - box.xmin()) / 5;
  deformer.translate(std::begin(handles), std::end(handles), Eigen::Vector3d(0, 0, lift));

  const LD::Deformation_result result = deformer.deform(4, 0.);
  if(!result)
  {
    std::cerr << "deform failed: " << result.message << std::endl;
    return EXIT_FAILURE;
  }
  std::cout << "handle edge now from " << mesh.point(handles[0]) << " to " << mesh.point(handles[1]) << std::endl;
  return CGAL::IO::write_polygon_mesh("k_ring_bfs_deformed.off", mesh, CGAL::parameters::stream_precision(17))
             ? EXIT_SUCCESS : EXIT_FAILURE;
}
