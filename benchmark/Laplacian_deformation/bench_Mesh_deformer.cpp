// Preprocess (operator, rows, factorisation) and one deform iteration (local step, right-hand
// side, solve) of Mesh_deformer, vertex- vs edge-based, on CGAL's armadillo with the ROI = every
// vertex but a fixed patch (the 2% lowest in y) and the 1% highest vertices as a moved handle.
//   build/benchmark/Laplacian_deformation/bench_Mesh_deformer
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/Laplacian_deformation/Mesh_deformer.h>
#include <CGAL/Laplacian_deformation/Vertex_based_representation.h>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <stdexcept>

namespace LD = CGAL::Laplacian_deformation;
typedef CGAL::Simple_cartesian<double> Kernel;
typedef CGAL::Surface_mesh<Kernel::Point_3> Mesh;
typedef boost::graph_traits<Mesh>::vertex_descriptor vertex_descriptor;

namespace {

const Mesh& armadillo()
{
  static const Mesh mesh = [] {
    Mesh m;
    if(!CGAL::IO::read_polygon_mesh(std::string(LAPLACIAN_DEFORMATION_DATA_DIR) + "/armadillo.off", m))
      throw std::runtime_error("cannot read armadillo.off: run scripts/setup.sh");
    return m;
  }();
  return mesh;
}

template <class Deformer>
void select(Deformer& d, const Mesh& m, std::vector<vertex_descriptor>& handle)
{
  std::vector<vertex_descriptor> by_height(vertices(m).begin(), vertices(m).end());
  std::sort(by_height.begin(), by_height.end(),
            [&](vertex_descriptor a, vertex_descriptor b) { return m.point(a).y() < m.point(b).y(); });
  const std::size_t fixed = by_height.size() / 50, moved = by_height.size() / 100;
  d.insert_roi_vertices(by_height.begin() + long(fixed), by_height.end());
  handle.assign(by_height.end() - long(moved), by_height.end());
  d.insert_control_vertices(handle.begin(), handle.end());
}

template <class Representation>
void BM_preprocess(benchmark::State& state)
{
  for(auto _ : state)
  {
    Mesh m = armadillo();
    LD::Mesh_deformer<Mesh, Representation> d(m);
    std::vector<vertex_descriptor> handle;
    select(d, m, handle);
    if(!d.preprocess())
      state.SkipWithError(d.last_result().message.c_str());
  }
  state.counters["vertices"] = double(num_vertices(armadillo()));
}

template <class Representation>
void BM_iteration(benchmark::State& state)
{
  Mesh m = armadillo();
  LD::Mesh_deformer<Mesh, Representation> d(m);
  std::vector<vertex_descriptor> handle;
  select(d, m, handle);
  if(!d.preprocess())
    state.SkipWithError(d.last_result().message.c_str());
  d.translate(handle.begin(), handle.end(), Kernel::Vector_3(0, 5, 0));
  d.deform(1, 0.);                                 // the T = I start
  for(auto _ : state)
    benchmark::DoNotOptimize(d.deform(1, 0.));    // local step + right-hand side + solve
}

} // namespace

BENCHMARK_TEMPLATE(BM_preprocess, LD::Vertex_based_representation)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_preprocess, LD::Edge_based_representation)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_iteration, LD::Vertex_based_representation)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_iteration, LD::Edge_based_representation)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
