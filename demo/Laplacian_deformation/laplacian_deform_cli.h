// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// Internal header of the laplacian_deform command-line tool (not part of the package's API):
// command-line parsing, loading and checking of a deformation task (mesh, selection, handle
// transformation), regions of interest around handles, output checks and atomic writes, the
// progress indicator and the per-run records. Shared by the tool and its GoogleTest suite.

#ifndef LAPLACIAN_DEFORM_CLI_H
#define LAPLACIAN_DEFORM_CLI_H

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Laplacian_deformation/Deformation_result.h>
#include <CGAL/Laplacian_deformation/IO/Botsch08.h>
#include <CGAL/Laplacian_deformation/metrics.h>

#include "policy_names.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <mutex>
#include <queue>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <unistd.h>

namespace laplacian_deform {

namespace fs = std::filesystem;
namespace LD = CGAL::Laplacian_deformation;
namespace policy_names = Laplacian_deformation_policy_names;

typedef CGAL::Simple_cartesian<double>               Kernel;
typedef Kernel::Point_3                              Point_3;
typedef CGAL::Surface_mesh<Point_3>                  Mesh;
typedef boost::graph_traits<Mesh>::vertex_descriptor vertex_descriptor;

/// exit codes of the tool
enum Exit_code { EXIT_OK = 0, EXIT_ERROR = 1, EXIT_USAGE = 2 };

/// everything the command line can say
// the library's Default_solver_traits: CHOLMOD when the package target found it
inline const char* default_solver()
{
#ifdef CGAL_LAPLACIAN_DEFORMATION_USE_CHOLMOD
  return "cholmod";
#else
  return "eigen";
#endif
}

struct Options
{
  // positional: MESH [SEL [DEF]]
  std::string mesh, selection, transform_file;
  // output
  std::string output, output_dir, report;
  bool force = false, triangulate = false, compare = false, quiet = false, help = false;
  std::string progress = "auto";    // auto (after about 1 s), always, never
  // method
  std::string representation = "edge", weights = "cotangent", transform = "sr1", solver = default_solver();
  unsigned int iterations = 4;
  std::string start = "identity";   // identity | rotation (Mesh_deformer::set_start)
  double rigidity = 0;              // Mesh_deformer::set_rigidity_weight
  double tolerance = 0;
  bool soft = false;
  double soft_weight = 1;
  unsigned int threads = 0;         // 0: the default (every core when TBB is available)
  // selection from the command line: --handle ids and ranges, as inclusive [first, last] pairs
  // (expanded only once the mesh is read and every id is known to exist)
  std::vector<std::pair<std::size_t, std::size_t>> handles;
  long roi_rings = -1;
  double roi_radius = -1;
  bool has_translate = false, has_rotate = false, has_center = false;
  std::array<double, 3> translate{{0, 0, 0}}, axis{{0, 0, 1}}, center{{0, 0, 0}};
  double angle_degrees = 0;
  std::vector<std::string> given;   // the options given, in order (for the report)

  /// the task is CGAL's cactus (no MESH) and both representations are compared
  bool main_job() const { return mesh.empty(); }
  bool comparing() const { return compare || main_job(); }
};

inline const char* usage_text()
{
  return
"usage: laplacian_deform [OPTIONS] [MESH [SEL [DEF]]]\n"
"\n"
"Deforms a triangle mesh with edge-based (or vertex-based) Laplacian deformation.\n"
"\n"
"  laplacian_deform                      the main job: CGAL's cactus with its Botsch08 selection and\n"
"                                        transform, vertex-based and edge-based S*R1, results and\n"
"                                        summary.txt in ./laplacian_deform_output (same as --compare)\n"
"  laplacian_deform MESH SEL DEF -o OUT  a Botsch08 task: SEL has one status per vertex (0 fixed,\n"
"                                        1 region of interest, 2 handle; '#' comments), DEF the 4x4\n"
"                                        affine handle transformation, row by row\n"
"  laplacian_deform MESH SEL --translate X,Y,Z [--rotate ...] -o OUT\n"
"  laplacian_deform MESH --handle IDS (--roi-rings K | --roi-radius R) [--translate X,Y,Z]\n"
"                        [--rotate AX,AY,AZ,DEG[,CX,CY,CZ]] -o OUT\n"
"  laplacian_deform --serve [MESH] [--port N] [--output DIR]\n"
"                                        the interactive editor in the browser, on 127.0.0.1\n"
"                                        (laplacian_deform --serve --help for its options)\n"
"\n"
"MESH is any file CGAL::IO::read_polygon_mesh reads (.off .obj .ply .stl); vertex ids are\n"
"0-based, in file order.\n"
"\n"
"Selection and handle motion:\n"
"  --handle IDS          handle vertices: ids and ranges, e.g. 12,40-45,300\n"
"  --roi-rings K         region of interest: the vertices at most K edges away from a handle\n"
"  --roi-radius R        region of interest: the vertices at distance at most R from a handle,\n"
"                        along mesh edges (Dijkstra over edge lengths, an upper bound of the\n"
"                        geodesic distance); the other vertices are fixed\n"
"  --translate X,Y,Z     translate the handles\n"
"  --rotate AX,AY,AZ,DEG[,CX,CY,CZ]\n"
"                        rotate the handles by DEG degrees about the axis (AX,AY,AZ) through\n"
"                        the centre C (default: the handles' centroid), before the translation\n"
"\n"
"Method:\n"
"  --representation edge|vertex        nodes at edge midpoints (default) or at vertices\n"
"  --weights cotangent|uniform         (default cotangent)\n"
"  --transform sr1|fixed|rotation|similarity|principal|rsr|anchored\n"
"                        per-node transform: the paper's S*R1 (default), identity, rotation,\n"
"                        rotation and isotropic scale, principal-axes S*R1, R2*S*R1, S*R1 with\n"
"                        its scales anchored at 1 (does not drift)\n"
"  --rigidity W          add rigidity rows of relative weight W on the node graph's spokes\n"
"                        (default 0; 0.3 keeps a twisted tube's radius, see the manual)\n"
"  --iterations N        iterations (default 4, the paper's 3 to 4)\n"
"  --start identity|rotation\n"
"                        first solve: T = I (default: plain Laplacian editing, then the\n"
"                        iterations), or the handles' rotation propagated by a harmonic field\n"
"                        (for large rotations: bends, twists)\n"
"  --tolerance X         stop when an iteration moves no vertex by more than X times the ROI's\n"
"                        bounding-box diagonal (default 0: run every iteration)\n"
"  --soft W              soft handle constraints of relative weight W (default: hard)\n"
"  --solver eigen|cholmod\n"
"                        sparse Cholesky: Eigen's simplicial LLT or CHOLMOD's supernodal one\n"
"                        (default: the library's default, CHOLMOD when built with it)\n"
"  --threads N           threads of the local step (TBB; default: every core)\n"
"\n"
"Output:\n"
"  -o, --output FILE     the deformed mesh, format from the extension (.off .obj .ply .stl);\n"
"                        default MESH's name with '_deformed' in the current folder\n"
"  --compare             run both representations, write both results and summary.txt into\n"
"                        --output-dir DIR (default ./laplacian_deform_output)\n"
"  --report FILE.json    write a JSON report\n"
"  --force               allow overwriting an input file\n"
"  --triangulate         triangulate non-triangle faces (otherwise they are an error)\n"
"  --progress auto|always|never   progress on stderr (auto: for runs longer than about 1 s)\n"
"  --quiet               no summary on stdout\n"
"  -h, --help            this help\n"
"\n"
"Files are written atomically (temporary file, then rename). Exit status: 0 success,\n"
"1 bad input or failed deformation, 2 bad command line.\n";
}

namespace detail {

inline bool parse_double(const std::string& text, double& value)
{
  if(text.empty())
    return false;
  std::size_t used = 0;
  try { value = std::stod(text, &used); } catch(...) { return false; }
  return used == text.size() && std::isfinite(value);
}

inline bool parse_unsigned(const std::string& text, unsigned long long& value)
{
  if(text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
    return false;
  try { value = std::stoull(text); } catch(...) { return false; }
  return true;
}

inline std::vector<std::string> split(const std::string& text, char separator)
{
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while(std::getline(in, part, separator))
    parts.push_back(part);
  if(!text.empty() && text.back() == separator)
    parts.push_back("");
  return parts;
}

inline bool parse_doubles(const std::string& text, std::vector<double>& values)
{
  values.clear();
  for(const std::string& part : split(text, ','))
  {
    double x;
    if(!parse_double(part, x))
      return false;
    values.push_back(x);
  }
  return true;
}

// "12,40-45,300" as the ranges [12, 12], [40, 45], [300, 300] (not expanded: a range is checked
// against the mesh's vertex count before it costs any memory)
inline bool parse_ids(const std::string& text, std::vector<std::pair<std::size_t, std::size_t>>& ranges)
{
  for(const std::string& part : split(text, ','))
  {
    const std::size_t dash = part.find('-');
    unsigned long long a, b;
    if(dash == std::string::npos)
    {
      if(!parse_unsigned(part, a))
        return false;
      b = a;
    }
    else if(!parse_unsigned(part.substr(0, dash), a) || !parse_unsigned(part.substr(dash + 1), b) || b < a)
      return false;
    ranges.emplace_back(std::size_t(a), std::size_t(b));
  }
  return true;
}

inline bool one_of(const std::string& value, std::initializer_list<const char*> choices)
{
  for(const char* c : choices)
    if(value == c)
      return true;
  return false;
}

} // namespace detail

/// Parses the arguments (without the program name). Returns `false` with a message in `error`
/// on a bad command line; checks only the command line, no file is opened.
inline bool parse_command_line(const std::vector<std::string>& args, Options& o, std::string& error)
{
  std::vector<std::string> positional;
  bool options_done = false;
  for(std::size_t i = 0; i < args.size(); ++i)
  {
    std::string arg = args[i];
    if(options_done || arg.empty() || arg[0] != '-' || arg == "-")
    {
      positional.push_back(arg);
      continue;
    }
    if(arg == "--")
    {
      options_done = true;
      continue;
    }
    std::string value;
    bool has_inline_value = false;
    if(arg.compare(0, 2, "--") == 0)
    {
      const std::size_t eq = arg.find('=');
      if(eq != std::string::npos)
      {
        value = arg.substr(eq + 1);
        arg = arg.substr(0, eq);
        has_inline_value = true;
      }
    }
    if(arg == "-o")
      arg = "--output";
    if(arg == "-h")
      arg = "--help";

    static const char* const flags[] = {"--help", "--force", "--triangulate", "--compare", "--quiet"};
    static const char* const valued[] = {"--output", "--output-dir", "--report", "--representation", "--weights",
                                         "--transform", "--start", "--rigidity", "--solver", "--iterations", "--tolerance", "--soft",
                                         "--threads", "--handle", "--roi-rings", "--roi-radius", "--translate",
                                         "--rotate", "--progress"};
    const bool is_flag = std::find_if(std::begin(flags), std::end(flags),
                                      [&](const char* f) { return arg == f; }) != std::end(flags);
    const bool is_valued = std::find_if(std::begin(valued), std::end(valued),
                                        [&](const char* f) { return arg == f; }) != std::end(valued);
    if(!is_flag && !is_valued)
    {
      error = "unknown option '" + args[i] + "' (see --help)";
      return false;
    }
    if(std::find(o.given.begin(), o.given.end(), arg) != o.given.end() && arg != "--handle")
    {
      error = "option " + arg + " is given twice";
      return false;
    }
    o.given.push_back(arg);
    if(is_flag)
    {
      if(has_inline_value)
      {
        error = "option " + arg + " takes no value";
        return false;
      }
      if(arg == "--help") o.help = true;
      else if(arg == "--force") o.force = true;
      else if(arg == "--triangulate") o.triangulate = true;
      else if(arg == "--compare") o.compare = true;
      else if(arg == "--quiet") o.quiet = true;
      continue;
    }
    if(!has_inline_value)
    {
      if(i + 1 >= args.size())
      {
        error = "option " + arg + " needs a value (see --help)";
        return false;
      }
      value = args[++i];
    }
    auto bad = [&](const std::string& expected) {
      error = "option " + arg + ": expected " + expected + ", got '" + value + "'";
      return false;
    };
    unsigned long long n = 0;
    double x = 0;
    std::vector<double> xs;
    if(arg == "--output") { if(value.empty()) return bad("a file name"); o.output = value; }
    else if(arg == "--output-dir") { if(value.empty()) return bad("a folder"); o.output_dir = value; }
    else if(arg == "--report") { if(value.empty()) return bad("a file name"); o.report = value; }
    else if(arg == "--representation")   // the names of policy_names.h, kept canonical
    {
      const auto* e = policy_names::find(policy_names::representations(), value);
      if(e == nullptr)
        return bad(policy_names::name_list(policy_names::representations()));
      o.representation = e->name;
    }
    else if(arg == "--weights")
    {
      const auto* e = policy_names::find(policy_names::weight_policies(), value);
      if(e == nullptr)
        return bad(policy_names::name_list(policy_names::weight_policies()));
      o.weights = e->name;
    }
    else if(arg == "--transform")
    {
      const auto* e = policy_names::find(policy_names::transform_policies(), value);
      if(e == nullptr)
        return bad(policy_names::name_list(policy_names::transform_policies()));
      o.transform = e->name;
    }
    else if(arg == "--start")
    {
      if(!detail::one_of(value, {"rotation", "identity"}))
      {
        return bad("rotation or identity");
      }
      o.start = value;
    }
    else if(arg == "--solver")
    {
      if(!detail::one_of(value, {"eigen", "cholmod"}))
      {
        return bad("eigen or cholmod");
      }
      o.solver = value;
    }
    else if(arg == "--progress")
    {
      if(!detail::one_of(value, {"auto", "always", "never"}))
      {
        return bad("auto, always or never");
      }
      o.progress = value;
    }
    else if(arg == "--iterations")
    {
      if(!detail::parse_unsigned(value, n) || n == 0 || n > 1000000)
      {
        return bad("a positive integer");
      }
      o.iterations = static_cast<unsigned int>(n);
    }
    else if(arg == "--threads")
    {
      if(!detail::parse_unsigned(value, n) || n == 0 || n > 4096)
      {
        return bad("a positive integer");
      }
      o.threads = static_cast<unsigned int>(n);
    }
    else if(arg == "--roi-rings")
    {
      if(!detail::parse_unsigned(value, n) || n > 1000000000)
      {
        return bad("a non-negative integer");
      }
      o.roi_rings = long(n);
    }
    else if(arg == "--tolerance")
    { if(!detail::parse_double(value, x) || x < 0) return bad("a non-negative number"); o.tolerance = x; }
    else if(arg == "--rigidity")
    {
      if(!detail::parse_double(value, x) || !(x >= 0) || !std::isfinite(x))
      {
        return bad("a non-negative finite number");
      }
      o.rigidity = x;
    }
    else if(arg == "--soft")
    { if(!detail::parse_double(value, x) || !(x > 0)) return bad("a positive number"); o.soft = true; o.soft_weight = x; }
    else if(arg == "--roi-radius")
    { if(!detail::parse_double(value, x) || !(x > 0)) return bad("a positive distance"); o.roi_radius = x; }
    else if(arg == "--handle")
    { if(!detail::parse_ids(value, o.handles)) return bad("vertex ids and ranges such as 12,40-45,300"); }
    else if(arg == "--translate")
    {
      if(!detail::parse_doubles(value, xs) || xs.size() != 3) return bad("three numbers X,Y,Z");
      o.has_translate = true;
      o.translate = {{xs[0], xs[1], xs[2]}};
    }
    else if(arg == "--rotate")
    {
      if(!detail::parse_doubles(value, xs) || (xs.size() != 4 && xs.size() != 7))
        return bad("AX,AY,AZ,DEGREES or AX,AY,AZ,DEGREES,CX,CY,CZ");
      if(xs[0] == 0 && xs[1] == 0 && xs[2] == 0)
        return bad("a non-zero rotation axis");
      o.has_rotate = true;
      o.axis = {{xs[0], xs[1], xs[2]}};
      o.angle_degrees = xs[3];
      o.has_center = xs.size() == 7;
      if(o.has_center)
        o.center = {{xs[4], xs[5], xs[6]}};
    }
  }
  if(o.help)
    return true;

  if(positional.size() > 3)
  {
    error = "too many arguments: '" + positional[3] + "' (expected MESH [SEL [DEF]])";
    return false;
  }
  if(positional.size() > 0) o.mesh = positional[0];
  if(positional.size() > 1) o.selection = positional[1];
  if(positional.size() > 2) o.transform_file = positional[2];

  auto given = [&](const char* name) { return std::find(o.given.begin(), o.given.end(), name) != o.given.end(); };
  auto conflict = [&](const std::string& message) { error = message; return false; };
  const bool cli_selection = given("--handle") || given("--roi-rings") || given("--roi-radius");
  const bool cli_motion = o.has_translate || o.has_rotate;
  if(o.main_job())
  {
    if(cli_selection || cli_motion)
      return conflict("--handle, --roi-*, --translate and --rotate need a MESH");
    if(given("--triangulate"))
      return conflict("--triangulate needs a MESH (the default task is CGAL's cactus)");
  }
  if(o.comparing())
  {
    if(given("--representation"))
      return conflict(o.main_job() ? "without MESH the tool compares both representations: --representation does not apply"
                                   : "--compare runs both representations: --representation does not apply");
    if(given("--output"))
      return conflict(o.main_job() ? "without MESH the tool writes a comparison: use --output-dir DIR, not --output"
                                   : "--compare writes a folder: use --output-dir DIR, not --output");
  }
  else if(given("--output-dir"))
    return conflict("--output-dir applies to --compare (and to the default task); use --output FILE");
  if(!o.main_job())
  {
    if(!o.transform_file.empty() && cli_motion)
      return conflict("the handle transformation comes from " + o.transform_file + ": do not also give --translate or --rotate");
    if(!o.selection.empty() && cli_selection)
      return conflict("the selection comes from " + o.selection + ": do not also give --handle or --roi-*");
    if(o.selection.empty())
    {
      if(o.handles.empty())
        return conflict("no handle: give a selection file (MESH SEL DEF) or --handle IDS with --roi-rings K or --roi-radius R");
      if(given("--roi-rings") == given("--roi-radius"))
        return conflict("give the region of interest around the handles: one of --roi-rings K or --roi-radius R");
    }
    if(!o.selection.empty() && o.transform_file.empty() && !cli_motion)
      return conflict("no handle motion: give DEF (MESH SEL DEF) or --translate / --rotate");
  }
  return true;
}

/// the kind of a file, from its extension (lower case, without the dot)
inline std::string extension_of(const fs::path& p)
{
  std::string e = p.extension().string();
  if(!e.empty())
    e = e.substr(1);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return e;
}

inline bool is_mesh_extension(const std::string& e) { return detail::one_of(e, {"off", "obj", "ply", "stl"}); }

inline std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

/// a deformation task: the rest mesh, the status of every vertex and the handle transformation
struct Task
{
  fs::path mesh_file, selection_file, transform_file;
  Mesh mesh;
  std::size_t triangulated_faces = 0;        // faces that --triangulate split
  std::vector<int> status;                   // LD::IO::Botsch08_status per vertex index
  Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();
  // --rotate: the handles' rotation as given (so that the rotation-aware start keeps its winding)
  bool has_rotation = false;
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d rotation_center = Eigen::Vector3d::Zero(), translation = Eigen::Vector3d::Zero();
  std::string selection_description, motion_description;

  std::size_t count(int s) const { return std::size_t(std::count(status.begin(), status.end(), s)); }
};

/// In a text mesh file (OFF, OBJ, ASCII PLY), the first token that reads as a number but is NaN or
/// infinite ("nan", "inf", "1e999"), as "line N: the coordinate 'TOKEN' is not a finite number"
/// (the token quoted with non-printable bytes escaped, cut after 40 bytes); empty if there is none
/// or the file is binary.
inline std::string non_finite_number_in(const fs::path& file)
{
  const std::string ext = extension_of(file);
  if(!detail::one_of(ext, {"off", "obj", "ply"}))
    return "";
  std::ifstream in(file, std::ios::binary);
  std::string line, token;
  for(std::size_t number = 1; std::getline(in, line); ++number)
  {
    if(ext == "ply" && line.compare(0, 7, "format ") == 0 && line.compare(0, 12, "format ascii") != 0)
      return "";
    const std::size_t first = line.find_first_not_of(" \t\r");
    if(first == std::string::npos || line[first] == '#' || line.compare(first, 7, "comment") == 0)
      continue;
    std::istringstream tokens(line);
    while(tokens >> token)
    {
      char* end = nullptr;
      const double x = std::strtod(token.c_str(), &end);
      if(end != token.c_str() && *end == '\0' && !std::isfinite(x))
        return "line " + std::to_string(number) + ": the coordinate " + LD::IO::internal::quoted_excerpt(token) +
               " is not a finite number";
    }
  }
  return "";
}

/// reads a mesh; refuses non-triangle faces unless `triangulate`
inline bool read_mesh(const fs::path& file, bool triangulate, Mesh& mesh, std::size_t& triangulated, std::string& error)
{
  std::error_code ec;
  if(!fs::exists(file, ec))
    return error = "cannot open " + quoted(file) + ": no such file", false;
  if(!fs::is_regular_file(file, ec))
    return error = "cannot read a mesh from " + quoted(file) + ": not a regular file", false;
  const std::string ext = extension_of(file);
  if(!is_mesh_extension(ext))
    return error = "cannot read a mesh from " + quoted(file) + ": unknown extension '" + ext +
                   "' (expected .off, .obj, .ply or .stl)", false;
  {
    std::ifstream probe(file, std::ios::binary);
    if(!probe)
      return error = "cannot open " + quoted(file) + ": permission denied or unreadable", false;
  }
  mesh.clear();
  const bool read = CGAL::IO::read_polygon_mesh(file.string(), mesh);
  bool finite = true;
  for(vertex_descriptor v : vertices(mesh))
    finite = finite && std::isfinite(mesh.point(v).x()) && std::isfinite(mesh.point(v).y()) &&
             std::isfinite(mesh.point(v).z());
  if(!read || !finite)
  {
    // NaN or infinite coordinates are a common cause: name the line and the value
    const std::string non_finite = non_finite_number_in(file);
    if(!non_finite.empty())
      return error = "cannot read a mesh from " + quoted(file) + ": " + non_finite +
                     " (NaN and infinite coordinates cannot be deformed)", false;
    if(!finite)
      return error = "cannot read a mesh from " + quoted(file) + ": a vertex has a NaN or infinite coordinate", false;
    return error = "cannot read a mesh from " + quoted(file) + ": not a valid " + ext +
                   " polygon mesh (malformed file, or faces that do not form a manifold mesh)", false;
  }
  if(is_empty(mesh) || num_faces(mesh) == 0)
    return error = "the mesh " + quoted(file) + " has no face", false;
  std::size_t non_triangles = 0;
  for(auto f : faces(mesh))
    if(CGAL::halfedges_around_face(halfedge(f, mesh), mesh).size() != 3)
      ++non_triangles;
  triangulated = 0;
  if(non_triangles > 0)
  {
    if(!triangulate)
      return error = "the mesh " + quoted(file) + " has " + std::to_string(non_triangles) + " non-triangle face" +
                     (non_triangles > 1 ? "s" : "") + " (of " + std::to_string(num_faces(mesh)) +
                     "); the deformation needs triangles: pass --triangulate to split them with "
                     "CGAL::Polygon_mesh_processing::triangulate_faces", false;
    if(!CGAL::Polygon_mesh_processing::triangulate_faces(mesh) || !CGAL::is_triangle_mesh(mesh))
      return error = "could not triangulate every face of " + quoted(file), false;
    triangulated = non_triangles;
  }
  return true;
}

/// the vertices at most `rings` edges away from `sources` (breadth-first)
inline std::vector<bool> k_ring_region(const Mesh& mesh, const std::vector<std::size_t>& sources, std::size_t rings)
{
  std::vector<std::size_t> depth(num_vertices(mesh), std::numeric_limits<std::size_t>::max());
  std::vector<std::size_t> queue;
  for(std::size_t s : sources)
    if(depth[s] != 0)
    {
      depth[s] = 0;
      queue.push_back(s);
    }
  for(std::size_t next = 0; next < queue.size(); ++next)
  {
    const std::size_t v = queue[next];
    if(depth[v] == rings)
      continue;
    for(vertex_descriptor w : vertices_around_target(halfedge(vertex_descriptor(Mesh::size_type(v)), mesh), mesh))
      if(depth[w] == std::numeric_limits<std::size_t>::max())
      {
        depth[w] = depth[v] + 1;
        queue.push_back(std::size_t(w));
      }
  }
  std::vector<bool> in(depth.size());
  for(std::size_t v = 0; v < depth.size(); ++v)
    in[v] = depth[v] != std::numeric_limits<std::size_t>::max();
  return in;
}

/// the vertices at distance at most `radius` from `sources` along mesh edges (Dijkstra)
inline std::vector<bool> radius_region(const Mesh& mesh, const std::vector<std::size_t>& sources, double radius)
{
  const double infinity = std::numeric_limits<double>::infinity();
  std::vector<double> distance(num_vertices(mesh), infinity);
  typedef std::pair<double, std::size_t> Entry;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for(std::size_t s : sources)
  {
    distance[s] = 0;
    queue.push(Entry(0., s));
  }
  while(!queue.empty())
  {
    const Entry top = queue.top();
    queue.pop();
    const std::size_t v = top.second;
    if(top.first > distance[v])
      continue;
    const vertex_descriptor vd(static_cast<Mesh::size_type>(v));
    for(vertex_descriptor w : vertices_around_target(halfedge(vd, mesh), mesh))
    {
      const double d = top.first + std::sqrt(CGAL::squared_distance(mesh.point(vd), mesh.point(w)));
      if(d <= radius && d < distance[w])
      {
        distance[w] = d;
        queue.push(Entry(d, std::size_t(w)));
      }
    }
  }
  std::vector<bool> in(distance.size());
  for(std::size_t v = 0; v < distance.size(); ++v)
    in[v] = distance[v] <= radius;
  return in;
}

/// the affine map of --rotate (about the centre) followed by --translate
inline Eigen::Matrix4d motion_matrix(const Options& o, const Eigen::Vector3d& default_center)
{
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  if(o.has_rotate)
  {
    const Eigen::Vector3d axis = Eigen::Vector3d(o.axis[0], o.axis[1], o.axis[2]).normalized();
    const Eigen::Matrix3d r = Eigen::AngleAxisd(o.angle_degrees * 3.14159265358979323846 / 180., axis).toRotationMatrix();
    const Eigen::Vector3d c = o.has_center ? Eigen::Vector3d(o.center[0], o.center[1], o.center[2]) : default_center;
    m.topLeftCorner<3, 3>() = r;
    m.topRightCorner<3, 1>() = c - r * c;
  }
  if(o.has_translate)
    m.topRightCorner<3, 1>() += Eigen::Vector3d(o.translate[0], o.translate[1], o.translate[2]);
  return m;
}

/// Loads the task the options describe (the cactus when no MESH is given). Returns `false`
/// with a message in `error` on any bad input.
inline bool load_task(const Options& o, const fs::path& data_dir, Task& task, std::string& error)
{
  task.mesh_file = o.main_job() ? data_dir / "cactus.off" : fs::path(o.mesh);
  task.selection_file = o.main_job() ? data_dir / "cactus.sel" : fs::path(o.selection);
  task.transform_file = o.main_job() ? data_dir / "cactus.def" : fs::path(o.transform_file);
  if(o.main_job() && !fs::exists(task.mesh_file))
    return error = "the default task needs CGAL's cactus in " + quoted(data_dir) +
                   ": run scripts/setup.sh (it unpacks the data from Debian's libcgal-demo)", false;
  if(!read_mesh(task.mesh_file, o.triangulate, task.mesh, task.triangulated_faces, error))
    return false;
  const std::size_t n = num_vertices(task.mesh);

  if(!task.selection_file.empty())
  {
    std::ifstream in(task.selection_file);
    if(!in)
      return error = "cannot open the selection " + quoted(task.selection_file) +
                     (fs::exists(task.selection_file) ? "" : ": no such file"), false;
    std::string why;
    if(!LD::IO::read_botsch08_selection(in, task.status, why, n))
      return error = "bad selection " + quoted(task.selection_file) + ": " + why, false;
    task.selection_description = task.selection_file.string();
  }
  else
  {
    std::vector<std::size_t> handles;
    for(const std::pair<std::size_t, std::size_t>& range : o.handles)
      if(range.second >= n)
        return error = "handle vertex " + std::to_string(range.second) + " does not exist: the mesh has " +
                       std::to_string(n) + " vertices (ids 0 to " + std::to_string(n - 1) + ")", false;
    for(const std::pair<std::size_t, std::size_t>& range : o.handles)
      for(std::size_t h = range.first; h <= range.second; ++h)
        handles.push_back(h);
    const std::vector<bool> roi = o.roi_rings >= 0 ? k_ring_region(task.mesh, handles, std::size_t(o.roi_rings))
                                                   : radius_region(task.mesh, handles, o.roi_radius);
    task.status.assign(n, LD::IO::BOTSCH08_FIXED);
    for(std::size_t v = 0; v < n; ++v)
      if(roi[v])
        task.status[v] = LD::IO::BOTSCH08_REGION_OF_INTEREST;
    for(std::size_t h : handles)
      task.status[h] = LD::IO::BOTSCH08_HANDLE;
    std::ostringstream d;
    d << handles.size() << " handle id" << (handles.size() > 1 ? "s" : "") << ", ";
    if(o.roi_rings >= 0)
      d << o.roi_rings << "-ring region of interest";
    else
      d << "region of interest within distance " << o.roi_radius << " along edges";
    task.selection_description = d.str();
  }
  if(task.count(LD::IO::BOTSCH08_HANDLE) == 0)
    return error = "the selection " + quoted(task.selection_file) + " has no handle vertex (status 2)", false;

  if(!task.transform_file.empty())
  {
    std::ifstream in(task.transform_file);
    if(!in)
      return error = "cannot open the handle transformation " + quoted(task.transform_file) +
                     (fs::exists(task.transform_file) ? "" : ": no such file"), false;
    std::string why;
    if(!LD::IO::read_botsch08_transform(in, task.transform, why))
      return error = "bad handle transformation " + quoted(task.transform_file) + ": " + why, false;
    task.motion_description = task.transform_file.string();
  }
  else
  {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for(std::size_t v = 0; v < n; ++v)
      if(task.status[v] == LD::IO::BOTSCH08_HANDLE)
      {
        const Point_3& p = task.mesh.point(vertex_descriptor(Mesh::size_type(v)));
        centroid += Eigen::Vector3d(p.x(), p.y(), p.z());
      }
    centroid /= double(task.count(LD::IO::BOTSCH08_HANDLE));
    task.transform = motion_matrix(o, centroid);
    if(o.has_rotate)
    {
      task.has_rotation = true;
      task.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(o.angle_degrees * 3.14159265358979323846 / 180.,
                                         Eigen::Vector3d(o.axis[0], o.axis[1], o.axis[2]).normalized()));
      task.rotation_center = o.has_center ? Eigen::Vector3d(o.center[0], o.center[1], o.center[2]) : centroid;
      if(o.has_translate)
        task.translation = Eigen::Vector3d(o.translate[0], o.translate[1], o.translate[2]);
    }
    std::ostringstream d;
    d.precision(6);
    if(o.has_rotate)
      d << "rotate " << o.angle_degrees << " deg about (" << o.axis[0] << ", " << o.axis[1] << ", " << o.axis[2] << ")";
    if(o.has_rotate && o.has_translate)
      d << ", then ";
    if(o.has_translate)
      d << "translate (" << o.translate[0] << ", " << o.translate[1] << ", " << o.translate[2] << ")";
    task.motion_description = d.str();
  }
  return true;
}

/// whether `a` and `b` name the same file (existing or not)
inline bool same_file(const fs::path& a, const fs::path& b)
{
  std::error_code ec1, ec2;
  if(fs::exists(a, ec1) && fs::exists(b, ec2))
    return fs::equivalent(a, b, ec1);
  return fs::weakly_canonical(a, ec1) == fs::weakly_canonical(b, ec2);
}

/// Checks that every output can be written and overwrites no input (unless `force`).
inline bool check_outputs(const std::vector<fs::path>& outputs, const std::vector<fs::path>& inputs, bool force,
                          std::string& error)
{
  for(std::size_t i = 0; i < outputs.size(); ++i)
  {
    const fs::path& out = outputs[i];
    for(const fs::path& in : inputs)
      if(!in.empty() && !force && same_file(out, in))
        return error = "the output " + quoted(out) + " is the input " + quoted(in) +
                       ": refusing to overwrite it (pass --force to allow it)", false;
    for(std::size_t j = 0; j < i; ++j)
      if(same_file(out, outputs[j]))
        return error = "two outputs are the same file " + quoted(out), false;
    std::error_code ec;
    if(fs::is_directory(out, ec))
      return error = "the output " + quoted(out) + " is a folder", false;
    const fs::path parent = out.parent_path().empty() ? fs::path(".") : out.parent_path();
    if(!fs::is_directory(parent, ec))
      return error = "cannot write " + quoted(out) + ": the folder " + quoted(parent) + " does not exist", false;
  }
  return true;
}

/// Writes through a temporary file in the same folder, then renames it: a reader never sees a
/// half-written file and a failure leaves no output. `write(path)` writes the temporary file.
inline bool write_atomically(const fs::path& path, const std::function<bool(const fs::path&)>& write,
                             std::string& error)
{
  const fs::path tmp = path.parent_path() /
      (".tmp." + std::to_string(::getpid()) + "." + path.filename().string());
  std::error_code ec;
  if(!write(tmp))
  {
    fs::remove(tmp, ec);
    return error = "cannot write " + quoted(path), false;
  }
  fs::rename(tmp, path, ec);
  if(ec)
  {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    return error = "cannot rename the temporary file to " + quoted(path) + ": " + ec.message(), false;
  }
  return true;
}

inline bool write_mesh_atomically(const fs::path& path, const Mesh& mesh, std::string& error)
{
  return write_atomically(path, [&](const fs::path& tmp) {
    return CGAL::IO::write_polygon_mesh(tmp.string(), mesh, CGAL::parameters::stream_precision(17));
  }, error);
}

inline bool write_text_atomically(const fs::path& path, const std::string& text, std::string& error)
{
  return write_atomically(path, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    out.close();
    return bool(out);
  }, error);
}

/// Progress on stderr: a stage ("preprocessing", "iteration 2/4") shown once the run is longer
/// than `delay` seconds. On a terminal one line is refreshed with the elapsed time; otherwise
/// one line is printed per stage.
class Progress
{
public:
  Progress(bool enabled, double delay, std::ostream& out = std::cerr)
    : m_enabled(enabled), m_delay(delay), m_out(out), m_tty(enabled && ::isatty(2)),
      m_start(std::chrono::steady_clock::now())
  {
    if(m_enabled)
      m_thread = std::thread([this] { loop(); });
  }
  ~Progress() { stop(); }
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void stage(const std::string& text)
  {
    if(!m_enabled)
      return;
    std::lock_guard<std::mutex> lock(m_mutex);
    m_stage = text;
    m_shown = false;
    if(elapsed() >= m_delay)
      show();
  }
  /// clears the progress line; call before printing anything else
  void stop()
  {
    if(!m_enabled)
      return;
    {
      std::lock_guard<std::mutex> lock(m_mutex);
      m_done = true;
    }
    m_wake.notify_all();
    if(m_thread.joinable())
      m_thread.join();
    std::lock_guard<std::mutex> lock(m_mutex);
    if(m_tty && m_line_open)
      m_out << '\r' << std::string(m_width, ' ') << '\r' << std::flush;
    m_line_open = false;
    m_enabled = false;
  }

private:
  double elapsed() const
  { return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count(); }
  void show()   // with the mutex held
  {
    std::ostringstream line;
    line.setf(std::ios::fixed);
    line.precision(1);
    line << "laplacian_deform: " << m_stage << " (" << elapsed() << " s)";
    if(m_tty)
    {
      std::string text = line.str();
      m_width = (std::max)(m_width, text.size());
      text.resize(m_width, ' ');
      m_out << '\r' << text << std::flush;
      m_line_open = true;
    }
    else if(!m_shown)
      m_out << line.str() << std::endl;
    m_shown = true;
  }
  void loop()
  {
    std::unique_lock<std::mutex> lock(m_mutex);
    while(!m_done)
    {
      m_wake.wait_for(lock, std::chrono::milliseconds(200));
      if(!m_done && !m_stage.empty() && elapsed() >= m_delay && (m_tty || !m_shown))
        show();
    }
  }

  bool m_enabled;
  double m_delay;
  std::ostream& m_out;
  bool m_tty;
  std::chrono::steady_clock::time_point m_start;
  std::mutex m_mutex;
  std::condition_variable m_wake;
  std::thread m_thread;
  std::string m_stage;
  bool m_done = false, m_shown = false, m_line_open = false;
  std::size_t m_width = 0;
};

/// one iteration of a run
struct Iteration_record
{
  double seconds = 0, local_step_seconds = 0, right_hand_side_seconds = 0, solve_seconds = 0;
  double energy = 0, change = 0;
};

/// one deformation of the task with one set of policies
struct Run_record
{
  std::string representation, weights, transform, solver;
  bool ok = false;
  std::string status, message;
  double preprocess_seconds = 0, deform_seconds = 0;
  std::size_t row_nodes = 0, factorizations = 0;
  std::vector<Iteration_record> iterations;
  double energy = 0, last_change = 0, max_constraint_residual = 0, max_handle_distance = 0;
  LD::Deformation_quality quality;     // metrics.h, over the non-fixed vertices
  std::vector<LD::Deformation_warning> warnings;   // of the last deform() call
  Mesh mesh;
  std::string name() const { return representation + "-based"; }
};

/// the quality metrics of metrics.h over the non-fixed vertices (region of interest and handles),
/// and the largest distance between a handle and its target
inline void measure(const Task& task, Run_record& run)
{
  std::vector<vertex_descriptor> region;
  for(vertex_descriptor v : vertices(task.mesh))
    if(task.status[v] != LD::IO::BOTSCH08_FIXED)
      region.push_back(v);
  // run.mesh is a copy of task.mesh: same vertex indices, so the task's points are the rest map
  run.quality = LD::deformation_quality(run.mesh, get(CGAL::vertex_point, task.mesh), region);
  run.max_handle_distance = 0;
  for(vertex_descriptor v : vertices(task.mesh))
    if(task.status[v] == LD::IO::BOTSCH08_HANDLE)
    {
      const Point_3& p = task.mesh.point(v);
      const Eigen::Vector4d t = task.transform * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.);
      run.max_handle_distance = (std::max)(run.max_handle_distance,
                                           std::sqrt(CGAL::squared_distance(run.mesh.point(v), Point_3(t.x(), t.y(), t.z()))));
    }
}

inline const char* status_name(LD::Deformation_status s)
{
  switch(s)
  {
    case LD::SUCCESS: return "SUCCESS";
    case LD::EMPTY_REGION_OF_INTEREST: return "EMPTY_REGION_OF_INTEREST";
    case LD::UNANCHORED_REGION: return "UNANCHORED_REGION";
    case LD::FACTORIZATION_FAILED: return "FACTORIZATION_FAILED";
    case LD::SOLVE_FAILED: return "SOLVE_FAILED";
    case LD::NON_FINITE_INPUT: return "NON_FINITE_INPUT";
    case LD::NON_FINITE_RESULT: return "NON_FINITE_RESULT";
    case LD::INVALID_PARAMETER: return "INVALID_PARAMETER";
    case LD::TOPOLOGY_CHANGED: return "TOPOLOGY_CHANGED";
    case LD::INVALID_MESH: return "INVALID_MESH";
  }
  return "UNKNOWN";
}

inline const char* warning_name(LD::Deformation_warning_kind k) { return LD::warning_kind_name(k); }

inline const char* transform_label(const std::string& t)
{
  const auto* e = policy_names::find(policy_names::transform_policies(), t);
  return e ? e->label : "unknown";
}

} // namespace laplacian_deform

#endif // LAPLACIAN_DEFORM_CLI_H
