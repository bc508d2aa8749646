// compare_deformations: the comparison harness. Runs every task with every representation x
// weights x transform combination of Mesh_deformer, each with both starts (IDENTITY_START and
// ROTATION_START, a run-time choice: Mesh_deformer::set_start()), and, on the same task (ROI,
// handle, targets), CGAL's Surface_mesh_deformation (ORIGINAL_ARAP, SPOKES_AND_RIMS, SRE_ARAP),
// all with the same number of iterations and tolerance 0; measures the quality metrics of
// metrics.h, the task metrics of deformation_task.h (bend, twist, volume change) and the timings;
// writes OUT/results.csv, OUT/results.md and, per task, OUT/<task>/{rest,vertex,edge,cgal_arap}.ply
// (with a per-vertex `distortion`; vertex and edge: cotangent weights, S*R1, identity start, the
// library's defaults) and task.json.
//
//   compare_deformations [--iterations N] [--data DIR] OUT TASK_FILE...
//   compare_deformations --convergence N [--data DIR] OUT TASK_FILE...
//
// --convergence N: instead, runs N iterations of every cotangent combination of ours (vertex and
// edge x every transform x both starts) and CGAL's three variants, and writes the task metrics
// after every iteration 1..N into OUT/convergence.csv (results.csv is not touched).
//
// Each run is executed in a forked child process so that its peak memory can be measured: the
// child reports VmHWM (the resident-set high-water mark of /proc/self/status) at the end of the
// run, and the extra memory over its resident set at the start of the run (after fork the child
// shares the parent's pages, so the extra is what the run itself allocated and touched).
// The methods of the comparison are in harness_methods.h, the tasks in deformation_task.h.
#include "harness_methods.h"
#include "tool_files.h"
#include "viewer_files.h"

#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
namespace tools = Laplacian_deformation_tools;
using namespace Laplacian_deformation_benchmark;   // the tasks and the methods (harness_methods.h)

namespace {

double status_megabytes(const char* key)
{
  std::ifstream in("/proc/self/status");
  std::string line;
  while(std::getline(in, line))
    if(line.compare(0, std::strlen(key), key) == 0)
      return std::atof(line.c_str() + std::strlen(key)) / 1024.;   // kB
  return 0;
}

// runs `method` in a child process; the child writes the PLY of a default combination
Record run_in_child(const Method& method, const Task& task, unsigned iterations, const fs::path& task_dir)
{
  Record r;
  int fds[2];
  if(pipe(fds) != 0)
    return set_message(r, "pipe() failed"), r;
  std::cout.flush();
  std::cerr.flush();
  const pid_t pid = fork();
  if(pid < 0)
    return set_message(r, "fork() failed"), r;
  if(pid == 0)
  {
    close(fds[0]);
    Record c;
    const double baseline = status_megabytes("VmRSS:");
    Mesh m;
    c.ok = method.run(task, iterations, m, c, Step()) ? 1 : 0;
    c.peak_rss_mb = status_megabytes("VmHWM:");
    c.extra_rss_mb = c.peak_rss_mb - baseline;
    if(c.ok)
    {
      c.quality = LD::deformation_quality(m, get(CGAL::vertex_point, task.mesh), task.roi);
      std::vector<std::pair<vertex_descriptor, Point_3> > controls;
      for(std::size_t i = 0; i < task.handle.size(); ++i)
        controls.emplace_back(task.handle[i], task.targets[i]);
      c.quality.max_constraint_residual = LD::constraint_residual(m, get(CGAL::vertex_point, task.mesh), controls);
      c.metrics = task_metrics(task, m);
      if(c.iterations)
      {
        c.iteration_seconds /= c.iterations;
        c.local_step_seconds /= c.iterations;
        c.right_hand_side_seconds /= c.iterations;
        c.solve_seconds /= c.iterations;
      }
      if(!method.panel.empty())
      {
        std::vector<double> field(num_vertices(m), 0.);
        LD::vertex_distortion_field(m, get(CGAL::vertex_point, task.mesh), CGAL::make_property_map(field));
        if(!laplacian_deform::write_viewer_ply(task_dir / (method.panel + ".ply"), m, field))
          c.ok = 0, set_message(c, "cannot write " + (task_dir / (method.panel + ".ply")).string());
      }
    }
    const char* p = reinterpret_cast<const char*>(&c);
    std::size_t left = sizeof(c);
    while(left > 0)
    {
      const ssize_t n = write(fds[1], p, left);
      if(n <= 0)
        break;
      p += n;
      left -= std::size_t(n);
    }
    close(fds[1]);
    _exit(0);
  }
  close(fds[1]);
  char* p = reinterpret_cast<char*>(&r);
  std::size_t got = 0;
  while(got < sizeof(r))
  {
    const ssize_t n = read(fds[0], p + got, sizeof(r) - got);
    if(n <= 0)
      break;
    got += std::size_t(n);
  }
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if(got != sizeof(r))
  {
    r = Record();
    set_message(r, WIFSIGNALED(status) ? "the run crashed (signal " + std::to_string(WTERMSIG(status)) + ")"
                                       : std::string("the run reported nothing"));
  }
  return r;
}

std::string fixed(double x, int digits)
{
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << x;
  return s.str();
}

std::string general(double x)
{
  std::ostringstream s;
  s << std::setprecision(3) << x;
  return s.str();
}

// a CSV cell: empty for NaN (a metric that does not apply)
std::string cell(double x)
{
  if(x != x)
    return std::string();
  std::ostringstream s;
  s << std::setprecision(6) << x;
  return s.str();
}

const char* const task_metric_columns =
    "bend_arc_error,bend_min_turn_deg,twist_mid_deg,twist_ideal_deg,twist_mid_radius_ratio,volume_change";

std::string task_metric_cells(const Task_metrics& t)
{
  return cell(t.bend_arc_error) + ',' + cell(t.bend_min_turn_deg) + ',' + cell(t.twist_mid_deg) + ',' +
         cell(t.twist_ideal_deg) + ',' + cell(t.twist_mid_radius_ratio) + ',' + cell(t.volume_change);
}

// --convergence: the task metrics after every iteration of the cotangent combinations and CGAL's
int run_convergence(unsigned iterations, const fs::path& out_dir, const std::vector<Task>& tasks)
{
  std::ostringstream csv;   // written atomically at the end (tool_files.h)
  csv << "task,method,representation,weights,transform,start,iteration,status," << task_metric_columns << '\n';
  for(const Task& task : tasks)
    for(const Method& method : all_methods())
    {
      if(method.method == "ours" && method.weights != "cotangent")
        continue;
      std::cerr << task.name << " (convergence): " << method.method << " " << method.representation << " "
                << method.transform << " " << method.start << std::endl;
      const std::string prefix = task.name + ',' + method.method + ',' + method.representation + ',' + method.weights +
                                 ',' + method.transform + ',' + (method.method == "ours" ? method.start : "-") + ',';
      Mesh m;
      Record r;
      const bool ok = method.run(task, iterations, m, r, [&](unsigned it, const Mesh& deformed) {
        csv << prefix << it << ",ok," << task_metric_cells(task_metrics(task, deformed)) << '\n';
      });
      if(!ok)
      {
        csv << prefix << r.iterations + 1 << ",failed," << task_metric_cells(Task_metrics()) << '\n';
        std::cerr << "  failed: " << r.message << std::endl;
      }
    }
  std::string error;
  if(!tools::write_text_atomically(out_dir / "convergence.csv", csv.str(), error))
    return std::cerr << "error: " << error << std::endl, EXIT_FAILURE;
  std::cout << "wrote " << (out_dir / "convergence.csv").string() << std::endl;
  return EXIT_SUCCESS;
}

int usage(std::ostream& out, int code)
{
  out << "usage: compare_deformations [--iterations N] [--data DIR] OUT TASK_FILE...\n"
         "       compare_deformations --convergence N [--data DIR] OUT TASK_FILE...\n"
         "  Runs every task (benchmark/Laplacian_deformation/tasks/*.task) with every representation x\n"
         "  weights x transform of Mesh_deformer, each with the identity and the rotation start, and CGAL's\n"
         "  Surface_mesh_deformation (ORIGINAL_ARAP, SPOKES_AND_RIMS, SRE_ARAP), N iterations each (default\n"
         "  10) with tolerance 0, and writes OUT/results.csv, OUT/results.md and\n"
         "  OUT/<task>/{rest,vertex,edge,cgal_arap}.ply + task.json.\n"
         "  --convergence N: the task metrics (bend, twist, volume change) after every iteration 1..N of\n"
         "  every cotangent combination of ours with both starts and of CGAL's three variants, into\n"
         "  OUT/convergence.csv (nothing else is written).\n"
         "  DIR: the folder of the real meshes (default: the one configured at build time).\n";
  return code;
}

} // namespace

int main(int argc, char** argv)
{
  unsigned iterations = defaults::comparison_iterations, convergence = 0;
  std::string data_dir = LAPLACIAN_DEFORMATION_DATA_DIR;
  std::vector<std::string> positional;
  for(int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if(a == "--help" || a == "-h")
      return usage(std::cout, EXIT_SUCCESS);
    if(a == "--iterations" && i + 1 < argc)
    {
      const int n = std::atoi(argv[++i]);
      if(n <= 0)
        return std::cerr << "error: --iterations needs a positive number\n", EXIT_FAILURE;
      iterations = unsigned(n);
    }
    else if(a == "--convergence" && i + 1 < argc)
    {
      const int n = std::atoi(argv[++i]);
      if(n <= 0)
        return std::cerr << "error: --convergence needs a positive number\n", EXIT_FAILURE;
      convergence = unsigned(n);
    }
    else if(a == "--data" && i + 1 < argc)
      data_dir = argv[++i];
    else if(!a.empty() && a[0] == '-')
      return usage(std::cerr, EXIT_FAILURE);
    else
      positional.push_back(a);
  }
  if(positional.size() < 2)
    return usage(std::cerr, EXIT_FAILURE);
  const fs::path out_dir = positional[0];

  // read every task first: a bad task file stops the harness before anything is written
  std::vector<Task> tasks(positional.size() - 1);
  for(std::size_t t = 0; t + 1 < positional.size(); ++t)
  {
    std::string error;
    if(!read_task(positional[t + 1], data_dir, tasks[t], error))
      return std::cerr << "error: " << error << std::endl, EXIT_FAILURE;
  }
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if(ec)
    return std::cerr << "error: cannot create " << out_dir << ": " << ec.message() << std::endl, EXIT_FAILURE;
  if(convergence)
    return run_convergence(convergence, out_dir, tasks);

  const std::vector<Method> methods = all_methods();
  std::ostringstream csv, md;   // written atomically at the end (tool_files.h)
  csv << "task,vertices,roi,handle,method,representation,weights,transform,start,status,iterations,"
         "preprocess_s,iteration_s,local_step_s,right_hand_side_s,solve_s,peak_rss_mb,extra_rss_mb,"
         "vertex_laplacian_error,edge_laplacian_error,edge_length_mean,edge_length_max,"
         "dihedral_change_mean_deg,dihedral_change_max_deg,normal_deviation_mean_deg,normal_deviation_max_deg,"
         "arap_energy,constraint_residual," << task_metric_columns << "\n";
  csv << std::setprecision(6);
  md << "# Deformation comparison\n\n"
     << "Every task with every representation x weights x transform of `Mesh_deformer` (hard constraints), each "
        "with the identity and the rotation start (`set_start()`; `fixed` keeps T = I and ignores it), and "
        "CGAL's `Surface_mesh_deformation` (ORIGINAL_ARAP, SPOKES_AND_RIMS, SRE_ARAP; its default solver), "
     << iterations << " iterations each with tolerance 0 (our `deform(1, 0)` / CGAL's `deform(1, 0)` called "
     << iterations << " times), each run in its own forked process.\n\n"
     << "Columns: prep = `preprocess()` (ms); iter = mean wall time of one iteration (ms), split for ours into "
        "local step / right-hand side / solve; peak = VmHWM of the run's process (MB) and, in parentheses, its "
        "growth during the run; Lv, Le = relative vertex- and edge-based Laplacian-coordinate errors; edge = "
        "edge-length distortion mean / max; dihedral = dihedral-angle change mean / max (degrees); normal = "
        "face-normal deviation after each 1-ring's best rotation mean / max (degrees); ARAP = normalised "
        "cotangent ARAP energy; res = constraint residual / bounding-box diagonal (see metrics.h); task metrics "
        "(deformation_task.h), where they apply: arc err = largest distance of the ring centroids from the ideal "
        "arc (tube radii), min turn = smallest signed turn of the centreline (degrees, negative: an S), twist = "
        "mid-slice twist angle (degrees; ideal in the heading), r ratio = mid-slice radius deformed / rest, "
        "dV = relative volume change (closed meshes).\n";

  for(const Task& task : tasks)
  {
    const fs::path task_dir = out_dir / task.name;
    fs::create_directories(task_dir, ec);
    {
      std::vector<double> zero(num_vertices(task.mesh), 0.);
      std::string error;
      if(!laplacian_deform::write_viewer_ply(task_dir / "rest.ply", task.mesh, zero) ||
         !tools::write_text_atomically(task_dir / "task.json",
                                       laplacian_deform::task_json(task.name, task.title, {"rest", "vertex", "edge", "cgal_arap"}),
                                       error))
        std::cerr << "error: cannot write the figure files of " << task_dir.string() << std::endl;
    }
    const bool bend = task.bend_axis >= 0, twist = task.twist_axis >= 0, closed = CGAL::is_closed(task.mesh);
    md << "\n## " << task.title << " (`" << task.name << "`)\n\n"
       << "Mesh `" << task.mesh_description << "`: " << num_vertices(task.mesh) << " vertices, ROI "
       << task.roi.size() << " vertices, handle " << task.handle.size() << " vertices"
       << (twist ? "; ideal mid-slice twist " + fixed(task.twist_ideal, 1) + " degrees" : std::string()) << ".\n\n"
       << "| method | weights | transform | start | prep ms | iter ms (local / rhs / solve) | peak MB | Lv | Le | edge | dihedral | normal | ARAP | res |"
       << (bend ? " arc err | min turn |" : "") << (twist ? " twist | r ratio |" : "") << (closed ? " dV |" : "") << "\n"
       << "|---|---|---|---|---:|---|---:|---:|---:|---|---|---|---:|---:|" << (bend ? "---:|---:|" : "")
       << (twist ? "---:|---:|" : "") << (closed ? "---:|" : "") << "\n";
    for(const Method& method : methods)
    {
      std::cerr << task.name << ": " << method.method << " " << method.representation << " " << method.weights << " "
                << method.transform << " " << method.start << std::endl;
      const Record r = run_in_child(method, task, iterations, task_dir);
      const LD::Deformation_quality& q = r.quality;
      csv << task.name << ',' << num_vertices(task.mesh) << ',' << task.roi.size() << ',' << task.handle.size() << ','
          << method.method << ',' << method.representation << ',' << method.weights << ',' << method.transform << ','
          << (method.method == "ours" ? method.start : "-") << ',' << (r.ok ? "ok" : "failed") << ',' << r.iterations << ',' << r.preprocess_seconds << ',' << r.iteration_seconds
          << ',';
      if(method.method == "ours")
        csv << r.local_step_seconds << ',' << r.right_hand_side_seconds << ',' << r.solve_seconds << ',';
      else
        csv << ",,,";
      csv << r.peak_rss_mb << ',' << r.extra_rss_mb << ',' << q.vertex_laplacian_error << ',' << q.edge_laplacian_error
          << ',' << q.mean_edge_length_distortion << ',' << q.max_edge_length_distortion << ','
          << q.mean_dihedral_angle_change << ',' << q.max_dihedral_angle_change << ',' << q.mean_normal_deviation << ','
          << q.max_normal_deviation << ',' << q.arap_energy << ',' << q.max_constraint_residual << ','
          << task_metric_cells(r.ok ? r.metrics : Task_metrics()) << '\n';
      const std::string name = method.method == "cgal" ? "CGAL" : method.representation;
      md << "| " << name << " | " << (method.method == "cgal" ? "cotangent" : method.weights) << " | "
         << method.transform << " | " << (method.method == "ours" ? method.start : "-") << " | ";
      if(!r.ok)
      {
        md << "failed: " << r.message << " | | | | | | | | | |" << (bend ? " | |" : "") << (twist ? " | |" : "")
           << (closed ? " |" : "") << "\n";
        std::cerr << "  failed: " << r.message << std::endl;
        continue;
      }
      md << fixed(1e3 * r.preprocess_seconds, 1) << " | " << fixed(1e3 * r.iteration_seconds, 2);
      if(method.method == "ours")
        md << " (" << fixed(1e3 * r.local_step_seconds, 2) << " / " << fixed(1e3 * r.right_hand_side_seconds, 2) << " / "
           << fixed(1e3 * r.solve_seconds, 2) << ")";
      md << " | " << fixed(r.peak_rss_mb, 0) << " (+" << fixed(r.extra_rss_mb, 0) << ") | "
         << general(q.vertex_laplacian_error) << " | " << general(q.edge_laplacian_error) << " | "
         << general(q.mean_edge_length_distortion) << " / " << general(q.max_edge_length_distortion) << " | "
         << fixed(q.mean_dihedral_angle_change, 2) << " / " << fixed(q.max_dihedral_angle_change, 1) << " | "
         << fixed(q.mean_normal_deviation, 2) << " / " << fixed(q.max_normal_deviation, 1) << " | "
         << general(q.arap_energy) << " | " << general(q.max_constraint_residual) << " |";
      const Task_metrics& t = r.metrics;
      if(bend)
        md << ' ' << fixed(t.bend_arc_error, 3) << " | " << fixed(t.bend_min_turn_deg, 2) << " |";
      if(twist)
        md << ' ' << fixed(t.twist_mid_deg, 2) << " | " << fixed(t.twist_mid_radius_ratio, 3) << " |";
      if(closed)
        md << ' ' << general(t.volume_change) << " |";
      md << "\n";
    }
  }
  std::string error;
  if(!tools::write_text_atomically(out_dir / "results.csv", csv.str(), error) ||
     !tools::write_text_atomically(out_dir / "results.md", md.str(), error))
    return std::cerr << "error: cannot write the results into " << out_dir << ": " << error << std::endl, EXIT_FAILURE;
  std::cout << "wrote " << (out_dir / "results.csv").string() << " and " << (out_dir / "results.md").string() << std::endl;
  return EXIT_SUCCESS;
}
