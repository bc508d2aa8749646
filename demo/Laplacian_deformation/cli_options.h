// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// Internal header of the laplacian_deform command-line tool (not part of the package's API): the
// tool's types, everything its command line can say (Options, with the tools' defaults of
// tool_defaults.h) and its help text. The parser is cli_parse.h.

#ifndef LAPLACIAN_DEFORM_CLI_OPTIONS_H
#define LAPLACIAN_DEFORM_CLI_OPTIONS_H

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include "policy_names.h"
#include "tool_defaults.h"

#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace laplacian_deform {

namespace fs = std::filesystem;
namespace LD = CGAL::Laplacian_deformation;
namespace policy_names = Laplacian_deformation_policy_names;
namespace defaults = Laplacian_deformation_tool_defaults;

typedef CGAL::Simple_cartesian<double>               Kernel;
typedef Kernel::Point_3                              Point_3;
typedef CGAL::Surface_mesh<Point_3>                  Mesh;
typedef boost::graph_traits<Mesh>::vertex_descriptor vertex_descriptor;

/// exit codes of the tool
enum Exit_code { EXIT_OK = 0, EXIT_ERROR = 1, EXIT_USAGE = 2 };

/// the library's Default_solver_traits: CHOLMOD when the package target found it
inline const char* default_solver() { return defaults::solver(); }

/// everything the command line can say
struct Options
{
  // positional: MESH [SEL [DEF]]
  std::string mesh, selection, transform_file;
  // output
  std::string output, output_dir, report;
  bool force = false, triangulate = false, compare = false, quiet = false, help = false;
  std::string progress = "auto";    // auto (after about 1 s), always, never
  // method
  std::string representation = defaults::representation(), weights = defaults::weights(),
              transform = defaults::transform(), solver = defaults::solver();
  unsigned int iterations = defaults::iterations;
  std::string start = defaults::start();           // identity | rotation (Mesh_deformer::set_start)
  double rigidity = defaults::rigidity;            // Mesh_deformer::set_rigidity_weight
  double tolerance = defaults::tolerance;
  bool soft = false;
  double soft_weight = defaults::soft_weight;
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
"MESH is an .off, .obj or .ply file (read with the library's checked reader, which refuses\n"
"malformed or non-manifold input) or an .stl file; vertex ids are 0-based, in file order.\n"
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
"1 bad input or failed deformation, 2 bad command line.\n"
"On Linux with glibc the tool starts itself again with GLIBC_TUNABLES=glibc.malloc.hugetlb=1\n"
"(huge pages for its large blocks) unless GLIBC_TUNABLES is set or\n"
"CGAL_LAPLACIAN_DEFORMATION_HUGE_PAGES=0.\n";
}

} // namespace laplacian_deform

#endif // LAPLACIAN_DEFORM_CLI_OPTIONS_H
