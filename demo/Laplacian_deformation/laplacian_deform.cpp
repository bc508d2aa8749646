// laplacian_deform: the package's command-line tool. This first version runs the main job:
// deform a mesh with a Botsch08 selection (.sel) and handle transformation (.def) with the
// vertex-based and the edge-based S*R1 deformation, write both results and a side-by-side summary.
//
//   laplacian_deform                                  CGAL's cactus (data unpacked by scripts/setup.sh)
//   laplacian_deform MESH SEL DEF [OUTPUT_DIR]        any mesh CGAL reads (OFF, OBJ, PLY, STL)
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/Laplacian_deformation/Mesh_deformer.h>
#include <CGAL/Laplacian_deformation/Vertex_based_representation.h>
#include <CGAL/Laplacian_deformation/IO/Botsch08.h>
#include "deformation_server.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace LD = CGAL::Laplacian_deformation;
namespace fs = std::filesystem;

typedef CGAL::Simple_cartesian<double>                  Kernel;
typedef Kernel::Point_3                                 Point_3;
typedef CGAL::Surface_mesh<Point_3>                     Mesh;
typedef boost::graph_traits<Mesh>::vertex_descriptor    vertex_descriptor;

namespace {

struct Run
{
  std::string name;
  LD::Deformation_result result;
  double preprocess_seconds = 0, deform_seconds = 0;
  double mean_edge_distortion = 0, max_edge_distortion = 0;
  Mesh mesh;
};

// relative change of the length of every edge with a ROI endpoint
void edge_distortion(const Mesh& rest, Run& run, const std::vector<int>& status)
{
  std::size_t count = 0;
  for(auto e : edges(rest))
  {
    const vertex_descriptor a = source(e, rest), b = target(e, rest);
    if(status[a] == LD::IO::BOTSCH08_FIXED && status[b] == LD::IO::BOTSCH08_FIXED)
      continue;
    const double l0 = std::sqrt(CGAL::squared_distance(rest.point(a), rest.point(b)));
    const double l1 = std::sqrt(CGAL::squared_distance(run.mesh.point(a), run.mesh.point(b)));
    const double d = l0 > 0 ? std::abs(l1 - l0) / l0 : 0.;
    run.mean_edge_distortion += d;
    run.max_edge_distortion = (std::max)(run.max_edge_distortion, d);
    ++count;
  }
  if(count)
    run.mean_edge_distortion /= double(count);
}

template <class Representation>
bool deform(const Mesh& rest, const std::vector<int>& status, const Eigen::Matrix4d& t, Run& run)
{
  typedef std::chrono::steady_clock Clock;
  run.mesh = rest;
  LD::Mesh_deformer<Mesh, Representation> deformer(run.mesh);   // cotangent weights, S*R1
  std::vector<vertex_descriptor> handles;
  for(vertex_descriptor v : vertices(run.mesh))
  {
    if(status[v] == LD::IO::BOTSCH08_REGION_OF_INTEREST)
      deformer.insert_roi_vertex(v);
    else if(status[v] == LD::IO::BOTSCH08_HANDLE)
    {
      deformer.insert_control_vertex(v);
      handles.push_back(v);
    }
  }
  const auto t0 = Clock::now();
  if(!deformer.preprocess())
  {
    std::cerr << run.name << ": " << deformer.last_result().message << std::endl;
    return false;
  }
  const auto t1 = Clock::now();
  for(vertex_descriptor v : handles)
  {
    const Point_3& p = run.mesh.point(v);
    const Eigen::Vector4d q = t * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.);
    deformer.set_target_position(v, Point_3(q.x(), q.y(), q.z()));
  }
  run.result = deformer.deform(4, 0.);   // the paper's 3 to 4 iterations
  const auto t2 = Clock::now();
  run.preprocess_seconds = std::chrono::duration<double>(t1 - t0).count();
  run.deform_seconds = std::chrono::duration<double>(t2 - t1).count();
  if(!run.result)
    std::cerr << run.name << ": " << run.result.message << std::endl;
  return bool(run.result);
}

// write to a temporary file in the same folder, then rename: never a half-written result
bool write_atomically(const fs::path& path, const Mesh& mesh)
{
  const fs::path tmp = path.parent_path() / (".tmp." + path.filename().string());
  if(!CGAL::IO::write_polygon_mesh(tmp.string(), mesh, CGAL::parameters::stream_precision(17)))
  {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    return false;
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  return !ec;
}

int usage(std::ostream& out, int code)
{
  out << "usage: laplacian_deform [MESH SEL DEF [OUTPUT_DIR]]\n"
         "  Deforms MESH (OFF, OBJ, PLY or STL triangle mesh) with the Botsch08 selection SEL\n"
         "  (one status per vertex: 0 fixed, 1 region of interest, 2 handle) and the 4x4 handle\n"
         "  transformation DEF, with the vertex-based and the edge-based S*R1 deformation\n"
         "  (cotangent weights, 4 iterations), and writes both results and summary.txt into\n"
         "  OUTPUT_DIR (default: laplacian_deform_output). Without arguments: CGAL's cactus.\n";
  return code;
}

} // namespace

int main(int argc, char** argv)
{
  // laplacian_deform --serve [MESH] [--port N] [--output DIR]: the browser editor (deformation_server.h)
  if(argc >= 2 && std::string(argv[1]) == "--serve")
    return Laplacian_deformation_server::serve_main(argc, argv, LAPLACIAN_DEFORMATION_DATA_DIR,
                                                    LAPLACIAN_DEFORMATION_VIEWER_DIR);
  if(argc == 2 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h"))
    return usage(std::cout, EXIT_SUCCESS);
  if(argc != 1 && argc != 4 && argc != 5)
    return usage(std::cerr, EXIT_FAILURE);
  const fs::path data(LAPLACIAN_DEFORMATION_DATA_DIR);
  const fs::path mesh_file = argc > 1 ? fs::path(argv[1]) : data / "cactus.off";
  const fs::path sel_file = argc > 1 ? fs::path(argv[2]) : data / "cactus.sel";
  const fs::path def_file = argc > 1 ? fs::path(argv[3]) : data / "cactus.def";
  const fs::path output = argc > 4 ? fs::path(argv[4]) : fs::path("laplacian_deform_output");

  Mesh rest;
  if(!fs::is_regular_file(mesh_file) || !CGAL::IO::read_polygon_mesh(mesh_file.string(), rest) || is_empty(rest))
  {
    std::cerr << "error: cannot read a mesh from " << mesh_file << std::endl;
    return EXIT_FAILURE;
  }
  if(!CGAL::is_triangle_mesh(rest))
  {
    std::cerr << "error: " << mesh_file << " has non-triangle faces" << std::endl;
    return EXIT_FAILURE;
  }
  std::vector<int> status;
  std::string error;
  std::ifstream sel(sel_file);
  if(!sel || !LD::IO::read_botsch08_selection(sel, status, error, num_vertices(rest)))
  {
    std::cerr << "error: " << sel_file << ": " << (sel ? error : "cannot open") << std::endl;
    return EXIT_FAILURE;
  }
  Eigen::Matrix4d transform;
  std::ifstream def(def_file);
  if(!def || !LD::IO::read_botsch08_transform(def, transform, error))
  {
    std::cerr << "error: " << def_file << ": " << (def ? error : "cannot open") << std::endl;
    return EXIT_FAILURE;
  }

  Run runs[2];
  runs[0].name = "vertex-based";
  runs[1].name = "edge-based";
  if(!deform<LD::Vertex_based_representation>(rest, status, transform, runs[0]) ||
     !deform<LD::Edge_based_representation>(rest, status, transform, runs[1]))
    return EXIT_FAILURE;

  std::error_code ec;
  fs::create_directories(output, ec);
  const std::string stem = mesh_file.stem().string();
  std::ostringstream summary;
  summary << std::setprecision(4);
  summary << "mesh " << mesh_file.string() << ": " << num_vertices(rest) << " vertices, " << num_edges(rest)
          << " edges; ROI " << std::count(status.begin(), status.end(), 1) << ", handles "
          << std::count(status.begin(), status.end(), 2) << ", fixed " << std::count(status.begin(), status.end(), 0)
          << "\ncotangent weights, S*R1 transforms, hard constraints, 4 iterations\n\n"
          << std::left << std::setw(16) << "" << std::setw(14) << "vertex-based" << "edge-based\n";
  auto row = [&](const char* label, auto get) {
    summary << std::left << std::setw(16) << label << std::setw(14) << get(runs[0]) << get(runs[1]) << '\n';
  };
  row("preprocess s", [](const Run& r) { return r.preprocess_seconds; });
  row("deform s", [](const Run& r) { return r.deform_seconds; });
  row("iterations", [](const Run& r) { return r.result.iterations; });
  row("energy", [](const Run& r) { return r.result.energy; });
  for(Run& r : runs)
    edge_distortion(rest, r, status);
  row("edge dist mean", [](const Run& r) { return r.mean_edge_distortion; });
  row("edge dist max", [](const Run& r) { return r.max_edge_distortion; });
  for(Run& r : runs)
  {
    const fs::path path = output / (stem + "_" + r.name + ".off");
    if(!write_atomically(path, r.mesh))
    {
      std::cerr << "error: cannot write " << path << std::endl;
      return EXIT_FAILURE;
    }
    summary << "wrote " << path.string() << '\n';
  }
  std::ofstream(output / "summary.txt") << summary.str();
  std::cout << summary.str() << "summary in " << (output / "summary.txt").string() << std::endl;
  return EXIT_SUCCESS;
}
