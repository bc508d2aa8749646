// The laplacian_deform command-line tool: its parser and task helpers in-process, and the real
// binary end to end (the cactus task reproduces the library exactly; every bad use gets a clear
// message, a non-zero exit and no output file).
#include "test_helpers.h"

#include "laplacian_deform_cli.h"

#include "policy_names.h"
#include "tool_mesh_io.h"
#include "tool_regions.h"
// the editor server's reader and k-ring (deformation_server/session.h, requests.h), to check that
// the tools share them
#include "deformation_server/session.h"

#include <CGAL/Laplacian_deformation/Mesh_deformer.h>
#include <CGAL/Laplacian_deformation/Vertex_based_representation.h>
#include <CGAL/Laplacian_deformation/Uniform_weights.h>
#include <CGAL/Laplacian_deformation/Anchored_scaled_rotation_transform.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#ifndef LAPLACIAN_DEFORM_TOOL
#error "LAPLACIAN_DEFORM_TOOL must be defined (by CMake) as the path of the laplacian_deform binary"
#endif

namespace {

namespace fs = std::filesystem;
namespace LD = CGAL::Laplacian_deformation;
namespace cli = laplacian_deform;
using namespace Laplacian_deformation_test;

// ---------------------------------------------------------------------------------------------
// The parser, in-process

bool parse(const std::vector<std::string>& args, cli::Options& o, std::string& error)
{
  o = cli::Options();
  error.clear();
  return cli::parse_command_line(args, o, error);
}

std::string parse_error(const std::vector<std::string>& args)
{
  cli::Options o;
  std::string error;
  EXPECT_FALSE(parse(args, o, error));
  return error;
}

TEST(LaplacianDeformCli, HandleRangesAreNotExpandedWhenParsed)
{
  // a range is kept as a range until the mesh is read: "0-18446744073709551615" used to be
  // expanded at parse time (bad_alloc, or 4 GB for 0-300000000 before the ids were refused)
  cli::Options o;
  std::string error;
  ASSERT_TRUE(parse({"m.off", "--handle", "0-18446744073709551615,7", "--roi-rings", "1", "--translate", "0,0,1"},
                    o, error)) << error;
  EXPECT_EQ(o.handles, (std::vector<std::pair<std::size_t, std::size_t>>{{0, std::size_t(-1)}, {7, 7}}));
}

TEST(LaplacianDeformCli, ParsesEveryOption)
{
  cli::Options o;
  std::string error;
  ASSERT_TRUE(parse({"m.off", "--handle", "3,5-7", "--handle=9", "--roi-rings", "4", "--translate", "1,-2,3e-1",
                     "--rotate", "0,0,1,90,1,2,3", "--representation", "vertex", "--weights=uniform",
                     "--transform", "similarity", "--start", "rotation", "--rigidity", "0.3", "--iterations", "7", "--tolerance", "1e-5", "--soft", "10",
                     "--solver", "cholmod", "--threads", "2", "-o", "out.obj", "--report", "r.json", "--force",
                     "--triangulate", "--progress", "never", "--quiet"}, o, error)) << error;
  EXPECT_EQ(o.mesh, "m.off");
  EXPECT_EQ(o.handles, (std::vector<std::pair<std::size_t, std::size_t>>{{3, 3}, {5, 7}, {9, 9}}));
  EXPECT_EQ(o.roi_rings, 4);
  EXPECT_TRUE(o.has_translate);
  EXPECT_EQ(o.translate[2], 0.3);
  EXPECT_TRUE(o.has_rotate && o.has_center);
  EXPECT_EQ(o.angle_degrees, 90.);
  EXPECT_EQ(o.start, "rotation");
  EXPECT_EQ(o.rigidity, 0.3);
  EXPECT_EQ(o.center[1], 2.);
  EXPECT_EQ(o.representation, "vertex");
  EXPECT_EQ(o.weights, "uniform");
  EXPECT_EQ(o.transform, "similarity");
  EXPECT_EQ(o.iterations, 7u);
  EXPECT_EQ(o.tolerance, 1e-5);
  EXPECT_TRUE(o.soft);
  EXPECT_EQ(o.soft_weight, 10.);
  EXPECT_EQ(o.solver, "cholmod");
  EXPECT_EQ(o.threads, 2u);
  EXPECT_EQ(o.output, "out.obj");
  EXPECT_EQ(o.report, "r.json");
  EXPECT_TRUE(o.force && o.triangulate && o.quiet);
  EXPECT_EQ(o.progress, "never");
  EXPECT_FALSE(o.comparing());

  ASSERT_TRUE(parse({}, o, error)) << error;
  EXPECT_TRUE(o.main_job() && o.comparing());
  EXPECT_EQ(o.iterations, 4u);
  EXPECT_EQ(o.tolerance, 0.);
  EXPECT_EQ(o.transform, "sr1");
  ASSERT_TRUE(parse({"--help"}, o, error));
  EXPECT_TRUE(o.help);
  ASSERT_TRUE(parse({"m.off", "s.sel", "d.def", "--compare", "--output-dir", "d"}, o, error)) << error;
  EXPECT_TRUE(o.comparing() && !o.main_job());
  ASSERT_TRUE(parse({"m.off", "s.sel", "--rotate", "1,0,0,30"}, o, error)) << error;
  EXPECT_FALSE(o.has_center);
}

// The one catalogue of policy names (policy_names.h): every name resolves to its policy, and the
// command line accepts exactly its names (the editor's server and the harness resolve the same
// table: test_server checks the server's side).
TEST(PolicyNames, OneTableNamesEveryPolicyOfEveryTool)
{
  namespace names = Laplacian_deformation_policy_names;
  struct Expected { const char* name; std::size_t index; };
  // Any_transform's alternatives: S*R1, fixed, rotation, similarity, principal, R2*S*R1, anchored
  const Expected transforms[] = {{"sr1", 0}, {"scaled_rotation", 0}, {"fixed", 1}, {"rotation", 2},
                                 {"similarity", 3}, {"principal", 4}, {"rsr", 5}, {"anchored", 6}};
  EXPECT_TRUE(names::transform_policy("sr1").holds<LD::Scaled_rotation_transform>());
  EXPECT_TRUE(names::transform_policy("scaled_rotation").holds<LD::Scaled_rotation_transform>());
  EXPECT_TRUE(names::transform_policy("fixed").holds<LD::Fixed_transform>());
  EXPECT_TRUE(names::transform_policy("rotation").holds<LD::Rotation_transform>());
  EXPECT_TRUE(names::transform_policy("similarity").holds<LD::Similarity_transform>());
  EXPECT_TRUE(names::transform_policy("principal").holds<LD::Principal_scaled_rotation_transform>());
  EXPECT_TRUE(names::transform_policy("rsr").holds<LD::Rotation_scale_rotation_transform>());
  EXPECT_TRUE(names::transform_policy("anchored").holds<LD::Anchored_scaled_rotation_transform>());
  EXPECT_TRUE(names::weight_policy("cotangent").holds<LD::Cotangent_weights>());
  EXPECT_TRUE(names::weight_policy("uniform").holds<LD::Uniform_weights>());
  EXPECT_EQ(names::representation("vertex"), names::Representation::VERTEX);
  EXPECT_EQ(names::representation("edge"), names::Representation::EDGE);
  // the defaults of the tools are the library's: the first entries
  EXPECT_EQ(cli::Options().transform, names::transform_policies()[0].name);
  EXPECT_EQ(cli::Options().weights, names::weight_policies()[0].name);
  EXPECT_EQ(cli::Options().representation, names::representations()[0].name);
  EXPECT_EQ(names::transform_policies()[0].policy.index(), LD::Any_transform().index());
  EXPECT_EQ(names::weight_policies()[0].policy.index(), LD::Any_weights().index());

  // every name (and alias) once; the command line takes each, canonical
  cli::Options o;
  std::string error;
  std::size_t table_names = 0;
  for(const auto& e : names::transform_policies())
    table_names += 1 + (e.alias != nullptr);
  EXPECT_EQ(table_names, std::size(transforms));
  for(const Expected& t : transforms)
  {
    const auto* e = names::find(names::transform_policies(), t.name);
    ASSERT_NE(e, nullptr) << t.name;
    EXPECT_EQ(e->policy.index(), t.index) << t.name;
    ASSERT_TRUE(parse({"--transform", t.name}, o, error)) << error;
    EXPECT_EQ(o.transform, e->name);
    EXPECT_EQ(names::transform_policy(o.transform).index(), t.index) << t.name;
    EXPECT_STRNE(cli::transform_label(o.transform), "unknown");
  }
  for(const auto& e : names::weight_policies())
  {
    ASSERT_TRUE(parse({"--weights", e.name}, o, error)) << error;
    EXPECT_EQ(names::weight_policy(o.weights).index(), e.policy.index());
  }
  for(const auto& e : names::representations())
  {
    ASSERT_TRUE(parse({"m.off", "s.sel", "d.def", "--representation", e.name}, o, error)) << error;
    EXPECT_EQ(names::representation(o.representation), e.policy);
  }
  EXPECT_EQ(parse_error({"--weights", "cot"}), "option --weights: expected " + names::name_list(names::weight_policies()) +
                                                   ", got 'cot'");
  EXPECT_EQ(parse_error({"--representation", "face"}), "option --representation: expected edge or vertex, got 'face'");
  // the help lists the table's names
  const std::string help = cli::usage_text();
  EXPECT_NE(help.find("--transform " + names::name_choices(names::transform_policies())), std::string::npos);
  EXPECT_NE(help.find("--weights " + names::name_choices(names::weight_policies())), std::string::npos);
  EXPECT_NE(help.find("--representation " + names::name_choices(names::representations())), std::string::npos);
}

TEST(LaplacianDeformCli, RejectsBadCommandLines)
{
  EXPECT_EQ(parse_error({"--bogus"}), "unknown option '--bogus' (see --help)");
  EXPECT_EQ(parse_error({"m.off", "--iterations"}), "option --iterations needs a value (see --help)");
  EXPECT_EQ(parse_error({"m.off", "--iterations", "0"}), "option --iterations: expected a positive integer, got '0'");
  EXPECT_EQ(parse_error({"m.off", "--tolerance", "-1"}), "option --tolerance: expected a non-negative number, got '-1'");
  EXPECT_EQ(parse_error({"m.off", "--soft", "nan"}), "option --soft: expected a positive number, got 'nan'");
  EXPECT_EQ(parse_error({"--start", "harmonic"}), "option --start: expected rotation or identity, got 'harmonic'");
  EXPECT_EQ(parse_error({"--rigidity", "-1"}), "option --rigidity: expected a non-negative finite number, got '-1'");
  EXPECT_EQ(parse_error({"--rigidity", "inf"}), "option --rigidity: expected a non-negative finite number, got 'inf'");
  EXPECT_EQ(parse_error({"--transform", "arap"}),
            "option --transform: expected sr1, fixed, rotation, similarity, principal, rsr or anchored, got 'arap'");
  EXPECT_EQ(parse_error({"m.off", "--handle", "1", "--roi-rings", "2", "--translate", "1,2"}),
            "option --translate: expected three numbers X,Y,Z, got '1,2'");
  EXPECT_EQ(parse_error({"m.off", "--handle", "4-2", "--roi-rings", "1"}),
            "option --handle: expected vertex ids and ranges such as 12,40-45,300, got '4-2'");
  EXPECT_EQ(parse_error({"m.off", "--rotate", "0,0,0,10"}), "option --rotate: expected a non-zero rotation axis, got '0,0,0,10'");
  EXPECT_EQ(parse_error({"--force=yes"}), "option --force takes no value");
  EXPECT_EQ(parse_error({"--iterations", "3", "--iterations", "4"}), "option --iterations is given twice");
  EXPECT_EQ(parse_error({"a", "b", "c", "d"}), "too many arguments: 'd' (expected MESH [SEL [DEF]])");
  EXPECT_EQ(parse_error({"m.off"}),
            "no handle: give a selection file (MESH SEL DEF) or --handle IDS with --roi-rings K or --roi-radius R");
  EXPECT_EQ(parse_error({"m.off", "--handle", "1"}),
            "give the region of interest around the handles: one of --roi-rings K or --roi-radius R");
  EXPECT_EQ(parse_error({"m.off", "--handle", "1", "--roi-rings", "1", "--roi-radius", "2"}),
            "give the region of interest around the handles: one of --roi-rings K or --roi-radius R");
  EXPECT_EQ(parse_error({"m.off", "s.sel", "d.def", "--translate", "1,0,0"}),
            "the handle transformation comes from d.def: do not also give --translate or --rotate");
  EXPECT_EQ(parse_error({"m.off", "s.sel", "d.def", "--handle", "1"}),
            "the selection comes from s.sel: do not also give --handle or --roi-*");
  EXPECT_EQ(parse_error({"m.off", "s.sel"}), "no handle motion: give DEF (MESH SEL DEF) or --translate / --rotate");
  EXPECT_EQ(parse_error({"--handle", "1"}), "--handle, --roi-*, --translate and --rotate need a MESH");
  EXPECT_EQ(parse_error({"--representation", "edge"}),
            "without MESH the tool compares both representations: --representation does not apply");
  EXPECT_EQ(parse_error({"-o", "x.off"}), "without MESH the tool writes a comparison: use --output-dir DIR, not --output");
  EXPECT_EQ(parse_error({"m.off", "s.sel", "d.def", "--output-dir", "x"}),
            "--output-dir applies to --compare (and to the default task); use --output FILE");
}

// ---------------------------------------------------------------------------------------------
// Regions of interest and handle motion, in-process

TEST(LaplacianDeformCli, RegionsAroundHandles)
{
  // 6 x 6 grid of unit squares split along one diagonal: an interior vertex has 6 neighbours,
  // 4 at distance 1 and 2 at distance sqrt(2)
  const cli::Mesh mesh = to_mesh<cli::Mesh>(grid_soup(6, 6));
  const std::size_t centre = 3 * 7 + 3;
  auto count = [](const std::vector<bool>& in) { return std::size_t(std::count(in.begin(), in.end(), true)); };
  EXPECT_EQ(count(cli::k_ring_region(mesh, {centre}, 0)), 1u);
  EXPECT_EQ(count(cli::k_ring_region(mesh, {centre}, 1)), 7u);
  EXPECT_EQ(count(cli::k_ring_region(mesh, {centre}, 100)), 49u);
  // the two corners of the diagonals: 3 neighbours each
  EXPECT_EQ(count(cli::k_ring_region(mesh, {0, 48}, 1)), 8u);
  EXPECT_EQ(count(cli::radius_region(mesh, {centre}, 0.5)), 1u);
  EXPECT_EQ(count(cli::radius_region(mesh, {centre}, 1.01)), 5u);
  EXPECT_EQ(count(cli::radius_region(mesh, {centre}, 1.5)), 7u);
  // distance 2 along edges: the 4 vertices two steps along an axis are in, (centre + (2, 2)) is not
  const std::vector<bool> r2 = cli::radius_region(mesh, {centre}, 2.);
  EXPECT_TRUE(r2[centre + 2] && r2[centre - 14]);
  EXPECT_FALSE(r2[centre + 2 + 14]);
}

// The tools' shared layer: the command line (cli_task.h) and the editor's server (session.h,
// requests.h) grow the same regions and read meshes the same way, through tool_regions.h and
// tool_mesh_io.h (the library's checked reader)
TEST(ToolLayerCliAndServer, GrowTheSameRegions)
{
  namespace tools = Laplacian_deformation_tools;
  namespace server = Laplacian_deformation_server;
  const cli::Mesh mesh = to_mesh<cli::Mesh>(grid_soup(6, 6));   // 7 x 7 vertices, see above
  const std::size_t centre = 3 * 7 + 3;
  struct Row { std::vector<std::size_t> sources; int rings; std::size_t in_rings; double radius; std::size_t in_radius; };
  const Row table[] = {
      {{centre}, 0, 1, 0.5, 1},
      {{centre}, 1, 7, 1.01, 5},
      {{centre}, 2, 19, 1.5, 7},           // a hexagonal ring has 6 k vertices
      {{centre}, 100, 49, 2., 13},         // and at distance 2: the axes' (+-2, 0), (1, -1), (-1, 1)
      {{0, 48}, 1, 8, 1., 6},              // the corners of the diagonals: 3 neighbours, 2 at distance 1
      {{0, 0, 48, 0}, 1, 8, 1., 6}};       // a source given twice counts once
  for(const Row& row : table)
  {
    std::vector<cli::vertex_descriptor> seeds;
    for(std::size_t v : row.sources)
      seeds.push_back(cli::vertex_descriptor(cli::Mesh::size_type(v)));
    const std::vector<cli::vertex_descriptor> grown = server::internal::grow(mesh, seeds, row.rings);
    const std::vector<bool> in_cli = cli::k_ring_region(mesh, row.sources, std::size_t(row.rings));
    EXPECT_EQ(grown.size(), row.in_rings) << row.rings;
    EXPECT_EQ(std::size_t(std::count(in_cli.begin(), in_cli.end(), true)), row.in_rings) << row.rings;
    EXPECT_EQ(tools::region_mask(num_vertices(mesh), grown), in_cli) << row.rings;
    EXPECT_EQ(grown, tools::k_ring_vertices(mesh, seeds, std::size_t(row.rings)));
    EXPECT_EQ(grown.front(), seeds.front());   // breadth-first: the sources first
    std::vector<double> distance;
    const std::vector<cli::vertex_descriptor> near = tools::geodesic_vertices(mesh, seeds, row.radius, &distance);
    const std::vector<bool> in_radius = cli::radius_region(mesh, row.sources, row.radius);
    EXPECT_EQ(near.size(), row.in_radius) << row.radius;
    EXPECT_EQ(tools::region_mask(num_vertices(mesh), near), in_radius) << row.radius;
    for(std::size_t i = 1; i < near.size(); ++i)   // in order of distance
      EXPECT_LE(distance[std::size_t(near[i - 1])], distance[std::size_t(near[i])]);
  }
}

TEST(LaplacianDeformCli, HandleMotionRotatesAboutTheCentreThenTranslates)
{
  cli::Options o;
  std::string error;
  ASSERT_TRUE(parse({"m.off", "--handle", "0", "--roi-rings", "1", "--rotate", "0,0,2,90,1,0,0",
                     "--translate", "0,0,5"}, o, error)) << error;
  const Eigen::Matrix4d m = cli::motion_matrix(o, Eigen::Vector3d(7, 7, 7));
  const Eigen::Vector4d p = m * Eigen::Vector4d(2, 0, 0, 1);
  EXPECT_NEAR(p.x(), 1., 1e-15);
  EXPECT_NEAR(p.y(), 1., 1e-15);
  EXPECT_NEAR(p.z(), 5., 1e-15);
  EXPECT_EQ(m.row(3), Eigen::RowVector4d(0, 0, 0, 1));
  // without a centre the rotation is about the given default (the handles' centroid)
  ASSERT_TRUE(parse({"m.off", "--handle", "0", "--roi-rings", "1", "--rotate", "0,0,1,180"}, o, error)) << error;
  const Eigen::Vector4d q = cli::motion_matrix(o, Eigen::Vector3d(1, 1, 0)) * Eigen::Vector4d(1, 1, 3, 1);
  EXPECT_NEAR((q.head<3>() - Eigen::Vector3d(1, 1, 3)).norm(), 0., 1e-15);
}

// ---------------------------------------------------------------------------------------------
// The binary, end to end

struct Tool_result
{
  int code = -1;
  std::string out, err;
};

std::string read_file(const fs::path& p)
{
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void write_file(const fs::path& p, const std::string& text)
{
  std::ofstream(p, std::ios::binary) << text;
}

std::string shell_quote(const std::string& s)
{
  std::string q = "'";
  for(char c : s)
    q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

TEST(ToolLayerCliAndServer, ReadMeshesTheSameWay)
{
  namespace server = Laplacian_deformation_server;
  const fs::path dir = fs::path(::testing::TempDir()) / "tool_layer_meshes";
  fs::remove_all(dir);
  fs::create_directories(dir);
  struct Options_stub { std::string mesh, data_dir; std::size_t max_vertices = 1000000; } options;   // load_mesh's
  options.data_dir = dir.string();
  struct Row { const char* name; std::string text; const char* reason; };   // reason null: read
  const Row table[] = {
      {"tetra.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n", nullptr},
      {"tetra.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n", nullptr},
      {"missing.off", "", "no such file"},
      {"broken.off", "OFF\n3 1 0\n0 0 0\n1 0\n", "not a valid off file"},
      // three triangles on one edge: refused by the library's checked reader
      {"fin.off", "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n",
       "the faces do not form a manifold, consistently oriented surface"},
      {"nan.off", "OFF\n4 4 0\n0 0 0\n1 nan 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n",
       "line 4: the coordinate 'nan' is not a finite number"}};
  for(const Row& row : table)
  {
    if(std::string(row.name) != "missing.off")
      write_file(dir / row.name, row.text);
    cli::Mesh from_cli;
    std::size_t triangulated = 0;
    std::string error, stem;
    const bool cli_read = cli::read_mesh(dir / row.name, false, from_cli, triangulated, error);
    std::string server_error;
    cli::Mesh from_server;
    try { from_server = server::load_mesh(options, row.name, stem); }
    catch(const server::Request_error& e) { server_error = e.message; }
    if(row.reason == nullptr)
    {
      ASSERT_TRUE(cli_read) << error;
      ASSERT_TRUE(server_error.empty()) << server_error;
      ASSERT_EQ(num_vertices(from_cli), 4u) << row.name;
      ASSERT_EQ(num_vertices(from_server), 4u) << row.name;
      EXPECT_EQ(num_faces(from_cli), num_faces(from_server)) << row.name;
      for(cli::vertex_descriptor v : vertices(from_cli))
        EXPECT_EQ(from_cli.point(v), from_server.point(v)) << row.name;
      continue;
    }
    ASSERT_FALSE(cli_read) << row.name;
    ASSERT_FALSE(server_error.empty()) << row.name;
    const std::string cli_prefix = std::string(row.reason) == "no such file" ? "cannot open " : "cannot read a mesh from ";
    EXPECT_EQ(error.rfind(cli_prefix + "'" + (dir / row.name).string() + "': " + row.reason, 0), 0u) << error;
    EXPECT_EQ(server_error.rfind(std::string("cannot read a mesh from ") + row.name + ": " + row.reason, 0), 0u)
        << server_error;
    // the same reason after the file's name
    EXPECT_EQ(error.substr(error.find("': ") + 3), server_error.substr(server_error.find(": ") + 2)) << row.name;
  }
}

class LaplacianDeformTool : public ::testing::Test
{
protected:
  void SetUp() override
  {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir = fs::current_path() / "laplacian_deform_cli_work" / info->name();
    fs::remove_all(dir);
    fs::create_directories(dir);
    cactus = data_path("cactus.off");
    sel = data_path("cactus.sel");
    def = data_path("cactus.def");
  }

  // runs the tool in `dir`
  Tool_result run(const std::vector<std::string>& args) const
  {
    std::string command = "cd " + shell_quote(dir.string()) + " && " + shell_quote(LAPLACIAN_DEFORM_TOOL);
    for(const std::string& a : args)
      command += " " + shell_quote(a);
    command += " >" + shell_quote((dir / ".stdout").string()) + " 2>" + shell_quote((dir / ".stderr").string());
    Tool_result r;
    const int status = std::system(command.c_str());
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = read_file(dir / ".stdout");
    r.err = read_file(dir / ".stderr");
    fs::remove(dir / ".stdout");
    fs::remove(dir / ".stderr");
    return r;
  }

  // the files in `dir` (a failed run must leave none, not even a temporary one)
  std::vector<std::string> files() const
  {
    std::vector<std::string> names;
    for(const auto& e : fs::recursive_directory_iterator(dir))
      names.push_back(fs::relative(e.path(), dir).string());
    std::sort(names.begin(), names.end());
    return names;
  }

  // a bad use: non-zero exit, the message on stderr, nothing written
  void expect_refused(const std::vector<std::string>& args, int code, const std::string& message)
  {
    const std::vector<std::string> before = files();
    const Tool_result r = run(args);
    EXPECT_EQ(r.code, code) << r.err;
    EXPECT_NE(r.err.find("laplacian_deform: error: " + message), std::string::npos)
        << "expected '" << message << "' in:\n" << r.err;
    EXPECT_EQ(files(), before) << "a failed run wrote a file";
    EXPECT_TRUE(r.out.empty()) << r.out;
  }

  fs::path dir;
  std::string cactus, sel, def;
};

// The deformation the library gives for the cactus task (the CLI's defaults: cotangent, S*R1,
// hard constraints, 4 iterations, tolerance 0).
template <class Representation, class Weights = LD::Cotangent_weights, class Transform = LD::Scaled_rotation_transform>
cli::Mesh library_result(LD::Deformation_start start = LD::IDENTITY_START)
{
  cli::Mesh mesh;
  EXPECT_TRUE(read_data_mesh("cactus.off", mesh));
  std::vector<int> status;
  Eigen::Matrix4d t;
  std::string error;
  std::ifstream s(data_path("cactus.sel")), d(data_path("cactus.def"));
  EXPECT_TRUE(LD::IO::read_botsch08_selection(s, status, error, num_vertices(mesh))) << error;
  EXPECT_TRUE(LD::IO::read_botsch08_transform(d, t, error)) << error;
  LD::Mesh_deformer<cli::Mesh, Representation, Weights, Transform> deformer(mesh);
  deformer.set_start(start);
  std::vector<cli::vertex_descriptor> handles;
  for(cli::vertex_descriptor v : vertices(mesh))
    if(status[v] == LD::IO::BOTSCH08_REGION_OF_INTEREST)
      deformer.insert_roi_vertex(v);
    else if(status[v] == LD::IO::BOTSCH08_HANDLE)
    {
      deformer.insert_control_vertex(v);
      handles.push_back(v);
    }
  for(cli::vertex_descriptor v : handles)
  {
    const cli::Point_3& p = mesh.point(v);
    const Eigen::Vector4d q = t * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.);
    deformer.set_target_position(v, cli::Point_3(q.x(), q.y(), q.z()));
  }
  const LD::Deformation_result r = deformer.deform(4, 0.);
  EXPECT_TRUE(bool(r)) << r.message;
  EXPECT_EQ(r.iterations, 4u);
  return mesh;
}

// Bitwise: OFF written with 17 digits round-trips. scripts/test.sh builds this test at -O2 and the
// tool at -O3, so these comparisons also check that the library gives the same bits at both levels
// (they caught the solve's FMA kernels, whose scalar tails GCC contracted at one level only).
void expect_identical(const fs::path& file, const cli::Mesh& expected)
{
  cli::Mesh written;
  ASSERT_TRUE(CGAL::IO::read_polygon_mesh(file.string(), written)) << file;
  ASSERT_EQ(num_vertices(written), num_vertices(expected));
  ASSERT_EQ(num_faces(written), num_faces(expected));
  std::size_t differing = 0;
  for(cli::vertex_descriptor v : vertices(expected))
    if(written.point(v) != expected.point(v))
      ++differing;
  EXPECT_EQ(differing, 0u) << file;
}

TEST_F(LaplacianDeformTool, CactusTaskReproducesTheLibraryExactly)
{
  const Tool_result r = run({cactus, sel, def, "-o", "edge.off", "--report", "report.json"});
  ASSERT_EQ(r.code, 0) << r.err;
  expect_identical(dir / "edge.off", library_result<LD::Edge_based_representation>());
  EXPECT_NE(r.out.find("620 vertices"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("iteration 4"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("wrote       edge.off"), std::string::npos) << r.out;

  const nlohmann::json report = nlohmann::json::parse(read_file(dir / "report.json"));
  ASSERT_EQ(report["runs"].size(), 1u);
  EXPECT_EQ(report["runs"][0]["status"], "SUCCESS");
  EXPECT_EQ(report["runs"][0]["representation"], "edge");
  EXPECT_EQ(report["runs"][0]["iterations"].size(), 4u);
  EXPECT_EQ(report["mesh"]["vertices"], 620);
  EXPECT_EQ(report["selection"]["handles"].get<std::size_t>() + report["selection"]["free"].get<std::size_t>() +
            report["selection"]["fixed"].get<std::size_t>(), 620u);
  EXPECT_EQ(report["motion"]["matrix"][3], nlohmann::json({0., 0., 0., 1.}));
  EXPECT_EQ(report["runs"][0]["max_handle_distance"], 0.);   // hard constraints
  EXPECT_EQ(report["options"]["start"], "identity");

  // --start rotation: the library's ROTATION_START, also bit for bit; the cactus's handle turns,
  // so the two starts differ
  const Tool_result i = run({cactus, sel, def, "--start", "rotation", "-o", "rotation.off"});
  ASSERT_EQ(i.code, 0) << i.err;
  const cli::Mesh rotation = library_result<LD::Edge_based_representation>(LD::ROTATION_START);
  expect_identical(dir / "rotation.off", rotation);
  const cli::Mesh identity = library_result<LD::Edge_based_representation>();
  double difference = 0;
  for(cli::vertex_descriptor v : vertices(identity))
    difference = (std::max)(difference, std::sqrt(CGAL::squared_distance(identity.point(v), rotation.point(v))));
  EXPECT_GT(difference, 1e-3);

  // other policies (run-time policies in the tool): the library's static types, bit for bit
  const Tool_result o = run({cactus, sel, def, "--representation", "vertex", "--weights", "uniform",
                             "--transform", "anchored", "--start", "rotation", "-o", "other.off"});
  ASSERT_EQ(o.code, 0) << o.err;
  expect_identical(dir / "other.off", library_result<LD::Vertex_based_representation, LD::Uniform_weights,
                                                     LD::Anchored_scaled_rotation_transform>(LD::ROTATION_START));
}

// On Linux with glibc the tool restarts itself with GLIBC_TUNABLES=glibc.malloc.hugetlb=1 (huge
// pages for its large blocks) unless GLIBC_TUNABLES is set or CGAL_LAPLACIAN_DEFORMATION_HUGE_PAGES=0;
// the result is the library's, bit for bit, either way
TEST_F(LaplacianDeformTool, RestartsWithHugePagesAndGivesTheSameResult)
{
  struct Case
  {
    std::string environment, expected;
  };
#if defined(__linux__) && defined(__GLIBC__)
  const std::string restarted = "glibc.malloc.hugetlb=1";
#else
  const std::string restarted = "";
#endif
  const Case cases[] = {{"env -u GLIBC_TUNABLES", restarted},
                        {"env -u GLIBC_TUNABLES CGAL_LAPLACIAN_DEFORMATION_HUGE_PAGES=0", ""},
                        {"env GLIBC_TUNABLES=glibc.malloc.hugetlb=0", "glibc.malloc.hugetlb=0"}};
  const cli::Mesh expected = library_result<LD::Edge_based_representation>();
  int k = 0;
  for(const Case& c : cases)
  {
    const std::string out = "edge" + std::to_string(k) + ".off", report = "report" + std::to_string(k++) + ".json";
    const std::string command = "cd " + shell_quote(dir.string()) + " && " + c.environment + " " +
                                shell_quote(LAPLACIAN_DEFORM_TOOL) + " " + shell_quote(cactus) + " " + shell_quote(sel) +
                                " " + shell_quote(def) + " -o " + out + " --report " + report + " --quiet";
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << command;
    expect_identical(dir / out, expected);
    const nlohmann::json r = nlohmann::json::parse(read_file(dir / report));
    EXPECT_EQ(r["environment"]["GLIBC_TUNABLES"], c.expected) << c.environment;
  }
}

TEST_F(LaplacianDeformTool, MainJobReproducesTheLibraryWithBothRepresentations)
{
  // the default task, as scripts/demo.sh runs it (no argument), here with an explicit folder
  const Tool_result r = run({"--output-dir", "cmp", "--progress", "always"});
  ASSERT_EQ(r.code, 0) << r.err;
  expect_identical(dir / "cmp" / "cactus_vertex-based.off", library_result<LD::Vertex_based_representation>());
  expect_identical(dir / "cmp" / "cactus_edge-based.off", library_result<LD::Edge_based_representation>());
  const std::string summary = read_file(dir / "cmp" / "summary.txt");
  EXPECT_NE(summary.find("vertex-based  edge-based"), std::string::npos) << summary;
  EXPECT_NE(summary.find("edge dist mean"), std::string::npos) << summary;
  EXPECT_NE(r.out.find("summary in  cmp/summary.txt"), std::string::npos) << r.out;
  // --progress always: a stage line per step on a non-terminal stderr
  EXPECT_NE(r.err.find("laplacian_deform: edge-based: iteration 4/4"), std::string::npos) << r.err;
}

TEST_F(LaplacianDeformTool, CommandLineSelectionAndPolicies)
{
  write_file(dir / "quads.off", [] {
    std::ostringstream s;
    const Soup q = quad_grid_soup(4, 4);
    s << "OFF\n" << q.points.size() << ' ' << q.faces.size() << " 0\n";
    for(const auto& p : q.points)
      s << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    for(const auto& f : q.faces)
      s << "4 " << f[0] << ' ' << f[1] << ' ' << f[2] << ' ' << f[3] << '\n';
    return s.str();
  }());
  // a non-triangle mesh, triangulated on request; vertex 12 is the centre of the 5 x 5 grid
  const Tool_result r = run({"quads.off", "--triangulate", "--handle", "12", "--roi-radius", "1.2", "--translate",
                             "0,0,0.5", "--representation", "vertex", "--weights", "uniform", "--transform",
                             "similarity", "--iterations", "3", "-o", "lifted.obj", "--report", "r.json"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("(16 non-triangle faces triangulated)"), std::string::npos) << r.out;
  cli::Mesh lifted;
  ASSERT_TRUE(CGAL::IO::read_polygon_mesh((dir / "lifted.obj").string(), lifted));
  EXPECT_EQ(num_faces(lifted), 32u);
  EXPECT_DOUBLE_EQ(lifted.point(cli::vertex_descriptor(12)).z(), 0.5);
  EXPECT_DOUBLE_EQ(lifted.point(cli::vertex_descriptor(0)).z(), 0.);      // outside the ROI
  EXPECT_GT(lifted.point(cli::vertex_descriptor(13)).z(), 0.);            // a free neighbour follows
  const nlohmann::json report = nlohmann::json::parse(read_file(dir / "r.json"));
  EXPECT_EQ(report["selection"]["handles"], 1);
  EXPECT_EQ(report["selection"]["free"], 4);      // the 4 axis neighbours (diagonals are longer than 1.2)
  EXPECT_EQ(report["runs"][0]["transform"], "similarity");
  EXPECT_EQ(report["runs"][0]["iterations"].size(), 3u);

  // soft constraints leave a residual; the input is never touched
  const std::string before = read_file(dir / "quads.off");
  const Tool_result soft = run({"quads.off", "--triangulate", "--handle", "12", "--roi-rings", "1", "--translate",
                                "0,0,0.5", "--soft", "0.01", "--quiet"});
  ASSERT_EQ(soft.code, 0) << soft.err;
  EXPECT_TRUE(soft.out.empty());
  EXPECT_TRUE(fs::exists(dir / "quads_deformed.off"));
  EXPECT_EQ(read_file(dir / "quads.off"), before);

  // the anchored S*R1 with rigidity rows, both named in the report
  const Tool_result anchored = run({"quads.off", "--triangulate", "--handle", "12", "--roi-rings", "2", "--rotate",
                                    "1,0,0,40", "--transform", "anchored", "--start", "rotation", "--rigidity", "0.3", "-o", "anchored.off",
                                    "--report", "a.json"});
  ASSERT_EQ(anchored.code, 0) << anchored.err;
  EXPECT_NE(anchored.out.find("anchored S*R1 transforms, rotation start, rigidity rows (weight 0.3)"), std::string::npos)
      << anchored.out;
  const nlohmann::json a = nlohmann::json::parse(read_file(dir / "a.json"));
  EXPECT_EQ(a["runs"][0]["transform"], "anchored");
  EXPECT_EQ(a["options"]["rigidity"], 0.3);
  EXPECT_EQ(a["runs"][0]["status"], "SUCCESS");
}

TEST_F(LaplacianDeformTool, HelpExitsCleanly)
{
  const Tool_result r = run({"--help"});
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("usage: laplacian_deform [OPTIONS] [MESH [SEL [DEF]]]"), std::string::npos);
  EXPECT_NE(r.out.find("--roi-radius R"), std::string::npos);
}

TEST_F(LaplacianDeformTool, BadUseIsRefusedAndWritesNothing)
{
  // unknown option
  expect_refused({"--bogus", cactus, sel, def}, 2, "unknown option '--bogus' (see --help)");
  // missing file
  expect_refused({"nothing.off", sel, def, "-o", "out.off"}, 1, "cannot open 'nothing.off': no such file");
  expect_refused({cactus, "nothing.sel", def, "-o", "out.off"}, 1,
                 "cannot open the selection 'nothing.sel': no such file");
  // unreadable mesh
  write_file(dir / "broken.off", "OFF\n3 1 0\n0 0 0\n1 0\n");
  expect_refused({"broken.off", sel, def, "-o", "out.off"}, 1, "cannot read a mesh from 'broken.off': not a valid off");
  // a non-manifold mesh (three triangles on one edge): the library's checked reader says why
  write_file(dir / "fin.off", "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n");
  expect_refused({"fin.off", "--handle", "0", "--roi-rings", "1", "--translate", "0,0,1", "-o", "out.off"}, 1,
                 "cannot read a mesh from 'fin.off': the faces do not form a manifold, consistently oriented surface");
  write_file(dir / "mesh.xyz", "0 0 0\n");
  expect_refused({"mesh.xyz", sel, def, "-o", "out.off"}, 1,
                 "cannot read a mesh from 'mesh.xyz': unknown extension 'xyz'");
  // .sel with the wrong number of lines
  write_file(dir / "short.sel", "# too short\n1\n2\n0\n");
  expect_refused({cactus, "short.sel", def, "-o", "out.off"}, 1,
                 "bad selection 'short.sel': the selection has 3 statuses but the mesh has 620 vertices");
  // .sel with a bad token (line 6 of a copy of cactus.sel)
  {
    std::istringstream in(read_file(sel));
    std::ostringstream out;
    std::string line;
    for(int number = 1; std::getline(in, line); ++number)
      out << (number == 6 ? std::string("3") : line) << '\n';
    write_file(dir / "token.sel", out.str());
  }
  expect_refused({cactus, "token.sel", def, "-o", "out.off"}, 1,
                 "bad selection 'token.sel': line 6: expected one status 0, 1 or 2, got '3'");
  // .def that is not 4x4 numbers, or has NaN
  write_file(dir / "short.def", "1 0 0 0\n0 1 0 0\n0 0 1 0\n");
  expect_refused({cactus, sel, "short.def", "-o", "out.off"}, 1,
                 "bad handle transformation 'short.def': expected 16 numbers (a 4x4 matrix), got 12");
  write_file(dir / "word.def", "1 0 0 0\n0 1 x 0\n0 0 1 0\n0 0 0 1\n");
  expect_refused({cactus, sel, "word.def", "-o", "out.off"}, 1,
                 "bad handle transformation 'word.def': entry 7 of the matrix is not a finite number: 'x'");
  write_file(dir / "nan.def", "1 0 0 nan\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  expect_refused({cactus, sel, "nan.def", "-o", "out.off"}, 1,
                 "bad handle transformation 'nan.def': entry 4 of the matrix is not a finite number: 'nan'");
  // output equal to input without --force (also through another spelling of the path)
  fs::copy_file(cactus, dir / "copy.off");
  const std::string original = read_file(dir / "copy.off");
  expect_refused({"copy.off", sel, def, "-o", "copy.off"}, 1,
                 "the output 'copy.off' is the input 'copy.off': refusing to overwrite it (pass --force to allow it)");
  expect_refused({"copy.off", sel, def, "-o", "./copy.off"}, 1,
                 "the output './copy.off' is the input 'copy.off': refusing to overwrite it");
  expect_refused({"copy.off", sel, def, "-o", "out.off", "--report", "copy.off"}, 1,
                 "the output 'copy.off' is the input 'copy.off'");
  EXPECT_EQ(read_file(dir / "copy.off"), original);
  // non-triangle input without --triangulate
  write_file(dir / "quad.off", "OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n4 0 1 2 3\n3 1 4 2\n");
  expect_refused({"quad.off", "--handle", "2", "--roi-rings", "1", "--translate", "0,0,1", "-o", "out.off"}, 1,
                 "the mesh 'quad.off' has 1 non-triangle face (of 2); the deformation needs triangles: pass "
                 "--triangulate to split them with CGAL::Polygon_mesh_processing::triangulate_faces");
  // and a few more: unknown output format, missing output folder, handle out of range
  expect_refused({cactus, sel, def, "-o", "out.txt"}, 2, "cannot write a mesh to 'out.txt': unknown extension 'txt'");
  expect_refused({cactus, sel, def, "-o", "no/such/dir/out.off"}, 1, "cannot write 'no/such/dir/out.off': the folder 'no/such/dir' does not exist");
  expect_refused({cactus, "--handle", "620", "--roi-rings", "2", "--translate", "0,0,1"}, 1,
                 "handle vertex 620 does not exist: the mesh has 620 vertices (ids 0 to 619)");
  // a huge range is refused by its last id, before any expansion
  expect_refused({cactus, "--handle", "3,0-300000000", "--roi-rings", "2", "--translate", "0,0,1"}, 1,
                 "handle vertex 300000000 does not exist: the mesh has 620 vertices (ids 0 to 619)");

  // with --force the input may be overwritten
  const Tool_result forced = run({"copy.off", sel, def, "-o", "copy.off", "--force", "--quiet"});
  EXPECT_EQ(forced.code, 0) << forced.err;
  EXPECT_NE(read_file(dir / "copy.off"), original);
}

// Results that look wrong are flagged, on the standard error (even with --quiet), in the summary
// and in the report; the run still succeeds and writes its result
TEST_F(LaplacianDeformTool, WarningsAreReported)
{
  write_file(dir / "grid.off", [] {
    std::ostringstream s;
    const Soup g = bumpy_plane_soup(8, 0.1);
    s.precision(17);
    s << "OFF\n" << g.points.size() << ' ' << g.faces.size() << " 0\n";
    for(const auto& p : g.points)
      s << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    for(const auto& f : g.faces)
      s << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
    return s.str();
  }());
  // a single handle rotated about itself (its centroid): nothing moves
  {
    const Tool_result r = run({"grid.off", "--handle", "40", "--roi-rings", "2", "--rotate", "0,0,1,30", "-o", "out.off",
                               "--report", "r.json", "--quiet"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("laplacian_deform: warning: every control vertex's target is its rest position"), std::string::npos)
        << r.err;
    const nlohmann::json report = nlohmann::json::parse(read_file(dir / "r.json"));
    ASSERT_EQ(report["runs"][0]["warnings"].size(), 1u) << report["runs"][0]["warnings"].dump();
    EXPECT_EQ(report["runs"][0]["warnings"][0]["kind"], "NO_MOTION");
    EXPECT_EQ(report["runs"][0]["warnings"][0]["count"], 1);
    EXPECT_TRUE(fs::exists(dir / "out.off"));
  }
  // a handle whose region of interest is only itself: it touches the fixed vertices; dragged
  // sideways past its neighbours, the faces around it fold
  {
    const Tool_result r = run({"grid.off", "--handle", "40", "--roi-rings", "0", "--translate", "0.3,0,0", "-o", "out2.off",
                               "--report", "r2.json"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("warning     FOLDED_FACES: "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("warning     HANDLE_TOUCHES_FIXED: 1 control vertices are adjacent to fixed vertices"),
              std::string::npos) << r.out;
    EXPECT_NE(r.err.find("laplacian_deform: warning: 1 control vertices are adjacent"), std::string::npos) << r.err;
    const nlohmann::json report = nlohmann::json::parse(read_file(dir / "r2.json"));
    ASSERT_EQ(report["runs"][0]["warnings"].size(), 2u) << report["runs"][0]["warnings"].dump();
    EXPECT_EQ(report["runs"][0]["warnings"][0]["kind"], "FOLDED_FACES");
    EXPECT_EQ(report["runs"][0]["warnings"][1]["kind"], "HANDLE_TOUCHES_FIXED");
  }
  // an ordinary task: no warning
  {
    const Tool_result r = run({"grid.off", "--handle", "40", "--roi-rings", "3", "--translate", "0,0,0.05", "-o", "out3.off",
                               "--report", "r3.json"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
    const nlohmann::json report = nlohmann::json::parse(read_file(dir / "r3.json"));
    EXPECT_TRUE(report["runs"][0]["warnings"].empty());
  }
}

// NaN or infinite coordinates in a mesh file: the line and the value, not "malformed file"
TEST_F(LaplacianDeformTool, NonFiniteCoordinatesNameTheLineAndTheValue)
{
  const std::string faces = "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
  const std::vector<std::string> task = {"--handle", "0", "--roi-rings", "1", "--translate", "0,0,1", "-o", "out.off"};
  auto refused = [&](const std::string& name, const std::string& text, const std::string& message) {
    write_file(dir / name, text);
    std::vector<std::string> args{name};
    args.insert(args.end(), task.begin(), task.end());
    expect_refused(args, 1, "cannot read a mesh from '" + name + "': " + message);
  };
  refused("nan.off", "OFF\n4 4 0\n0 0 0\n1 nan 0\n0 1 0\n0 0 1\n" + faces,
          "line 4: the coordinate 'nan' is not a finite number (NaN and infinite coordinates cannot be deformed)");
  refused("inf.off", "OFF\n# a comment\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 -inf\n" + faces,
          "line 7: the coordinate '-inf' is not a finite number");
  refused("overflow.obj", "v 0 0 0\nv 1 0 0\nv 0 1e999 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n",
          "line 3: the coordinate '1e999' is not a finite number");
}

// Binary garbage in a .sel or .def is quoted with its non-printable bytes escaped and cut after
// 40 bytes, never echoed raw to the terminal
TEST_F(LaplacianDeformTool, GarbageInTaskFilesIsQuotedEscaped)
{
  std::string garbage = "\x01\x1b[2J\x7f'\\";
  for(int k = 0; k < 100; ++k)
    garbage += char(0x80 + k);
  {
    std::istringstream in(read_file(sel));
    std::ostringstream out;
    std::string line;
    for(int number = 1; std::getline(in, line); ++number)
      out << (number == 3 ? garbage : line) << '\n';
    write_file(dir / "garbage.sel", out.str());
  }
  write_file(dir / "garbage.def", "1 0 0 0\n0 1 0 0\n0 0 " + garbage + " 0\n0 0 0 1\n");
  auto printable = [](const std::string& text) {
    return std::all_of(text.begin(), text.end(), [](char c) { return c == '\n' || (c >= 0x20 && c <= 0x7e); });
  };
  const std::string shown = "'\\x01\\x1b[2J\\x7f\\'\\\\\\x80\\x81";
  for(const std::vector<std::string>& args : {std::vector<std::string>{cactus, "garbage.sel", def, "-o", "out.off"},
                                              std::vector<std::string>{cactus, sel, "garbage.def", "-o", "out.off"}})
  {
    const Tool_result r = run(args);
    EXPECT_EQ(r.code, 1);
    EXPECT_TRUE(printable(r.err)) << r.err;
    EXPECT_NE(r.err.find(shown), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("... (" + std::to_string(garbage.size()) + " bytes)"), std::string::npos) << r.err;
    EXPECT_LT(r.err.size(), 400u) << r.err;
  }
  const Tool_result r = run({cactus, "garbage.sel", def, "-o", "out.off"});
  EXPECT_NE(r.err.find("bad selection 'garbage.sel': line 3: expected one status 0, 1 or 2, got '"), std::string::npos)
      << r.err;
}

} // namespace
