// Micro-benchmarks (Google Benchmark): preprocess (operator, rows, factorisation) and one deform
// iteration (local step, right-hand side, solve, and `around`: the rest of the deform() call, its
// reading of the ROI, writing of the solution and warnings; reported as counters in ms) of Mesh_deformer,
// vertex- vs edge-based (cotangent weights, S*R1), next to CGAL's Surface_mesh_deformation
// (ORIGINAL_ARAP, its default solver) on the same ROI, on CGAL's armadillo (level 0, 26k vertices)
// and its Loop subdivisions (CGAL::Subdivision_method_3::Loop_subdivision: level 1 ~104k, level 2
// ~416k vertices; computed once per process).
// vertex_any, edge_any (level 0 only): the same with the run-time policies Any_weights and
// Any_transform (holding the defaults), the cost of the type erasure against the static path.
// ROIs: "all_but_2pct" = every vertex but the 2% lowest in y (fixed), "roi_10pct" = the 10%
// highest in y; in both the 1% highest vertices are the handle, moved up by 5% of the height;
// "roi_1pct" = the 1% highest, of which the 0.1% highest are the handle.
// first_use (roi_10pct and roi_1pct): the constructor, the insertions and the first preprocess()
// timed together (CGAL's constructor computes the weights of every halfedge of the mesh);
// new_selection: a second selection of the same size (the lowest vertices) on the same deformer,
// the ROI cleared, the new one inserted and preprocess() timed. No preprocess case times the copy
// of the mesh or the destruction of the deformer and of the copy (before 2026-12-07 the preprocess
// case timed both destructions).
//
//   bench_Mesh_deformer [--levels=0,1] [--spatial_order] [Google Benchmark flags, e.g. --benchmark_format=json]
//
// --spatial_order: every case runs on a copy of the mesh whose vertices are numbered along a
// Morton (Z-order) curve of their positions and whose faces are added in the order of their
// smallest new vertex index (so the edges are numbered near their vertices too): the same surface,
// the same selections (chosen by height), a cache-friendly numbering. CGAL's subdivisions append
// the new vertices and edges at the end, so neighbours are far apart in memory; this shows what
// that costs each method. run_harness.sh does not pass it (the rows are for the mesh as read).
//
// Level 2 is slow (factorisations of a 416k-vertex system): it runs only when asked for.
//
// Counters besides the times:
// - peak_mb, base_mb, extra_mb: memory. At the start of each call of the case (Google Benchmark may
//   call a case more than once), once the (cached) mesh and the selection are ready, the case resets
//   the process's peak resident set size (writes 5 to /proc/self/clear_refs) and reads VmRSS
//   (base_mb); after the call it reads VmHWM (peak_mb): the peak of the last call, or the memory the
//   process kept from earlier calls if larger; extra_mb = peak_mb - base_mb (small when earlier calls
//   left their freed memory in the process). peak_reset = 1 when the reset worked. Freed memory of
//   other cases may stay in the process too: run_harness.sh runs every case in its own process
//   (--benchmark_filter) and reports peak_mb. The preprocess, first_use and new_selection cases
//   reset again inside each call, just before its timed part (the mesh copy and, but for first_use,
//   the deformer with its first selection are ready): their base_mb and extra_mb are the memory
//   the timed part itself touched, not the copy of the mesh made for it.
// - ours only (CHOLMOD build): factor_ms (CHOLMOD analyse + factorise inside preprocess()),
//   factor_mb (bytes of the supernodal factor L: values and row indices, read once by the forward
//   and once by the backward substitution), factor_lnz (nonzeros of L), n (unknowns per coordinate).
// - bandwidth/read_1GiB/threads:T: sums a 1 GiB array of 64-bit integers with T threads (bytes_per_second):
//   the machine's memory read bandwidth, for the bound "solve >= 2 x factor bytes / bandwidth".
// - memory/first_touch_256MiB: the cost of a page fault (us_per_page): every MB a case touches for
//   the first time costs 256 of them (on this project's CI machines about 11 us each, ~2.8 ms per MB).
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_deformation.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/subdivision_method_3.h>
#include <CGAL/Laplacian_deformation/Mesh_deformer.h>
#include <CGAL/Laplacian_deformation/Vertex_based_representation.h>
#include <CGAL/Laplacian_deformation/Any_weights.h>
#include <CGAL/Laplacian_deformation/Any_transform.h>

#ifdef CGAL_LAPLACIAN_DEFORMATION_USE_CHOLMOD
#include <CGAL/Laplacian_deformation/Cholmod_solver_traits.h>
#endif

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <dlfcn.h>
#ifdef __GLIBC__
#include <malloc.h>   // malloc_trim
#endif
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace LD = CGAL::Laplacian_deformation;
typedef CGAL::Simple_cartesian<double> Kernel;
typedef CGAL::Surface_mesh<Kernel::Point_3> Mesh;
typedef boost::graph_traits<Mesh>::vertex_descriptor vertex_descriptor;

namespace {

// ---- memory of the process (Linux /proc)
double proc_status_mb(const char* key)   // VmRSS, VmHWM, ... in MB
{
  std::ifstream in("/proc/self/status");
  const std::size_t length = std::strlen(key);
  for(std::string line; std::getline(in, line);)
    if(line.compare(0, length, key) == 0 && line.size() > length && line[length] == ':')
      return std::atof(line.c_str() + length + 1) / 1024.;   // kB
  return 0;
}

// VmHWM := VmRSS (Linux >= 4.0), after the heap's free memory went back to the system: Google
// Benchmark calls a case several times, and glibc kept what an earlier call freed (the freed
// deformer) in the base of the next call (at 26k, the edge-based iteration case's base was 113.5
// MB, 28.8 MB with the trim; its peak, 156 MB, did not change: it includes the memory that stays
// after a first call, such as BLAS's buffers: the peak of a process that calls the case once is
// 143.7 MB)
bool reset_peak_memory()
{
#ifdef __GLIBC__
  malloc_trim(0);
#endif
  std::ofstream out("/proc/self/clear_refs");
  out << "5";
  out.flush();
  return bool(out);
}

struct Memory_probe
{
  bool reset = reset_peak_memory();
  double base = proc_status_mb("VmRSS");
  void restart()   // the peak and the base from now on
  {
    reset = reset_peak_memory();
    base = proc_status_mb("VmRSS");
  }
  void report(benchmark::State& state) const
  {
    const double peak = proc_status_mb("VmHWM");
    state.counters["peak_mb"] = peak;
    state.counters["base_mb"] = base;
    state.counters["extra_mb"] = peak - base;
    state.counters["peak_reset"] = reset ? 1 : 0;
  }
};

// ---- the factor of ours: CHOLMOD's supernodal LLT recording the size of L and the factorisation time
struct Factor_record
{
  double seconds = 0, analyse_seconds = 0, factorise_seconds = 0, flops = 0, bytes = 0, lnz = 0, n = 0;
  double solve_sequential_share = 1, solve_groups = 1, solve_levels = 0;   // of the last three-column solve
  bool valid = false;
};
Factor_record last_factor;
double last_metis_seconds = 0;   // of the metisdirect experiment

#ifdef CGAL_LAPLACIAN_DEFORMATION_USE_CHOLMOD
// Exactly Cholmod_supernodal_llt (the solver of Default_solver_traits); compute() also records.
struct Recording_supernodal_llt : public LD::Cholmod_supernodal_llt
{
  typedef LD::Cholmod_supernodal_llt Base;
  Recording_supernodal_llt()
  {
    // experiments: LD_BENCH_ORDERING=cholmod is CHOLMOD's default choice (set_ordering(
    // CHOLMOD_DEFAULT_ORDERING)); amd|metis|nesdis forces one of CHOLMOD's fill-reducing orderings
    if(const char* o = std::getenv("LD_BENCH_ORDERING"); o != nullptr && std::strcmp(o, "cholmod") == 0)
      set_ordering(CHOLMOD_DEFAULT_ORDERING);
    else if(o != nullptr && *o != 0 && std::strcmp(o, "metisdirect") != 0)
    {
      const std::string ordering = o;
      cholmod().nmethods = 1;
      cholmod().method[0].ordering = ordering == "metis" ? CHOLMOD_METIS : ordering == "nesdis" ? CHOLMOD_NESDIS : CHOLMOD_AMD;
      cholmod().postorder = 1;
    }
    // experiments: LD_BENCH_MULTIFRONTAL=0 uses CHOLMOD's own numeric factorisation
    if(const char* m = std::getenv("LD_BENCH_MULTIFRONTAL"); m != nullptr && std::strcmp(m, "0") == 0)
      set_multifrontal(false);
    // experiments: LD_BENCH_RELAX=n0,n1,n2,z0,z1,z2 sets CHOLMOD's supernodal amalgamation
    // (nrelax, zrelax; CHOLMOD's defaults 4,16,48,0.8,0.1,0.05)
    if(const char* r = std::getenv("LD_BENCH_RELAX"); r != nullptr && *r != 0)
    {
      double v[6] = {4, 16, 48, 0.8, 0.1, 0.05};
      std::sscanf(r, "%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5]);
      for(int k = 0; k < 3; ++k)
      {
        cholmod().nrelax[k] = static_cast<std::size_t>(v[k]);
        cholmod().zrelax[k] = v[3 + k];
      }
    }
  }
  // experiment: LD_BENCH_ORDERING=metisdirect orders with METIS_NodeND called directly, options from
  // LD_BENCH_METIS="niter,nseps,ufactor,ctype,compress" (-1: METIS's default), then CHOLMOD's
  // analysis of that permutation (CHOLMOD_GIVEN, postordered)
  void analyzePattern(const Eigen::SparseMatrix<double>& matrix)
  {
    const char* o = std::getenv("LD_BENCH_ORDERING");
    if(o == nullptr || std::strcmp(o, "metisdirect") != 0)
      return Base::analyzePattern(matrix);
    typedef int (*Node_nd)(int*, int*, int*, int*, int*, int*, int*);
    typedef int (*Set_default)(int*);
    static Node_nd node_nd = reinterpret_cast<Node_nd>(dlsym(RTLD_DEFAULT, "METIS_NodeND"));
    static Set_default set_default = reinterpret_cast<Set_default>(dlsym(RTLD_DEFAULT, "METIS_SetDefaultOptions"));
    if(node_nd == nullptr || set_default == nullptr)
      throw std::runtime_error("METIS not found");
    const int n = int(matrix.rows());
    std::vector<int> degree(std::size_t(n) + 1, 0);
    for(int j = 0; j < n; ++j)
      for(Eigen::SparseMatrix<double>::InnerIterator it(matrix, j); it; ++it)
        if(it.row() > j)
          ++degree[std::size_t(it.row()) + 1], ++degree[std::size_t(j) + 1];
    for(int i = 0; i < n; ++i)
      degree[std::size_t(i) + 1] += degree[std::size_t(i)];
    std::vector<int> adjacency(static_cast<std::size_t>(degree[std::size_t(n)]));
    std::vector<int> fill(degree.begin(), degree.end() - 1);
    for(int j = 0; j < n; ++j)
      for(Eigen::SparseMatrix<double>::InnerIterator it(matrix, j); it; ++it)
        if(it.row() > j)
        {
          adjacency[std::size_t(fill[std::size_t(it.row())]++)] = j;
          adjacency[std::size_t(fill[std::size_t(j)]++)] = int(it.row());
        }
    int options[40];
    set_default(options);
    int v[5] = {-1, -1, -1, -1, -1};
    if(const char* m = std::getenv("LD_BENCH_METIS"))
      std::sscanf(m, "%d,%d,%d,%d,%d", &v[0], &v[1], &v[2], &v[3], &v[4]);
    if(v[0] >= 0) options[6] = v[0];    // METIS_OPTION_NITER
    if(v[1] >= 0) options[15] = v[1];   // METIS_OPTION_NSEPS
    if(v[2] >= 0) options[16] = v[2];   // METIS_OPTION_UFACTOR
    if(v[3] >= 0) options[2] = v[3];    // METIS_OPTION_CTYPE (0 RM, 1 SHEM)
    if(v[4] >= 0) options[12] = v[4];   // METIS_OPTION_COMPRESS
    std::vector<int> perm(static_cast<std::size_t>(n)), iperm(static_cast<std::size_t>(n));
    int nn = n;
    const auto t0 = std::chrono::steady_clock::now();
    if(node_nd(&nn, degree.data(), adjacency.data(), nullptr, options, perm.data(), iperm.data()) != 1)
      throw std::runtime_error("METIS_NodeND failed");
    last_metis_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    cholmod_common& c = cholmod();
    c.nmethods = 1;
    c.method[0].ordering = CHOLMOD_GIVEN;
    c.postorder = 1;
    cholmod_sparse a = Eigen::viewAsCholmod(Eigen::Ref<Eigen::SparseMatrix<double>>(const_cast<Eigen::SparseMatrix<double>&>(matrix)));
    a.stype = -1;
    if(m_cholmodFactor)
      cholmod_free_factor(&m_cholmodFactor, &c);
    m_cholmodFactor = cholmod_analyze_p(&a, perm.data(), nullptr, 0, &c);
    m_analysisIsOk = m_cholmodFactor != nullptr;
    m_factorizationIsOk = false;
    this->m_isInitialized = true;
    this->m_info = m_analysisIsOk ? Eigen::Success : Eigen::NumericalIssue;
    set_multifrontal(is_multifrontal());   // (the derived class's state: forget the old preparation)
  }
  Recording_supernodal_llt& compute(const Eigen::SparseMatrix<double>& matrix)
  {
    typedef std::chrono::steady_clock Clock;
    const auto start = Clock::now();
    analyzePattern(matrix);                    // what Base::compute() does, timed in two parts
    const auto analysed = Clock::now();
    Base::factorize(matrix);
    const auto end = Clock::now();
    last_factor.seconds = std::chrono::duration<double>(end - start).count();
    last_factor.analyse_seconds = std::chrono::duration<double>(analysed - start).count();
    last_factor.factorise_seconds = std::chrono::duration<double>(end - analysed).count();
    last_factor.flops = cholmod().fl;          // the factorisation's flop count (from the analysis)
    last_factor.valid = m_cholmodFactor != nullptr;
    if(last_factor.valid)
    {
      const cholmod_factor& l = *m_cholmodFactor;
      const double index_bytes = l.itype == CHOLMOD_LONG ? 8 : 4;
      last_factor.bytes = l.is_super ? 8. * double(l.xsize) + index_bytes * double(l.ssize)
                                     : (8. + index_bytes) * double(l.nzmax);
      last_factor.lnz = cholmod().lnz;
      last_factor.n = double(l.n);
    }
    return *this;
  }
  // Base::solve_columns(), also recording how the substitutions were shared between threads
  template <class Matrix>
  bool solve_columns(const Eigen::Ref<const Eigen::MatrixXd>& b, Matrix& x) const
  {
    const bool ok = Base::solve_columns(b, x);
    last_factor.solve_sequential_share = sequential_share();
    last_factor.solve_groups = double(number_of_parallel_groups());
    last_factor.solve_levels = double(number_of_parallel_levels());
    return ok;
  }
};
typedef CGAL::Eigen_solver_traits<Recording_supernodal_llt> Bench_solver_traits;
#else
typedef CGAL::Default Bench_solver_traits;
#endif

void report_factor(benchmark::State& state)
{
  if(!last_factor.valid)
    return;
  state.counters["factor_ms"] = 1e3 * last_factor.seconds;
  state.counters["analyse_ms"] = 1e3 * last_factor.analyse_seconds;
  if(last_metis_seconds > 0)
    state.counters["metis_ms"] = 1e3 * last_metis_seconds;
  state.counters["factorise_ms"] = 1e3 * last_factor.factorise_seconds;
  state.counters["factor_gflop"] = last_factor.flops / 1e9;
  state.counters["factor_gflops"] = last_factor.factorise_seconds > 0 ? last_factor.flops / last_factor.factorise_seconds / 1e9 : 0.;
  state.counters["factor_mb"] = last_factor.bytes / 1e6;
  state.counters["factor_lnz"] = last_factor.lnz;
  state.counters["n"] = last_factor.n;
  state.counters["solve_sequential_share"] = last_factor.solve_sequential_share;
  state.counters["solve_groups"] = last_factor.solve_groups;
  state.counters["solve_levels"] = last_factor.solve_levels;
}

#ifdef LAPLACIAN_DEFORMATION_BENCH_HAS_BLAS
extern "C" void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k,
                       const double* alpha, const double* a, const int* lda, const double* b, const int* ldb,
                       const double* beta, double* c, const int* ldc);

// ---- the machine's dgemm rate: C = A B with the BLAS CHOLMOD calls (its threads as configured),
// n x n matrices; the limit of a supernodal factorisation, whose work is dense blocks
void BM_dgemm(benchmark::State& state, int n)
{
  std::vector<double> a(std::size_t(n) * std::size_t(n), 1e-3), b(a), c(a.size(), 0.);
  const double one = 1, zero = 0;
  for(auto _ : state)
  {
    dgemm_("N", "N", &n, &n, &n, &one, a.data(), &n, b.data(), &n, &zero, c.data(), &n);
    benchmark::DoNotOptimize(c.data());
    benchmark::ClobberMemory();
  }
  if(!(std::abs(c[0] - double(n) * 1e-6) <= 1e-9 * double(n)))
    state.SkipWithError("wrong product");
  state.counters["gflops"] = benchmark::Counter(2. * double(n) * double(n) * double(n) * 1e-9 * double(state.iterations()),
                                                benchmark::Counter::kIsRate);
}
#endif

// ---- memory read bandwidth: sum a 1 GiB array of 64-bit integers with `threads` threads
void BM_read_bandwidth(benchmark::State& state, int threads)
{
  const std::size_t count = (std::size_t(1) << 30) / sizeof(std::uint64_t);
  std::vector<std::uint64_t> data(count, 1);
  std::vector<std::uint64_t> sums(std::size_t(threads) * 8);
  for(auto _ : state)
  {
    std::vector<std::thread> workers;
    for(int t = 0; t < threads; ++t)
      workers.emplace_back([&, t] {
        const std::size_t begin = count * std::size_t(t) / std::size_t(threads);
        const std::size_t end = count * std::size_t(t + 1) / std::size_t(threads);
        std::uint64_t sum = 0;
        for(std::size_t i = begin; i < end; ++i)
          sum += data[i];
        sums[std::size_t(t) * 8] = sum;     // one cache line apart
      });
    for(std::thread& w : workers)
      w.join();
    benchmark::DoNotOptimize(sums.data());
    benchmark::ClobberMemory();
  }
  std::uint64_t total = 0;
  for(int t = 0; t < threads; ++t)
    total += sums[std::size_t(t) * 8];
  if(total != count)
    state.SkipWithError("wrong sum");
  state.SetBytesProcessed(std::int64_t(state.iterations()) * std::int64_t(count * sizeof(std::uint64_t)));
}

// ---- first touch of fresh memory: allocate 256 MiB, write one byte per 4 KiB page, free; each
// page is a page fault. Reports us_per_page and ms_per_mb: what every megabyte of memory a case
// touches for the first time costs on this machine before any computation.
void BM_first_touch(benchmark::State& state)
{
  const std::size_t bytes = std::size_t(256) << 20, page = 4096;
  double seconds = 0;
  for(auto _ : state)
  {
    const auto t0 = std::chrono::steady_clock::now();
    char* data = static_cast<char*>(std::malloc(bytes));     // above the mmap threshold: fresh pages
    if(data == nullptr)
    {
      state.SkipWithError("out of memory");
      return;
    }
    for(std::size_t i = 0; i < bytes; i += page)
      data[i] = 1;
    benchmark::DoNotOptimize(data);
    benchmark::ClobberMemory();
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::free(data);
  }
  const double pages = double(bytes / page) * double(state.iterations());
  state.counters["us_per_page"] = pages > 0 ? 1e6 * seconds / pages : 0.;
  state.counters["ms_per_mb"] = pages > 0 ? 1e3 * seconds / pages * 1e6 / double(page) : 0.;
}

bool spatial_order = false;   // --spatial_order

// `m` renumbered (see --spatial_order above): vertices by the Morton code of their position in the
// bounding box (20 bits per coordinate, interleaved), faces by their smallest new vertex index
Mesh spatially_ordered(const Mesh& m)
{
  double low[3] = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
  double high[3] = {-low[0], -low[1], -low[2]};
  for(vertex_descriptor v : vertices(m))
    for(int i = 0; i < 3; ++i)
    {
      low[i] = (std::min)(low[i], m.point(v)[i]);
      high[i] = (std::max)(high[i], m.point(v)[i]);
    }
  auto morton = [&](const Mesh::Point& p) {
    std::uint64_t key[3], code = 0;
    for(int i = 0; i < 3; ++i)
    {
      const double t = high[i] > low[i] ? (p[i] - low[i]) / (high[i] - low[i]) : 0.;
      key[i] = std::uint64_t((std::min)((std::max)(t, 0.), 1.) * double((1 << 20) - 1));
    }
    for(int bit = 19; bit >= 0; --bit)
      for(int i = 0; i < 3; ++i)
        code = (code << 1) | ((key[i] >> bit) & 1u);
    return code;
  };
  std::vector<std::pair<std::uint64_t, vertex_descriptor>> by_code;
  for(vertex_descriptor v : vertices(m))
    by_code.emplace_back(morton(m.point(v)), v);
  std::sort(by_code.begin(), by_code.end());
  Mesh out;
  std::vector<vertex_descriptor> renumbered(num_vertices(m));
  for(const auto& [code, v] : by_code)
    renumbered[std::size_t(v)] = out.add_vertex(m.point(v));
  std::vector<std::pair<std::size_t, Mesh::Face_index>> by_vertex;
  for(Mesh::Face_index f : faces(m))
  {
    std::size_t smallest = std::numeric_limits<std::size_t>::max();
    for(vertex_descriptor v : vertices_around_face(halfedge(f, m), m))
      smallest = (std::min)(smallest, std::size_t(renumbered[std::size_t(v)]));
    by_vertex.emplace_back(smallest, f);
  }
  std::sort(by_vertex.begin(), by_vertex.end());
  for(const auto& [smallest, f] : by_vertex)
  {
    std::vector<vertex_descriptor> corners;
    for(vertex_descriptor v : vertices_around_face(halfedge(f, m), m))
      corners.push_back(renumbered[std::size_t(v)]);
    if(out.add_face(corners) == Mesh::null_face())
      throw std::runtime_error("--spatial_order: a face could not be added again");
  }
  return out;
}

// the armadillo subdivided `level` times, computed at its first use (reading a 416k-vertex OFF file
// takes longer here than the two subdivisions); renumbered with --spatial_order
const Mesh& armadillo(int level)
{
  static std::map<int, Mesh> meshes;
  auto it = meshes.find(level);
  if(it != meshes.end())
    return it->second;
  const std::string data(LAPLACIAN_DEFORMATION_DATA_DIR);
  Mesh m;
  if(!CGAL::IO::read_polygon_mesh(data + "/armadillo.off", m) || is_empty(m))
    throw std::runtime_error("cannot read armadillo.off: run scripts/setup.sh");
  if(level > 0)
    CGAL::Subdivision_method_3::Loop_subdivision(m, CGAL::parameters::number_of_iterations(level));
  return meshes[level] = spatial_order ? spatially_ordered(m) : m;
}

struct Selection
{
  std::vector<vertex_descriptor> roi, handle;
  double height = 0;
};

// roi_percent = 98: all but the 2% lowest; 10: the 10% highest; 1: the 1% highest (a small
// selection on a big mesh, as in the editor). The handle: the 1% highest (0.1% with the 1% ROI).
// lowest = true: the same counted from the bottom (another selection of the same size).
Selection select(const Mesh& m, int roi_percent, bool lowest = false)
{
  std::vector<vertex_descriptor> by_height(vertices(m).begin(), vertices(m).end());
  std::sort(by_height.begin(), by_height.end(), [&](vertex_descriptor a, vertex_descriptor b) {
    return lowest ? m.point(a).y() > m.point(b).y() : m.point(a).y() < m.point(b).y();
  });
  Selection s;
  const std::size_t n = by_height.size(), in_roi = n * std::size_t(roi_percent) / 100,
                    moved = roi_percent > 1 ? n / 100 : n / 1000;
  s.roi.assign(by_height.end() - long(in_roi), by_height.end());
  s.handle.assign(by_height.end() - long(moved), by_height.end());
  s.height = std::abs(m.point(by_height.back()).y() - m.point(by_height.front()).y());
  return s;
}

template <class Representation>
struct Ours
{
  typedef LD::Mesh_deformer<Mesh, Representation, CGAL::Default, CGAL::Default, Bench_solver_traits> Deformer;
  static constexpr bool split = true;
  static void insert(Deformer& d, const Selection& s)
  {
    d.insert_roi_vertices(s.roi.begin(), s.roi.end());
    d.insert_control_vertices(s.handle.begin(), s.handle.end());
  }
};

// the same with the run-time policies (Any_weights, Any_transform; holding the defaults, cotangent
// weights and S*R1): the cost of the type erasure against the static path above
template <class Representation>
struct Ours_any : Ours<Representation>
{
  typedef LD::Mesh_deformer<Mesh, Representation, LD::Any_weights, LD::Any_transform, Bench_solver_traits> Deformer;
  static void insert(Deformer& d, const Selection& s)
  {
    d.insert_roi_vertices(s.roi.begin(), s.roi.end());
    d.insert_control_vertices(s.handle.begin(), s.handle.end());
  }
};

struct Cgal_arap
{
  typedef CGAL::Surface_mesh_deformation<Mesh, CGAL::Default, CGAL::Default, CGAL::ORIGINAL_ARAP> Deformer;
  static constexpr bool split = false;
  static void insert(Deformer& d, const Selection& s)
  {
    d.insert_roi_vertices(s.roi.begin(), s.roi.end());
    for(vertex_descriptor v : s.handle)
      d.insert_control_vertex(v);
  }
};

// The preprocess cases. None times the copy of the mesh nor the destruction of the deformer and
// of the copy.
// - preprocess: preprocess() alone, on a deformer constructed for the case with the selection
//   inserted.
// What a user waits for on a small selection:
// - first_use: a new mesh meets its first selection. Timed: the deformer's constructor, the
//   insertion of the ROI and the handle, and the first preprocess(). CGAL's constructor does work
//   proportional to the mesh (it computes the weight of every halfedge of the mesh), which the
//   preprocess case leaves out; ours keeps per-vertex arrays and the rest positions.
// - new_selection (the editor's case: the user selects again): the highest vertices were selected
//   and preprocessed; timed: the ROI and the controls cleared, a selection of the same size at the
//   bottom of the mesh inserted, and preprocess().
enum class Preprocess_case { preprocess, first_use, new_selection };

template <class Method>
void BM_preprocess(benchmark::State& state, int level, int roi_percent, Preprocess_case what)
{
  const Mesh& base = armadillo(level);
  const bool again = what == Preprocess_case::new_selection;
  const Selection first = select(base, roi_percent), s = again ? select(base, roi_percent, true) : first;
  last_factor = Factor_record();
  Memory_probe memory;
  for(auto _ : state)
  {
    state.PauseTiming();
    std::optional<Mesh> m(base);
    std::optional<typename Method::Deformer> d;
    if(what != Preprocess_case::first_use)
    {
      d.emplace(*m);
      Method::insert(*d, first);
      if(again && !d->preprocess())
      {
        state.SkipWithError("preprocess failed");   // no timer call after it
        break;
      }
    }
    memory.restart();   // the timed part's own memory (not the mesh copy's)
    state.ResumeTiming();
    if(what == Preprocess_case::first_use)
      d.emplace(*m);
    else if(again)
      d->clear_roi_vertices();
    if(what != Preprocess_case::preprocess)
      Method::insert(*d, s);
    const bool ok = d->preprocess();
    state.PauseTiming();
    d.reset();
    m.reset();
    if(!ok)
    {
      state.SkipWithError("preprocess failed");
      break;
    }
    state.ResumeTiming();
  }
  memory.report(state);
  report_factor(state);
  state.counters["vertices"] = double(num_vertices(base));
  state.counters["roi"] = double(s.roi.size());
}

template <class Deformer>
void record_split(const Deformer& d, double& local, double& rhs, double& solve, double& around)
{
  const LD::Deformation_result& r = d.last_result();
  local += r.local_step_seconds;
  rhs += r.right_hand_side_seconds;
  solve += r.solve_seconds;
  // the rest of the call: reading the ROI's positions, writing the solution, the warnings
  around += r.seconds - r.local_step_seconds - r.right_hand_side_seconds - r.solve_seconds;
}

template <class Method>
void BM_iteration(benchmark::State& state, int level, int roi_percent)
{
  const Mesh& base = armadillo(level);
  const Selection s = select(base, roi_percent);
  last_factor = Factor_record();
  const Memory_probe memory;
  Mesh m = base;
  typename Method::Deformer d(m);
  Method::insert(d, s);
  // the same work as CGAL's deform(1, 0.), which computes its energy only when given a tolerance:
  // ours computes no energy either (the positions are the same, bit for bit)
  if constexpr(Method::split)
    d.set_energy_tracking(false);
  if(!d.preprocess())
  {
    state.SkipWithError("preprocess failed");
    return;
  }
  for(vertex_descriptor v : s.handle)
  {
    const Kernel::Point_3& p = m.point(v);
    d.set_target_position(v, Kernel::Point_3(p.x(), p.y() + 0.05 * s.height, p.z()));
  }
  d.deform(1, 0.);                                 // the T = I start (ours), first solve (CGAL)
  double local = 0, rhs = 0, solve = 0, around = 0;
  for(auto _ : state)
  {
    d.deform(1, 0.);                              // local step + right-hand side + solve
    if constexpr(Method::split)
      record_split(d, local, rhs, solve, around);
  }
  if constexpr(Method::split)
  {
    state.counters["local_ms"] = benchmark::Counter(1e3 * local, benchmark::Counter::kAvgIterations);
    state.counters["rhs_ms"] = benchmark::Counter(1e3 * rhs, benchmark::Counter::kAvgIterations);
    state.counters["solve_ms"] = benchmark::Counter(1e3 * solve, benchmark::Counter::kAvgIterations);
    state.counters["around_ms"] = benchmark::Counter(1e3 * around, benchmark::Counter::kAvgIterations);
  }
  memory.report(state);
  report_factor(state);
  state.counters["vertices"] = double(num_vertices(base));
  state.counters["roi"] = double(s.roi.size());
}

template <class Method>
void register_method(const std::string& name, int level)
{
  for(int roi_percent : {98, 10, 1})
  {
    const std::string suffix = "/armadillo_loop" + std::to_string(level) + (roi_percent == 98 ? "/all_but_2pct" : roi_percent == 10 ? "/roi_10pct" : "/roi_1pct");
    auto* p = benchmark::RegisterBenchmark(("preprocess/" + name + suffix).c_str(), [=](benchmark::State& st) {
      BM_preprocess<Method>(st, level, roi_percent, Preprocess_case::preprocess);
    });
    auto* i = benchmark::RegisterBenchmark(("iteration/" + name + suffix).c_str(),
                                           [=](benchmark::State& st) { BM_iteration<Method>(st, level, roi_percent); });
    p->Unit(benchmark::kMillisecond);
    i->Unit(benchmark::kMillisecond);
    if(level > 0)   // one factorisation takes seconds: few repetitions
      p->Iterations(level > 1 ? 1 : 2);
    if(roi_percent < 98)   // a selection small against the mesh: what its first use costs
    {
      for(Preprocess_case what : {Preprocess_case::first_use, Preprocess_case::new_selection})
      {
        const std::string kind = what == Preprocess_case::first_use ? "first_use/" : "new_selection/";
        auto* b = benchmark::RegisterBenchmark((kind + name + suffix).c_str(), [=](benchmark::State& st) {
          BM_preprocess<Method>(st, level, roi_percent, what);
        });
        b->Unit(benchmark::kMillisecond);
        if(level > 0)   // as the preprocess case: the first call of its process at 416k
          b->Iterations(level > 1 ? 1 : 2);
      }
    }
    if(level > 1)   // at least 2 s of iterations (Google Benchmark's default, 0.5 s, timed one at 416k)
      i->MinTime(2.0);
  }
}

} // namespace

int main(int argc, char** argv)
{
  std::vector<int> levels = {0, 1};
  std::vector<char*> args;
  for(int i = 0; i < argc; ++i)
  {
    if(std::strncmp(argv[i], "--levels=", 9) == 0)
    {
      levels.clear();
      std::stringstream list(argv[i] + 9);
      for(std::string item; std::getline(list, item, ',');)
      {
        const int level = std::atoi(item.c_str());
        if(item.empty() || level < 0 || level > 3)
          return std::cerr << "error: --levels takes a comma-separated list of 0..3\n", 1;
        levels.push_back(level);
      }
    }
    else if(std::strcmp(argv[i], "--spatial_order") == 0)
      spatial_order = true;
    else
      args.push_back(argv[i]);
  }
  int count = int(args.size());
  benchmark::Initialize(&count, args.data());
  if(benchmark::ReportUnrecognizedArguments(count, args.data()))
    return 1;
  for(int threads : {1, 2})
    benchmark::RegisterBenchmark(("bandwidth/read_1GiB/threads:" + std::to_string(threads)).c_str(),
                                 [=](benchmark::State& st) { BM_read_bandwidth(st, threads); })
        ->Unit(benchmark::kMillisecond)->UseRealTime();
  benchmark::RegisterBenchmark("memory/first_touch_256MiB", BM_first_touch)->Unit(benchmark::kMillisecond)->UseRealTime();
#ifdef LAPLACIAN_DEFORMATION_BENCH_HAS_BLAS
  for(int n : {256, 2000})
    benchmark::RegisterBenchmark(("dgemm/" + std::to_string(n)).c_str(), [n](benchmark::State& st) { BM_dgemm(st, n); })
        ->Unit(benchmark::kMillisecond)->UseRealTime();
#endif
  for(int level : levels)
  {
    register_method<Ours<LD::Vertex_based_representation> >("vertex", level);
    register_method<Ours<LD::Edge_based_representation> >("edge", level);
    if(level == 0)    // the type-erased path, on the armadillo only
    {
      register_method<Ours_any<LD::Vertex_based_representation> >("vertex_any", level);
      register_method<Ours_any<LD::Edge_based_representation> >("edge_any", level);
    }
    register_method<Cgal_arap>("cgal_arap", level);
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
