// Micro-benchmark (Google Benchmark) of the local step's fits alone: 10^5 random cells (10 spokes
// each, the size of an edge-based row's cell; rest edges Gaussian, current edges a random rotation
// and anisotropic scale of them plus noise, random weights in [0, 2]), fitted by each built-in
// policy either one cell at a time (transform(cell), "scalar") or through transform_block() with
// each kernel target the processor runs (portable = the compilation's own instruction set,
// SSE2 on a default x86-64 build; avx2; avx512). Counter ns_per_cell: processor time per
// cell (std::clock), less sensitive than the wall time to a busy machine; one thread. The cells are
// gathered once (the core's gather and scaling are not timed).
//
//   bench_local_step [Google Benchmark flags, e.g. --benchmark_filter=Scaled]

#include <CGAL/Laplacian_deformation/Anchored_scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Node_cell.h>
#include <CGAL/Laplacian_deformation/Principal_scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Rotation_scale_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Rotation_transform.h>
#include <CGAL/Laplacian_deformation/Scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Similarity_transform.h>
#include <CGAL/Laplacian_deformation/internal/batched_transforms.h>

#include <benchmark/benchmark.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cstddef>
#include <ctime>
#include <random>
#include <string>
#include <vector>

namespace {

namespace LD = CGAL::Laplacian_deformation;
namespace B = CGAL::Laplacian_deformation::internal::batched;

struct Cells
{
  std::vector<Eigen::Vector3d> rest, current;
  std::vector<double> weights;
  std::vector<LD::Transform_cell> cells;

  Cells(std::size_t count, std::size_t degree)
  {
    std::mt19937_64 g(7);
    std::normal_distribution<double> n(0, 1);
    std::uniform_real_distribution<double> u(0, 2);
    rest.reserve(count * degree);
    current.reserve(count * degree);
    weights.reserve(count * degree);
    for(std::size_t k = 0; k < count; ++k)
    {
      const Eigen::Matrix3d m = Eigen::Quaterniond(n(g), n(g), n(g), n(g)).normalized().toRotationMatrix() *
                                Eigen::Vector3d(1 + 0.2 * n(g), 1 + 0.2 * n(g), 1 + 0.2 * n(g)).asDiagonal();
      for(std::size_t i = 0; i < degree; ++i)
      {
        const Eigen::Vector3d e(n(g), n(g), n(g));
        rest.push_back(e);
        current.push_back(m * e + 0.05 * Eigen::Vector3d(n(g), n(g), n(g)));
        weights.push_back(u(g));
      }
    }
    for(std::size_t k = 0; k < count; ++k)
      cells.emplace_back(rest.data() + k * degree, current.data() + k * degree, weights.data() + k * degree, degree);
  }
};

const Cells& cells()
{
  static const Cells c(100000, 10);
  return c;
}

// target < 0: transform(cell) per cell; otherwise transform_block() in groups of 32 cells (as
// Deformation_core::local_step() calls it) with that target
template <class Policy>
void BM_fit(benchmark::State& state, int target)
{
  const std::vector<LD::Transform_cell>& c = cells().cells;
  const Policy policy;
  std::vector<Eigen::Matrix3d> out(c.size());
  const B::Batch_target saved = B::batch_target();
  if(target >= 0)
    B::set_batch_target(B::Batch_target(target));
  double cpu_seconds = 0;
  for(auto _ : state)
  {
    const std::clock_t start = std::clock();
    if(target < 0)
      for(std::size_t i = 0; i < c.size(); ++i)
        out[i] = policy.transform(c[i]);
    else
      for(std::size_t first = 0; first < c.size(); first += 32)
        policy.transform_block(c.data() + first, std::min<std::size_t>(32, c.size() - first), out.data() + first);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
    cpu_seconds += double(std::clock() - start) / CLOCKS_PER_SEC;
  }
  B::set_batch_target(saved);
  // processor time / (iterations x cells), in ns
  state.counters["ns_per_cell"] = benchmark::Counter(1e9 * cpu_seconds / double(c.size()), benchmark::Counter::kAvgIterations);
}

template <class Policy>
void register_policy(const std::string& name)
{
  benchmark::RegisterBenchmark(("local_step/" + name + "/scalar").c_str(),
                               [](benchmark::State& st) { BM_fit<Policy>(st, -1); })->Unit(benchmark::kMillisecond);
  for(B::Batch_target t : {B::Batch_target::portable, B::Batch_target::avx2, B::Batch_target::avx512})
    if(B::batch_target_supported(t))
      benchmark::RegisterBenchmark(("local_step/" + name + "/" + B::batch_target_name(t)).c_str(),
                                   [t](benchmark::State& st) { BM_fit<Policy>(st, int(t)); })
          ->Unit(benchmark::kMillisecond);
}

} // namespace

int main(int argc, char** argv)
{
  benchmark::Initialize(&argc, argv);
  if(benchmark::ReportUnrecognizedArguments(argc, argv))
    return 1;
  register_policy<LD::Rotation_transform>("Rotation");
  register_policy<LD::Similarity_transform>("Similarity");
  register_policy<LD::Scaled_rotation_transform>("Scaled_rotation");
  register_policy<LD::Anchored_scaled_rotation_transform>("Anchored_scaled_rotation");
  register_policy<LD::Principal_scaled_rotation_transform>("Principal_scaled_rotation");
  register_policy<LD::Rotation_scale_rotation_transform>("Rotation_scale_rotation");
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
