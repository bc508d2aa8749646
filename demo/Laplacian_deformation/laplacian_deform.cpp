// laplacian_deform: the package's command-line tool (see laplacian_deform --help).
//
//   laplacian_deform                      the main job: CGAL's cactus (data unpacked by scripts/setup.sh)
//                                         with its Botsch08 selection and transform, vertex-based and
//                                         edge-based S*R1, both results and summary.txt written into
//                                         ./laplacian_deform_output
//   laplacian_deform MESH SEL DEF -o OUT  a Botsch08 task, any mesh CGAL reads (OFF, OBJ, PLY, STL)
//   laplacian_deform MESH --handle IDS --roi-rings K --translate X,Y,Z -o OUT
#include "laplacian_deform_run.h"

#include <nlohmann/json.hpp>

#ifdef CGAL_LINKED_WITH_TBB
#include <tbb/global_control.h>
#endif

#include <cstdlib>
#if defined(__linux__)
#include <unistd.h>
#endif
#include <iomanip>
#include <memory>

using namespace laplacian_deform;

namespace {

const char* const program = "laplacian_deform";

int fail(std::ostream& err, int code, const std::string& message)
{
  err << program << ": error: " << message << std::endl;
  if(code == EXIT_USAGE)
    err << "usage: " << program << " [OPTIONS] [MESH [SEL [DEF]]]   (see --help)" << std::endl;
  return code;
}

std::string method_line(const Options& o, const std::string& representation, unsigned int threads)
{
  std::ostringstream s;
  s << (representation.empty() ? std::string("vertex- and edge-based") : representation + "-based") << ", "
    << o.weights << " weights, " << transform_label(o.transform) << " transforms, " << o.start << " start, ";
  if(o.rigidity > 0)
    s << "rigidity rows (weight " << o.rigidity << "), ";
  if(o.soft)
    s << "soft constraints (weight " << o.soft_weight << "), ";
  else
    s << "hard constraints, ";
  s << o.solver << " solver, " << o.iterations << " iteration" << (o.iterations > 1 ? "s" : "") << " at most, tolerance "
    << o.tolerance << ", " << threads << " thread" << (threads > 1 ? "s" : "");
  return s.str();
}

std::string task_lines(const Task& task)
{
  std::ostringstream s;
  s << "mesh        " << task.mesh_file.string() << ": " << num_vertices(task.mesh) << " vertices, "
    << num_edges(task.mesh) << " edges, " << num_faces(task.mesh) << " faces";
  if(task.triangulated_faces > 0)
    s << " (" << task.triangulated_faces << " non-triangle faces triangulated)";
  s << "\nselection   " << task.selection_description << ": " << task.count(LD::IO::BOTSCH08_REGION_OF_INTEREST)
    << " free, " << task.count(LD::IO::BOTSCH08_HANDLE) << " handle, " << task.count(LD::IO::BOTSCH08_FIXED)
    << " fixed vertices\nmotion      " << task.motion_description << '\n';
  return s.str();
}

// one run, as a human-readable block
std::string run_lines(const Run_record& r)
{
  std::ostringstream s;
  s << std::setprecision(4);
  s << "preprocess  " << r.preprocess_seconds << " s (" << r.row_nodes << " rows)\n";
  for(std::size_t k = 0; k < r.iterations.size(); ++k)
    s << "iteration " << std::setw(2) << std::left << k + 1 << std::right << r.iterations[k].seconds
      << " s, energy " << r.iterations[k].energy << ", change " << r.iterations[k].change << '\n';
  s << "result      " << r.iterations.size() << " iteration" << (r.iterations.size() == 1 ? "" : "s") << " in "
    << r.deform_seconds << " s, energy " << r.energy << ", largest handle distance to target "
    << r.max_handle_distance << '\n';
  const LD::Deformation_quality& q = r.quality;
  s << "quality     over the deformed region (metrics.h): edge-length change mean " << q.mean_edge_length_distortion
    << ", max " << q.max_edge_length_distortion << "; dihedral change (deg) mean " << q.mean_dihedral_angle_change
    << ", max " << q.max_dihedral_angle_change << "; normal deviation after the best one-ring rotation (deg) mean "
    << q.mean_normal_deviation << ", max " << q.max_normal_deviation << "; Laplacian error vertex "
    << q.vertex_laplacian_error << ", edge " << q.edge_laplacian_error << "; ARAP energy " << q.arap_energy << '\n';
  return s.str();
}

// the warnings of a run (a success whose result looks wrong), one line each
std::string warning_lines(const Run_record& r, bool name_the_run)
{
  std::ostringstream s;
  for(const LD::Deformation_warning& w : r.warnings)
    s << "warning     " << (name_the_run ? r.name() + ": " : std::string()) << warning_name(w.kind) << ": "
      << w.message << '\n';
  return s.str();
}

// the side-by-side table of a comparison
std::string comparison_table(const Run_record runs[2])
{
  std::ostringstream s;
  s << std::setprecision(4) << std::left;
  s << std::setw(20) << "" << std::setw(14) << runs[0].name() << runs[1].name() << '\n';
  auto row = [&](const std::string& label, auto get) {
    s << std::setw(20) << label << std::setw(14) << get(runs[0]) << get(runs[1]) << '\n';
  };
  row("rows", [](const Run_record& r) { return r.row_nodes; });
  row("preprocess s", [](const Run_record& r) { return r.preprocess_seconds; });
  const std::size_t n = (std::max)(runs[0].iterations.size(), runs[1].iterations.size());
  for(std::size_t k = 0; k < n; ++k)
    row("iteration " + std::to_string(k + 1) + " s", [k](const Run_record& r) {
      return k < r.iterations.size() ? std::to_string(r.iterations[k].seconds).substr(0, 8) : std::string("-");
    });
  row("deform s", [](const Run_record& r) { return r.deform_seconds; });
  row("iterations", [](const Run_record& r) { return r.iterations.size(); });
  row("energy", [](const Run_record& r) { return r.energy; });
  row("handle distance", [](const Run_record& r) { return r.max_handle_distance; });
  row("edge dist mean", [](const Run_record& r) { return r.quality.mean_edge_length_distortion; });
  row("edge dist max", [](const Run_record& r) { return r.quality.max_edge_length_distortion; });
  row("dihedral mean deg", [](const Run_record& r) { return r.quality.mean_dihedral_angle_change; });
  row("dihedral max deg", [](const Run_record& r) { return r.quality.max_dihedral_angle_change; });
  row("normal mean deg", [](const Run_record& r) { return r.quality.mean_normal_deviation; });
  row("normal max deg", [](const Run_record& r) { return r.quality.max_normal_deviation; });
  row("Laplacian err (v)", [](const Run_record& r) { return r.quality.vertex_laplacian_error; });
  row("Laplacian err (e)", [](const Run_record& r) { return r.quality.edge_laplacian_error; });
  row("ARAP energy", [](const Run_record& r) { return r.quality.arap_energy; });
  return s.str();
}

nlohmann::json run_json(const Run_record& r)
{
  nlohmann::json warnings = nlohmann::json::array();
  for(const LD::Deformation_warning& w : r.warnings)
    warnings.push_back({{"kind", warning_name(w.kind)}, {"count", w.count}, {"message", w.message}});
  nlohmann::json iterations = nlohmann::json::array();
  for(const Iteration_record& it : r.iterations)
    iterations.push_back({{"seconds", it.seconds}, {"local_step_seconds", it.local_step_seconds},
                          {"right_hand_side_seconds", it.right_hand_side_seconds},
                          {"solve_seconds", it.solve_seconds}, {"energy", it.energy}, {"change", it.change}});
  return {{"representation", r.representation}, {"weights", r.weights}, {"transform", r.transform},
          {"solver", r.solver}, {"status", r.status}, {"rows", r.row_nodes},
          {"preprocess_seconds", r.preprocess_seconds}, {"deform_seconds", r.deform_seconds},
          {"iterations", iterations}, {"energy", r.energy}, {"last_change", r.last_change},
          {"max_constraint_residual", r.max_constraint_residual}, {"max_handle_distance", r.max_handle_distance},
          {"quality", {{"vertex_laplacian_error", r.quality.vertex_laplacian_error},
                       {"edge_laplacian_error", r.quality.edge_laplacian_error},
                       {"edge_length_distortion", {{"mean", r.quality.mean_edge_length_distortion},
                                                   {"max", r.quality.max_edge_length_distortion}}},
                       {"dihedral_angle_change_degrees", {{"mean", r.quality.mean_dihedral_angle_change},
                                                          {"max", r.quality.max_dihedral_angle_change}}},
                       {"normal_deviation_degrees", {{"mean", r.quality.mean_normal_deviation},
                                                     {"max", r.quality.max_normal_deviation}}},
                       {"arap_energy", r.quality.arap_energy}}},
          {"warnings", warnings}};
}

int run_tool(const std::vector<std::string>& args, std::ostream& out, std::ostream& err)
{
  Options o;
  std::string error;
  if(!parse_command_line(args, o, error))
    return fail(err, EXIT_USAGE, error);
  if(o.help)
  {
    out << usage_text();
    return EXIT_OK;
  }
#ifndef CGAL_LAPLACIAN_DEFORMATION_HAS_CHOLMOD
  if(o.solver == "cholmod")
    return fail(err, EXIT_USAGE, "this build has no CHOLMOD (SuiteSparse was not found): use --solver eigen");
#endif
  unsigned int threads = 1;
#ifdef CGAL_LINKED_WITH_TBB
  std::unique_ptr<tbb::global_control> thread_limit;
  if(o.threads > 0)
    thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, o.threads);
  threads = unsigned(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
#else
  if(o.threads > 1)
    return fail(err, EXIT_USAGE, "this build has no TBB: only --threads 1 is supported");
#endif

  // the outputs, checked before any work
  const fs::path mesh_file = o.main_job() ? fs::path(LAPLACIAN_DEFORMATION_DATA_DIR) / "cactus.off" : fs::path(o.mesh);
  const std::string stem = mesh_file.stem().string();
  const std::vector<fs::path> inputs = {mesh_file, o.selection, o.transform_file};
  fs::path output, output_dir;
  std::vector<fs::path> outputs;
  if(o.comparing())
  {
    output_dir = o.output_dir.empty() ? fs::path(defaults::output_dir()) : fs::path(o.output_dir);
    std::error_code ec;
    if(fs::exists(output_dir, ec) && !fs::is_directory(output_dir, ec))
      return fail(err, EXIT_ERROR, "the output folder " + quoted(output_dir) + " is a file");
    for(const char* name : {"_vertex-based.off", "_edge-based.off"})
      outputs.push_back(output_dir / (stem + name));
    outputs.push_back(output_dir / "summary.txt");
    if(!fs::exists(output_dir, ec))   // created after the deformation: only the inputs can clash
      for(const fs::path& p : outputs)
        for(const fs::path& in : inputs)
          if(!in.empty() && !o.force && same_file(p, in))
            return fail(err, EXIT_ERROR, "the output " + quoted(p) + " is the input " + quoted(in) +
                                         ": refusing to overwrite it (pass --force to allow it)");
  }
  else
  {
    output = o.output.empty() ? fs::path(stem + "_deformed" + mesh_file.extension().string()) : fs::path(o.output);
    if(!is_mesh_extension(extension_of(output)))
      return fail(err, EXIT_USAGE, "cannot write a mesh to " + quoted(output) + ": unknown extension '" +
                                   extension_of(output) + "' (expected .off, .obj, .ply or .stl)");
    outputs.push_back(output);
  }
  if(!o.report.empty())
    outputs.push_back(o.report);
  {
    std::vector<fs::path> checked;
    std::error_code ec;
    for(const fs::path& p : outputs)
      if(!(o.comparing() && p.parent_path() == output_dir && !fs::exists(output_dir, ec)))
        checked.push_back(p);
    if(!check_outputs(checked, inputs, o.force, error))
      return fail(err, EXIT_ERROR, error);
  }

  Progress progress(o.progress != "never", o.progress == "always" ? 0. : 1., err);
  progress.stage("reading " + mesh_file.string());
  Task task;
  if(!load_task(o, LAPLACIAN_DEFORMATION_DATA_DIR, task, error))
  {
    progress.stop();
    return fail(err, EXIT_ERROR, error);
  }

  std::vector<Run_record> runs(o.comparing() ? 2 : 1);
  for(std::size_t k = 0; k < runs.size(); ++k)
  {
    Run_record& r = runs[k];
    r.representation = o.comparing() ? (k == 0 ? "vertex" : "edge") : o.representation;
    r.weights = o.weights;
    r.transform = o.transform;
    r.solver = o.solver;
    run_deformation(task, o, r, progress);
    if(!r.ok)
    {
      progress.stop();
      return fail(err, EXIT_ERROR, "the " + r.name() + " deformation failed (" + r.status + "): " + r.message +
                                   "; nothing was written");
    }
  }

  // the human summary
  std::ostringstream summary;
  summary << task_lines(task) << "method      " << method_line(o, o.comparing() ? "" : o.representation, threads) << '\n';
  if(o.comparing())
    summary << '\n' << comparison_table(runs.data());
  else
    summary << run_lines(runs[0]);
  for(const Run_record& r : runs)
    summary << warning_lines(r, o.comparing());

  // the JSON report
  nlohmann::json report;
  if(!o.report.empty())
  {
    nlohmann::json js_runs = nlohmann::json::array();
    for(const Run_record& r : runs)
      js_runs.push_back(run_json(r));
    std::vector<std::string> written;
    for(const fs::path& p : outputs)
      if(p != fs::path(o.report))
        written.push_back(p.string());
    report = {{"tool", program},
              {"mesh", {{"file", task.mesh_file.string()}, {"vertices", num_vertices(task.mesh)},
                        {"edges", num_edges(task.mesh)}, {"faces", num_faces(task.mesh)},
                        {"triangulated_faces", task.triangulated_faces}}},
              {"selection", {{"source", task.selection_description},
                             {"free", task.count(LD::IO::BOTSCH08_REGION_OF_INTEREST)},
                             {"handles", task.count(LD::IO::BOTSCH08_HANDLE)},
                             {"fixed", task.count(LD::IO::BOTSCH08_FIXED)}}},
              {"motion", {{"source", task.motion_description}, {"matrix", {
                  {task.transform(0, 0), task.transform(0, 1), task.transform(0, 2), task.transform(0, 3)},
                  {task.transform(1, 0), task.transform(1, 1), task.transform(1, 2), task.transform(1, 3)},
                  {task.transform(2, 0), task.transform(2, 1), task.transform(2, 2), task.transform(2, 3)},
                  {task.transform(3, 0), task.transform(3, 1), task.transform(3, 2), task.transform(3, 3)}}}}},
              {"options", {{"weights", o.weights}, {"transform", o.transform}, {"start", o.start}, {"rigidity", o.rigidity}, {"solver", o.solver},
                           {"iterations", o.iterations}, {"tolerance", o.tolerance},
                           {"constraints", o.soft ? "soft" : "hard"}, {"soft_weight", o.soft ? o.soft_weight : 0.},
                           {"threads", threads}}},
              {"runs", js_runs},
              {"outputs", written},
              // what the process ran with (the tool sets GLIBC_TUNABLES for itself: see main())
              {"environment", {{"GLIBC_TUNABLES", std::getenv("GLIBC_TUNABLES") ? std::getenv("GLIBC_TUNABLES") : ""}}}};
  }

  // the outputs, each written atomically
  progress.stage("writing the results");
  if(o.comparing())
  {
    std::error_code ec;
    fs::create_directories(output_dir, ec);
    if(ec)
    {
      progress.stop();
      return fail(err, EXIT_ERROR, "cannot create the folder " + quoted(output_dir) + ": " + ec.message());
    }
  }
  std::vector<fs::path> done;
  auto undo = [&] {
    std::error_code ignored;
    for(const fs::path& p : done)
      fs::remove(p, ignored);
  };
  for(std::size_t k = 0; k < runs.size(); ++k)
  {
    if(!write_mesh_atomically(outputs[k], runs[k].mesh, error))
    {
      undo();
      progress.stop();
      return fail(err, EXIT_ERROR, error);
    }
    done.push_back(outputs[k]);
    summary << "wrote       " << outputs[k].string() << '\n';
  }
  if(!o.report.empty())
    summary << "report      " << o.report << '\n';
  if(o.comparing())
  {
    if(!write_text_atomically(outputs[2], summary.str(), error))
    {
      undo();
      progress.stop();
      return fail(err, EXIT_ERROR, error);
    }
    done.push_back(outputs[2]);
  }
  if(!o.report.empty() && !write_text_atomically(o.report, report.dump(2) + "\n", error))
  {
    undo();
    progress.stop();
    return fail(err, EXIT_ERROR, error);
  }
  progress.stop();
  // the warnings also on the standard error, even with --quiet: the run succeeded, but its result
  // probably is not what was meant
  for(const Run_record& r : runs)
    for(const LD::Deformation_warning& w : r.warnings)
      err << program << ": warning: " << (o.comparing() ? r.name() + ": " : std::string()) << w.message << std::endl;
  if(!o.quiet)
  {
    out << summary.str();
    if(o.comparing())
      out << "summary in  " << outputs[2].string() << '\n';
    out << std::flush;
  }
  return EXIT_OK;
}

} // namespace

int laplacian_deform_serve(int argc, char** argv);   // laplacian_deform_serve.cpp

namespace {
// On Linux with glibc, the tool starts itself again (same arguments) with
// GLIBC_TUNABLES=glibc.malloc.hugetlb=1 when that variable is not set: the C library then asks
// for transparent huge pages for every large block of the process (glibc 2.35 or later; older
// ones ignore the tunable). A fresh 4 KiB page costs a page fault when it is first written, and a
// big mesh's preprocess writes hundreds of MB (see the manual's "First touch and huge pages").
// Nothing is restarted when GLIBC_TUNABLES is set (the user's choice is kept) or when
// CGAL_LAPLACIAN_DEFORMATION_HUGE_PAGES=0; if the restart fails, the tool runs as it is.
void restart_with_huge_pages(char** argv)
{
#if defined(__linux__) && defined(__GLIBC__)
  const char* off = std::getenv("CGAL_LAPLACIAN_DEFORMATION_HUGE_PAGES");
  if(std::getenv("GLIBC_TUNABLES") != nullptr || (off != nullptr && std::string(off) == "0"))
    return;
  if(setenv("GLIBC_TUNABLES", "glibc.malloc.hugetlb=1", 1) != 0)
    return;
  execv("/proc/self/exe", argv);
  unsetenv("GLIBC_TUNABLES");   // not restarted: run without it
#else
  (void)argv;
#endif
}
} // namespace

int main(int argc, char** argv)
{
  restart_with_huge_pages(argv);
  try
  {
    // laplacian_deform --serve [MESH] [--port N] [--output DIR]: the browser editor
    if(argc >= 2 && std::string(argv[1]) == "--serve")
      return laplacian_deform_serve(argc, argv);
    return run_tool(std::vector<std::string>(argv + 1, argv + argc), std::cout, std::cerr);
  }
  catch(const std::exception& e)
  {
    return fail(std::cerr, EXIT_ERROR, std::string("unexpected failure: ") + e.what());
  }
}
