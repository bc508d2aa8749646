// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// laplacian_deform --serve (demo/Laplacian_deformation/deformation_server.h): the JSON API through
// its handler layer (no sockets): malformed requests get 4xx with a clear error and change
// nothing, a drag never refactors and replies with the moving vertices only (JSON or the binary
// frame), policies re-apply the same drag, sessions are bounded without evicting a live one, one
// session's lock never blocks another, a queued drag is superseded by a newer one, downloads and
// saves stay in their folder, the static file guard, where the viewer files are found; then over
// a real socket (httplib::Client): every refusal of the guard (Host, Origin, token, content type,
// 413, multipart), no compression, cacheable static files, and a taken port is an error.
#include "deformation_server.h"

#include <gtest/gtest.h>

#include <atomic>
#include <future>
#include <thread>

#include <netinet/in.h>
#include <arpa/inet.h>
#include <unistd.h>

namespace {

using namespace Laplacian_deformation_server;

// A fresh data folder (one small OFF mesh, no cactus: "default" is the generated bumpy plane)
// and output folder per test.
struct Server_test : ::testing::Test
{
  fs::path root;
  Server_options options;
  std::unique_ptr<Deformation_server> server;

  void SetUp() override
  {
    root = fs::temp_directory_path() /
           ("laplacian_server_test_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(root);
    fs::create_directories(root / "data");
    std::ofstream(root / "data" / "tetra.off") << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
    std::ofstream(root / "secret.off") << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    options.data_dir = (root / "data").string();
    options.output_dir = (root / "out").string();
    options.viewer_dir = LAPLACIAN_DEFORMATION_VIEWER_DIR;
    options.token = "test-token-0123456789abcdef";
    server = std::make_unique<Deformation_server>(options);
  }
  void TearDown() override { fs::remove_all(root); }

  json post(const std::string& path, const json& body, int expected = 200)
  {
    const Reply r = server->post(path, body.dump());
    EXPECT_EQ(r.status, expected) << path << " " << body.dump().substr(0, 200) << " -> " << r.body.substr(0, 300);
    return json::parse(r.body);
  }
  // the error message of a request that must fail with `expected`
  std::string error(const std::string& path, const std::string& body, int expected = 400)
  {
    const Reply r = server->post(path, body);
    EXPECT_EQ(r.status, expected) << path << " " << body << " -> " << r.body;
    const json j = json::parse(r.body, nullptr, false);
    return j.is_object() && j.contains("error") ? j["error"].get<std::string>() : std::string("(no error member)");
  }
  std::string download(const std::string& id, const std::string& format, int expected = 200)
  {
    const Reply r = server->get("/api/download", {{"session", id}, {"format", format}});
    EXPECT_EQ(r.status, expected) << format << " -> " << r.body.substr(0, 200);
    return r.body;
  }
  // a session on the default mesh (41 x 41 bumpy plane) with a selection: ROI = 6 rings around
  // the centre, handle = the centre
  std::string selected_session(json* selection = nullptr)
  {
    const json s = post("/api/session", {{"mesh", "default"}});
    EXPECT_EQ(s["vertices"].size(), 3u * 41 * 41);
    EXPECT_EQ(s["faces"].size(), 3u * 2 * 40 * 40);
    const std::string id = s["session"];
    const json sel = post("/api/select", {{"session", id}, {"handles", {20 * 41 + 20}}, {"grow", 6}});
    if(selection) *selection = sel;
    return id;
  }
};

// the position of vertex v in a deformation reply (its "positions" follow the selection's "moving")
double coordinate(const json& reply, const json& moving, std::size_t v, int k)
{
  for(std::size_t i = 0; i < moving.size(); ++i)
    if(moving[i].get<std::size_t>() == v)
      return reply["positions"][3 * i + std::size_t(k)].get<double>();
  ADD_FAILURE() << "vertex " << v << " is not a moving vertex";
  return 0;
}

TEST_F(Server_test, malformed_requests_get_clear_errors_and_change_nothing)
{
  const std::string id = selected_session();
  const std::string s = "\"session\":\"" + id + "\"";
  post("/api/drag", {{"session", id}, {"translation", {0, 0, 0.1}}});
  const std::string before = download(id, "off");
  const std::size_t factorizations = server->number_of_factorizations(id);

  EXPECT_NE(error("/api/drag", "{not json").find("not valid JSON"), std::string::npos);
  EXPECT_NE(error("/api/drag", "[1,2,3]").find("must be a JSON object"), std::string::npos);
  EXPECT_NE(error("/api/drag", "{}").find("missing \"session\""), std::string::npos);
  EXPECT_NE(error("/api/drag", "{\"session\":42}").find("session must be a string"), std::string::npos);
  EXPECT_NE(error("/api/drag", "{\"session\":\"nope\"}", 404).find("unknown session"), std::string::npos);
  // NaN is no JSON: a parse error; a number too large for a double is refused too
  EXPECT_NE(error("/api/drag", "{" + s + ",\"translation\":[NaN,0,0]}").find("not valid JSON"), std::string::npos);
  const std::string huge = error("/api/drag", "{" + s + ",\"translation\":[1e999,0,0]}");
  EXPECT_TRUE(huge.find("finite") != std::string::npos || huge.find("not valid JSON") != std::string::npos) << huge;
  EXPECT_NE(error("/api/drag", "{" + s + ",\"translation\":[1,0]}").find("array of 3 numbers"), std::string::npos);
  EXPECT_NE(error("/api/drag", "{" + s + ",\"translation\":[\"1\",0,0]}").find("translation[0] must be a number"),
            std::string::npos);
  EXPECT_NE(error("/api/drag", "{" + s + ",\"rotation\":{\"axis\":[0,0,0],\"angle\":1}}").find("must not be zero"),
            std::string::npos);
  EXPECT_NE(error("/api/drag", "{" + s + ",\"rotation\":{\"axis\":[0,0,1]}}").find("rotation.angle must be a number"),
            std::string::npos);
  EXPECT_NE(error("/api/drag", "{" + s + ",\"rotation\":[1]}").find("rotation must be an object"), std::string::npos);
  EXPECT_NE(error("/api/drag", "{" + s + ",\"iterations\":0}").find("iterations must be in [1, 100]"),
            std::string::npos);
  EXPECT_NE(error("/api/select", "{" + s + ",\"handles\":[1681]}").find("unknown vertex id 1681 (the mesh has 1681"),
            std::string::npos);
  EXPECT_NE(error("/api/select", "{" + s + ",\"handles\":[-1]}").find("unknown vertex id -1"), std::string::npos);
  EXPECT_NE(error("/api/select", "{" + s + ",\"handles\":[1.5]}").find("handles[0] must be an integer"),
            std::string::npos);
  EXPECT_NE(error("/api/select", "{" + s + ",\"roi\":[1,\"x\"],\"handles\":[3]}").find("roi[1] must be an integer"),
            std::string::npos);
  EXPECT_NE(error("/api/select", "{" + s + ",\"roi\":7,\"handles\":[3]}").find("roi must be an array"),
            std::string::npos);
  EXPECT_NE(error("/api/select", "{" + s + ",\"roi\":[1,2]}").find("at least one vertex"), std::string::npos);
  EXPECT_NE(error("/api/select", "{" + s + ",\"handles\":[3],\"grow\":-1}").find("grow must be in"), std::string::npos);
  EXPECT_NE(error("/api/policy", "{" + s + ",\"weights\":\"mean\"}").find("weights must be"), std::string::npos);
  EXPECT_NE(error("/api/policy", "{" + s + ",\"representation\":1}").find("representation must be a string"),
            std::string::npos);
  EXPECT_NE(error("/api/policy", "{" + s + ",\"transform\":\"shear\"}").find("transform must be"), std::string::npos);
  EXPECT_NE(error("/api/policy", "{" + s + ",\"start\":\"harmonic\"}").find("start must be"), std::string::npos);
  EXPECT_NE(error("/api/reset", "{" + s + ",\"selection\":\"yes\"}").find("selection must be true or false"),
            std::string::npos);
  EXPECT_NE(error("/api/nothing", "{}", 404).find("no such API"), std::string::npos);
  EXPECT_EQ(server->get("/api/download", {{"session", id}, {"format", "exe"}}).status, 400);
  EXPECT_EQ(server->get("/api/download", {{"format", "off"}}).status, 400);
  // bytes that are not UTF-8, echoed in a message, still give a JSON error (found by fuzz_server)
  const Reply latin = server->get("/api/download", {{"session", id}, {"format", "\xfd\xff"}});
  EXPECT_EQ(latin.status, 400);
  EXPECT_TRUE(json::parse(latin.body, nullptr, false).is_object()) << latin.body;
  const Reply url = get_static(options.viewer_dir, "/\xfdx");
  EXPECT_EQ(url.status, 404);
  EXPECT_TRUE(json::parse(url.body, nullptr, false).is_object()) << url.body;

  // nothing changed: same mesh, same factorisation, and the session still deforms
  EXPECT_EQ(download(id, "off"), before);
  EXPECT_EQ(server->number_of_factorizations(id), factorizations);
  const json d = post("/api/drag", {{"session", id}, {"translation", {0, 0, 0.1}}});
  EXPECT_LT(d["handle_error"].get<double>(), 1e-9);
}

TEST_F(Server_test, meshes_by_name_only_from_the_data_folder)
{
  const json list = json::parse(server->get("/api/meshes", {}).body);
  EXPECT_EQ(list["meshes"], json::array({"default", "tetra.off"}));
  const json t = post("/api/session", {{"mesh", "tetra.off"}});
  EXPECT_EQ(t["vertices"].size(), 12u);
  for(const char* bad : {"../secret.off", "/etc/passwd", "..", "data/tetra.off", "tetra.exe", ".off", "-tetra.off"})
    EXPECT_NE(error("/api/session", json{{"mesh", bad}}.dump()).find("mesh must be \"default\" or a file name"),
              std::string::npos) << bad;
  EXPECT_NE(error("/api/session", R"({"mesh":"missing.off"})").find("cannot read a mesh from missing.off"),
            std::string::npos);
  EXPECT_NE(error("/api/session", R"({"mesh":3})").find("mesh must be a string"), std::string::npos);
}

TEST_F(Server_test, a_mesh_is_read_once_per_file_version_and_sent_as_a_binary_frame)
{
  const json t = post("/api/session", {{"mesh", "tetra.off"}});
  EXPECT_EQ(server->mesh_cache_hits(), 0u);
  // the same file again, as the binary frame: the mesh read before, the same numbers
  Reply r = server->post("/api/session", R"({"mesh":"tetra.off","binary":true})");
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(r.content_type, binary_type());
  EXPECT_EQ(server->mesh_cache_hits(), 1u);
  json header;
  std::vector<double> xyz;
  std::vector<std::uint32_t> faces;
  ASSERT_TRUE(decode_mesh_frame(r.body, header, xyz, faces));
  EXPECT_EQ(header["vertex_count"], 4u);
  EXPECT_EQ(header["face_count"], 4u);
  EXPECT_EQ(header["mesh"], "tetra.off");
  EXPECT_TRUE(header["session"].is_string());
  EXPECT_NE(header["session"], t["session"]);
  EXPECT_EQ(header["policy"], t["policy"]);
  EXPECT_FALSE(header.contains("vertices"));
  ASSERT_EQ(xyz.size(), t["vertices"].size());
  for(std::size_t i = 0; i < xyz.size(); ++i)
    EXPECT_EQ(xyz[i], t["vertices"][i].get<double>()) << i;
  ASSERT_EQ(faces.size(), t["faces"].size());
  for(std::size_t i = 0; i < faces.size(); ++i)
    EXPECT_EQ(faces[i], t["faces"][i].get<std::uint32_t>()) << i;
  // a truncated or padded frame is not one
  std::string bad = r.body;
  bad.pop_back();
  EXPECT_FALSE(decode_mesh_frame(bad, header, xyz, faces));
  EXPECT_FALSE(decode_mesh_frame(r.body + "    ", header, xyz, faces));

  // the file rewritten with the same size: read again (its time changed), not the kept mesh
  const fs::path file = root / "data" / "tetra.off";
  const fs::file_time_type before = fs::last_write_time(file);
  std::ofstream(file) << "OFF\n4 4 0\n0 0 0\n2 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
  fs::last_write_time(file, before + std::chrono::seconds(2));
  const json u = post("/api/session", {{"mesh", "tetra.off"}});
  EXPECT_EQ(server->mesh_cache_hits(), 1u);
  EXPECT_EQ(u["vertices"][3].get<double>(), 2.);
  EXPECT_EQ(post("/api/session", {{"mesh", "tetra.off"}})["vertices"][3].get<double>(), 2.);
  EXPECT_EQ(server->mesh_cache_hits(), 2u);
  // a file that has become unreadable is refused, even though an older version was kept
  std::ofstream(file) << "OFF\n4 4 0\n0 0 0\n";
  EXPECT_NE(error("/api/session", R"({"mesh":"tetra.off","binary":true})").find("cannot read a mesh from tetra.off"),
            std::string::npos);
  EXPECT_NE(error("/api/session", R"({"mesh":"tetra.off","binary":1})").find("binary must be true or false"), std::string::npos);

  // the generated default mesh (no cactus in this data folder) as a frame too
  r = server->post("/api/session", R"({"binary":true})");
  ASSERT_EQ(r.status, 200);
  ASSERT_TRUE(decode_mesh_frame(r.body, header, xyz, faces));
  EXPECT_EQ(xyz.size(), 3u * 41 * 41);
  EXPECT_EQ(faces.size(), 3u * 2 * 40 * 40);
  EXPECT_EQ(*std::max_element(faces.begin(), faces.end()), 41u * 41 - 1);
}

TEST_F(Server_test, sessions_are_bounded_without_evicting_a_live_one)
{
  options.max_sessions = 3;
  server = std::make_unique<Deformation_server>(options);
  std::vector<std::string> ids;
  for(int i = 0; i < 3; ++i)
    ids.push_back(post("/api/session", {{"mesh", "tetra.off"}})["session"]);
  // a fourth is refused with a clear error, and every live session still answers
  const std::string full = error("/api/session", R"({"mesh":"tetra.off"})", 503);
  EXPECT_NE(full.find("too many sessions: 3 editor pages are open (at most 3)"), std::string::npos) << full;
  EXPECT_EQ(server->number_of_sessions(), 3u);
  for(const std::string& id : ids)
    EXPECT_EQ(server->post("/api/reset", json{{"session", id}}.dump()).status, 200) << id;
  // closing one (the page does on leaving) makes room
  EXPECT_EQ(post("/api/close", {{"session", ids[1]}})["closed"], true);
  EXPECT_EQ(post("/api/close", {{"session", ids[1]}})["closed"], false);
  EXPECT_EQ(server->post("/api/reset", json{{"session", ids[1]}}.dump()).status, 404);
  ids[1] = post("/api/session", {{"mesh", "tetra.off"}})["session"];
  // a session idle for session_idle_seconds makes room: the least recently used goes
  options.session_idle_seconds = 0;
  server = std::make_unique<Deformation_server>(options);
  ids.clear();
  for(int i = 0; i < 3; ++i)
    ids.push_back(post("/api/session", {{"mesh", "tetra.off"}})["session"]);
  post("/api/reset", {{"session", ids[0]}});   // ids[1] is now the least recently used
  const std::string x = post("/api/session", {{"mesh", "tetra.off"}})["session"];
  EXPECT_EQ(server->number_of_sessions(), 3u);
  EXPECT_EQ(server->post("/api/reset", json{{"session", ids[1]}}.dump()).status, 404);
  // order of use now: ids[2], ids[0], x; but one in use (its lock held by a request) never goes
  {
    auto hold = server->hold_session(ids[2]);
    post("/api/session", {{"mesh", "tetra.off"}});   // ids[0] goes
  }
  EXPECT_EQ(server->post("/api/reset", json{{"session", ids[2]}}.dump()).status, 200);
  EXPECT_EQ(server->post("/api/reset", json{{"session", ids[0]}}.dump()).status, 404);
  EXPECT_EQ(server->post("/api/reset", json{{"session", x}}.dump()).status, 200);
}

TEST_F(Server_test, drags_move_targets_without_refactoring)
{
  json sel;
  const std::string id = selected_session(&sel);
  EXPECT_EQ(sel["handles"], json::array({20 * 41 + 20}));
  EXPECT_GT(sel["roi"].size(), 60u);   // 6 rings around one vertex of a triangulated grid
  EXPECT_EQ(sel["factorizations"], 1);
  EXPECT_EQ(server->number_of_factorizations(id), 1u);
  // the moving vertices: the ROI, then the handles (the order of the drag replies' positions)
  const json moving = sel["moving"];
  ASSERT_EQ(moving.size(), sel["roi"].size() + 1);
  EXPECT_EQ(moving.back(), 20 * 41 + 20);
  for(std::size_t i = 0; i < sel["roi"].size(); ++i)
    EXPECT_EQ(moving[i], sel["roi"][i]);

  const json rest = post("/api/session", {{"mesh", "default"}})["vertices"];
  const std::size_t h = 20 * 41 + 20;
  for(int step = 1; step <= 5; ++step)
  {
    const double dz = 0.02 * step;
    const json d = post("/api/drag", {{"session", id}, {"translation", {0, 0, dz}}, {"iterations", 2}});
    EXPECT_EQ(d["factorizations"], 1);
    EXPECT_EQ(server->number_of_factorizations(id), 1u);
    EXPECT_LT(d["handle_error"].get<double>(), 1e-9);
    EXPECT_EQ(d["positions"].size(), 3 * moving.size());   // the moving vertices only
    EXPECT_EQ(d["count"], moving.size());
    EXPECT_NEAR(coordinate(d, moving, h, 2), rest[3 * h + 2].get<double>() + dz, 1e-9);
    EXPECT_GE(d["seconds"].get<double>(), d["solve_seconds"].get<double>());
    EXPECT_EQ(d["iterations"], 2);
    EXPECT_EQ(d["seq"], step);
  }
  // a rotation about the handle's own centre leaves a single handle where it is
  const json r = post("/api/drag", {{"session", id}, {"rotation", {{"axis", {0, 0, 1}}, {"angle", 0.5}}}});
  EXPECT_NEAR(coordinate(r, moving, h, 2), rest[3 * h + 2].get<double>(), 1e-9);
  const json rt = post("/api/drag", {{"session", id}, {"translation", {0, 0, 0.1}},
                                     {"rotation", {{"axis", {1, 0, 0}}, {"angle", 0.3}, {"center", {0.5, 0, 0}}}}});
  EXPECT_LT(rt["handle_error"].get<double>(), 1e-9);
  EXPECT_EQ(server->number_of_factorizations(id), 1u);

  // the binary frame holds the same positions (as float32) and the same timings' members
  const Reply b = server->post("/api/drag", json{{"session", id}, {"translation", {0, 0, 0.1}}, {"binary", true},
                                                 {"rotation", {{"axis", {1, 0, 0}}, {"angle", 0.3}, {"center", {0.5, 0, 0}}}}}.dump());
  EXPECT_EQ(b.status, 200);
  EXPECT_EQ(b.content_type, "application/octet-stream");
  json header;
  std::vector<float> xyz;
  ASSERT_TRUE(decode_frame(b.body, header, xyz));
  EXPECT_EQ(header["count"], moving.size());
  EXPECT_FALSE(header.contains("positions"));
  EXPECT_LT(header["handle_error"].get<double>(), 1e-9);
  ASSERT_EQ(xyz.size(), 3 * moving.size());
  for(std::size_t i = 0; i < xyz.size(); ++i)
    EXPECT_NEAR(xyz[i], rt["positions"][i].get<double>(), 1e-6) << i;
  EXPECT_LT(b.body.size(), 4 + 1024 + 12 * moving.size());

  // a vertex outside the ROI never moves
  EXPECT_EQ(std::count(moving.begin(), moving.end(), 0), 0);
  {
    std::istringstream off(download(id, "off"));
    Mesh m;
    ASSERT_TRUE(CGAL::IO::read_OFF(off, m));
    EXPECT_EQ(m.point(vertex_descriptor(0)).z(), rest[2].get<double>());
  }
  // the same drag with other policies: a new deformer (one factorisation), a different shape
  const json p = post("/api/policy", {{"session", id}, {"representation", "vertex"}, {"weights", "uniform"},
                                      {"transform", "rotation"}, {"start", "rotation"}});
  EXPECT_EQ(p["policy"]["representation"], "vertex");
  EXPECT_EQ(p["policy"]["start"], "rotation");
  ASSERT_TRUE(p["warnings"].is_array());              // the library's warnings, passed on
  for(const json& w : p["warnings"])
    EXPECT_TRUE(w["kind"].is_string() && w["message"].is_string());
  EXPECT_EQ(p["factorizations"], 1);
  EXPECT_LT(p["handle_error"].get<double>(), 1e-9);
  EXPECT_EQ(p["positions"].size(), 3 * moving.size());
  EXPECT_NE(p["positions"], rt["positions"]);
  // reset: back to rest, selection kept, still one factorisation
  const json z = post("/api/reset", {{"session", id}});
  for(std::size_t i = 0; i < moving.size(); ++i)
    for(int k = 0; k < 3; ++k)
      EXPECT_EQ(z["positions"][3 * i + std::size_t(k)], rest[3 * moving[i].get<std::size_t>() + std::size_t(k)]);
  EXPECT_EQ(z["factorizations"], 1);
  EXPECT_LT(post("/api/drag", {{"session", id}, {"translation", {0.1, 0, 0}}})["handle_error"].get<double>(), 1e-9);
  // reset with the selection: no deformer, drags refused
  post("/api/reset", {{"session", id}, {"selection", true}});
  EXPECT_NE(error("/api/drag", json{{"session", id}}.dump()).find("select a region of interest"), std::string::npos);
}

// A session keeps its deformer across selections and policy changes of one representation: a new
// selection starts from the rest mesh (the previous selection's vertices back at rest, bitwise),
// and every result equals that of a fresh session with the same selection and policies.
TEST_F(Server_test, a_new_selection_keeps_the_deformer_and_starts_from_rest)
{
  auto positions = [](const json& reply) {
    std::vector<double> p;
    for(const json& x : reply["positions"]) p.push_back(x.get<double>());
    return p;
  };
  auto expect_near = [](const std::vector<double>& a, const std::vector<double>& b, const char* what) {
    ASSERT_EQ(a.size(), b.size()) << what;
    double worst = 0;
    for(std::size_t i = 0; i < a.size(); ++i) worst = (std::max)(worst, std::abs(a[i] - b[i]));
    EXPECT_LT(worst, 1e-9) << what;
  };
  const json a_handles = {20 * 41 + 20}, b_handles = {8 * 41 + 30};
  const json drag = {{"translation", {0.05, 0, 0.2}}, {"iterations", 3}};
  // a fresh session per comparison: select, then the policies, then the drag
  auto fresh = [&](const json& handles, int grow, const json& policy) {
    const std::string f = post("/api/session", {{"mesh", "default"}})["session"];
    post("/api/select", {{"session", f}, {"handles", handles}, {"grow", grow}});
    json p = policy;
    p["session"] = f;
    post("/api/policy", p);
    json d = drag;
    d["session"] = f;
    return positions(post("/api/drag", d));
  };
  const std::string id = post("/api/session", {{"mesh", "default"}})["session"];
  const std::string at_rest = download(id, "off");
  post("/api/select", {{"session", id}, {"handles", a_handles}, {"grow", 6}});
  json d = drag;
  d["session"] = id;
  EXPECT_LT(post("/api/drag", d)["handle_error"].get<double>(), 1e-9);
  EXPECT_NE(download(id, "off"), at_rest);

  // another selection, partly overlapping the first: the whole mesh at rest again, one factorisation
  const json sel = post("/api/select", {{"session", id}, {"handles", b_handles}, {"grow", 9}});
  EXPECT_EQ(sel["factorizations"], 1);
  EXPECT_EQ(server->number_of_factorizations(id), 1u);
  EXPECT_EQ(server->deformer_counts(id), std::make_pair(std::size_t(1), std::size_t(2)));   // one deformer, two selections
  EXPECT_EQ(download(id, "off"), at_rest);
  const json b = post("/api/drag", d);
  EXPECT_EQ(b["factorizations"], 1);
  expect_near(positions(b), fresh(b_handles, 9, json::object()), "second selection");

  // a transform or start change keeps the factorisation; a weight change refactors once
  const json t = post("/api/policy", {{"session", id}, {"transform", "rotation"}, {"start", "rotation"}});
  EXPECT_EQ(t["factorizations"], 1);
  EXPECT_EQ(server->number_of_factorizations(id), 1u);
  EXPECT_EQ(server->deformer_counts(id), std::make_pair(std::size_t(1), std::size_t(2)));   // no new factorisation
  expect_near(positions(t), fresh(b_handles, 9, {{"transform", "rotation"}, {"start", "rotation"}}), "transform change");
  const json w = post("/api/policy", {{"session", id}, {"weights", "uniform"}});
  EXPECT_EQ(w["factorizations"], 1);
  EXPECT_EQ(server->deformer_counts(id), std::make_pair(std::size_t(1), std::size_t(3)));
  expect_near(positions(w), fresh(b_handles, 9, {{"transform", "rotation"}, {"start", "rotation"}, {"weights", "uniform"}}),
              "weight change");
  // the other representation (a new deformer) and back, then the first selection again
  const json v = post("/api/policy", {{"session", id}, {"representation", "vertex"}});
  EXPECT_EQ(v["factorizations"], 1);
  const json e = post("/api/policy", {{"session", id}, {"representation", "edge"}});
  EXPECT_EQ(server->deformer_counts(id).first, 3u);
  expect_near(positions(e), positions(w), "representation and back");
  post("/api/select", {{"session", id}, {"handles", a_handles}, {"grow", 6}});
  EXPECT_EQ(download(id, "off"), at_rest);
  expect_near(positions(post("/api/drag", d)),
              fresh(a_handles, 6, {{"transform", "rotation"}, {"start", "rotation"}, {"weights", "uniform"}}),
              "first selection again");
  // the selection cleared by a reset: the mesh at rest, drags refused until the next selection
  post("/api/reset", {{"session", id}, {"selection", true}});
  EXPECT_EQ(download(id, "off"), at_rest);
  EXPECT_EQ(server->number_of_factorizations(id), 0u);
  EXPECT_NE(error("/api/drag", json{{"session", id}}.dump()).find("select a region of interest"), std::string::npos);
}

// The policy names are those of the tools' one catalogue (policy_names.h, also the command line's
// and the harness's): the server takes every name and alias of it, and nothing else.
TEST_F(Server_test, every_policy_name_of_the_catalogue_is_accepted)
{
  for(const auto& t : policy_names::transform_policies())
    for(const char* name : {t.name, t.alias})
    {
      if(name == nullptr)
        continue;
      Policy p;
      p.transform = name;
      EXPECT_NO_THROW(validate_policy(p)) << name;
    }
  for(const auto& w : policy_names::weight_policies())
  {
    Policy p;
    p.weights = w.name;
    EXPECT_NO_THROW(validate_policy(p)) << w.name;
  }
  for(const auto& r : policy_names::representations())
  {
    Policy p;
    p.representation = r.name;
    EXPECT_NO_THROW(validate_policy(p)) << r.name;
  }
  // the editor's default S*R1 name is the catalogue's alias of sr1
  EXPECT_EQ(policy_names::find(policy_names::transform_policies(), Policy().transform),
            &policy_names::transform_policies()[0]);
  Policy bad;
  bad.transform = "SR1";
  EXPECT_THROW(validate_policy(bad), Request_error);

  // a deformation with every transform through the API: one factorisation each
  const std::string id = selected_session();
  post("/api/drag", {{"session", id}, {"translation", {0, 0, 0.2}}});
  for(const auto& t : policy_names::transform_policies())
  {
    const json r = post("/api/policy", {{"session", id}, {"transform", t.name}, {"weights", "uniform"}});
    EXPECT_EQ(r["policy"]["transform"], t.name);
    EXPECT_EQ(r["factorizations"], 1) << t.name;
    EXPECT_LT(r["handle_error"].get<double>(), 1e-9) << t.name;
  }
}

// The lock of one session never blocks another session (nor the mesh list).
TEST_F(Server_test, a_busy_session_does_not_block_another)
{
  const std::string a = selected_session(), b = selected_session();
  auto hold = server->hold_session(a);   // as if a long drag of `a` were running
  auto other = std::async(std::launch::async, [&] {
    return server->post("/api/drag", json{{"session", b}, {"translation", {0, 0, 0.1}}}.dump()).status;
  });
  ASSERT_EQ(other.wait_for(std::chrono::seconds(20)), std::future_status::ready) << "session b waited for session a";
  EXPECT_EQ(other.get(), 200);
  auto list = std::async(std::launch::async, [&] { return server->get("/api/meshes", {}).status; });
  ASSERT_EQ(list.wait_for(std::chrono::seconds(20)), std::future_status::ready);
  EXPECT_EQ(list.get(), 200);
  auto created = std::async(std::launch::async, [&] { return server->post("/api/session", R"({"mesh":"tetra.off"})").status; });
  ASSERT_EQ(created.wait_for(std::chrono::seconds(20)), std::future_status::ready);
  EXPECT_EQ(created.get(), 200);
  // while `a`'s own request waits
  auto mine = std::async(std::launch::async, [&] {
    return server->post("/api/drag", json{{"session", a}, {"translation", {0, 0, 0.1}}}.dump()).status;
  });
  EXPECT_EQ(mine.wait_for(std::chrono::milliseconds(200)), std::future_status::timeout);
  hold.unlock();
  EXPECT_EQ(mine.get(), 200);
}

// A drag queued behind the session's lock is dropped unsolved when a newer one arrives; an older
// drag is never applied after a newer one.
TEST_F(Server_test, a_newer_drag_supersedes_a_queued_one)
{
  const std::string id = selected_session();
  const std::size_t h = 20 * 41 + 20;
  auto drag = [&](int seq, double dz) {
    return server->post("/api/drag", json{{"session", id}, {"seq", seq}, {"translation", {0, 0, dz}}}.dump());
  };
  std::unique_lock<std::mutex> hold = server->hold_session(id);   // a long drag is running
  auto first = std::async(std::launch::async, [&] { return drag(1, 0.1); });
  while(server->newest_drag(id) < 1) std::this_thread::yield();
  auto second = std::async(std::launch::async, [&] { return drag(2, 0.2); });
  while(server->newest_drag(id) < 2) std::this_thread::yield();
  hold.unlock();
  const Reply r1 = first.get(), r2 = second.get();
  EXPECT_EQ(r1.status, 409) << r1.body;
  const json j1 = json::parse(r1.body);
  EXPECT_EQ(j1["superseded"], true);
  EXPECT_NE(j1["error"].get<std::string>().find("superseded: drag 1 of this session was overtaken by drag 2"), std::string::npos);
  ASSERT_EQ(r2.status, 200) << r2.body;
  EXPECT_EQ(json::parse(r2.body)["seq"], 2);
  // an older drag arriving late is refused, and the mesh stays at the newer one
  EXPECT_EQ(drag(1, 0.5).status, 409);
  std::istringstream off(download(id, "off"));
  Mesh m;
  ASSERT_TRUE(CGAL::IO::read_OFF(off, m));
  EXPECT_NEAR(m.point(vertex_descriptor(h)).z(), 0.2, 1e-9);
  // without "seq" a drag is numbered on arrival, after the newest
  const json d = post("/api/drag", {{"session", id}, {"translation", {0, 0, 0.3}}});
  EXPECT_EQ(d["seq"], 3);
  EXPECT_NE(error("/api/drag", json{{"session", id}, {"seq", 0}}.dump()).find("seq must be in [1, "), std::string::npos);
  EXPECT_NE(error("/api/drag", json{{"session", id}, {"binary", 1}}.dump()).find("binary must be true or false"),
            std::string::npos);
}

TEST_F(Server_test, selection_without_handles_is_refused_and_leaves_the_mesh_at_rest)
{
  const std::string id = post("/api/session", {{"mesh", "tetra.off"}})["session"];
  const std::string before = download(id, "off");
  EXPECT_NE(error("/api/select", json{{"session", id}, {"roi", {0, 1, 2, 3}}, {"handles", json::array()}}.dump())
                .find("handles must hold at least one vertex"), std::string::npos);
  EXPECT_EQ(download(id, "off"), before);
}

TEST_F(Server_test, downloads_and_saves)
{
  const std::string id = selected_session();
  post("/api/drag", {{"session", id}, {"translation", {0, 0, 0.25}}});
  std::istringstream off(download(id, "off"));
  Mesh m;
  ASSERT_TRUE(CGAL::IO::read_OFF(off, m));
  EXPECT_EQ(num_vertices(m), 41u * 41u);
  EXPECT_NEAR(m.point(vertex_descriptor(20 * 41 + 20)).z(), 0.25, 1e-9);   // the bumpy plane is 0 there
  std::istringstream ply(download(id, "ply"));
  Mesh m2;
  ASSERT_TRUE(CGAL::IO::read_PLY(ply, m2));
  EXPECT_EQ(num_faces(m2), 2u * 40 * 40);

  std::istringstream sel(download(id, "sel"));
  std::vector<int> status;
  std::string message;
  ASSERT_TRUE(LD::IO::read_botsch08_selection(sel, status, message, 41 * 41)) << message;
  EXPECT_EQ(std::count(status.begin(), status.end(), 2), 1);
  EXPECT_GT(std::count(status.begin(), status.end(), 1), 60);
  std::istringstream def(download(id, "def"));
  Eigen::Matrix4d t;
  ASSERT_TRUE(LD::IO::read_botsch08_transform(def, t, message)) << message;
  EXPECT_DOUBLE_EQ(t(2, 3), 0.25);
  EXPECT_TRUE((t.topLeftCorner<3, 3>().isIdentity(1e-15)));

  // save: only under the output folder, and only plain names
  for(const char* bad : {"../evil", "/tmp/evil", "a/b", "", ".hidden", "-rf", "--output", "pose.off", "pose.exe", "a\\b",
                         "x y", "\xc3\xa9t\xc3\xa9"})
    EXPECT_NE(error("/api/save", json{{"session", id}, {"name", bad}}.dump()).find("name must be 1 to 64 letters"),
              std::string::npos) << bad;
  EXPECT_NE(error("/api/save", json{{"session", id}, {"name", std::string(65, 'a')}}.dump()).find("name must be"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(root / "evil.off"));
  const json saved = post("/api/save", {{"session", id}, {"name", "pose_1"}});
  EXPECT_EQ(saved["files"].size(), 3u);
  for(const char* ext : {".off", ".sel", ".def"})
    EXPECT_TRUE(fs::is_regular_file(root / "out" / (std::string("pose_1") + ext))) << ext;
  std::size_t files = 0;
  for(const auto& e : fs::recursive_directory_iterator(root))
    files += e.is_regular_file();
  EXPECT_EQ(files, 2u + 3u);   // tetra.off, secret.off and the three saved files
}

TEST_F(Server_test, static_files_stay_in_their_folders)
{
  const std::string viewer = options.viewer_dir;
  EXPECT_TRUE(static_file(viewer, "/").has_value());
  EXPECT_TRUE(static_file(viewer, "/editor.js").has_value());
  EXPECT_TRUE(static_file(viewer, "/lib/mesh.js").has_value());
  const Reply js = get_static(viewer, "/lib/mesh.js");
  EXPECT_EQ(js.content_type, "application/javascript; charset=utf-8");
  EXPECT_EQ(js.cache_control, "no-cache");   // revalidated: 304 when unchanged
  ASSERT_FALSE(js.etag.empty());
  const Reply again = get_static(viewer, "/lib/mesh.js", js.etag);
  EXPECT_EQ(again.status, 304);
  EXPECT_TRUE(again.body.empty());
  EXPECT_EQ(get_static(viewer, "/lib/mesh.js", "\"other\"").status, 200);
  EXPECT_NE(get_static(viewer, "/").body.find("<html"), std::string::npos);
  for(const char* bad : {"/../CMakeLists.txt", "/lib/../editor.html", "/three/../../package.json", "/lib/x%00.js",
                         "/test/unit.mjs", "/package.json", "/serve.mjs", "/lib/", "/three/..", "\\lib\\mesh.js",
                         "/lib/missing.js", std::string("/lib/a\0.js", 10).c_str()})
    EXPECT_EQ(get_static(viewer, bad).status, 404) << bad;
}

// --viewer, then the environment variable, then viewer/ next to the executable, then
// ../share/laplacian_deformation/viewer: no source path compiled in.
TEST_F(Server_test, the_viewer_files_are_found_next_to_the_executable)
{
  const fs::path prefix = root / "prefix";
  fs::create_directories(prefix / "bin");
  fs::create_directories(prefix / "share" / "laplacian_deformation" / "viewer");
  std::ofstream(prefix / "share" / "laplacian_deformation" / "viewer" / "editor.html") << "<html>";
  const fs::path exe = prefix / "bin" / "laplacian_deform";
  const fs::path share = (prefix / "share" / "laplacian_deformation" / "viewer").lexically_normal();
  EXPECT_EQ(find_viewer_dir("", nullptr, exe), share.string());
  fs::create_directories(prefix / "bin" / "viewer");
  std::ofstream(prefix / "bin" / "viewer" / "editor.html") << "<html>";
  EXPECT_EQ(find_viewer_dir("", nullptr, exe), (prefix / "bin" / "viewer").lexically_normal().string());
  EXPECT_EQ(find_viewer_dir("", options.viewer_dir.c_str(), exe), fs::path(options.viewer_dir).lexically_normal().string());
  EXPECT_EQ(find_viewer_dir(share.string(), options.viewer_dir.c_str(), exe), share.string());
  std::vector<std::string> tried;
  EXPECT_EQ(find_viewer_dir("", nullptr, root / "elsewhere" / "laplacian_deform", &tried), "");
  EXPECT_EQ(tried.size(), 2u);
  EXPECT_EQ(find_viewer_dir((root / "none").string(), nullptr, exe), "");   // an explicit folder is not second-guessed
}

// The guard without sockets: every refusal names its reason.
TEST_F(Server_test, the_guard_refuses_other_hosts_origins_tokens_and_types)
{
  const std::string token = options.token;
  Request_facts ok;
  ok.method = "POST";
  ok.path = "/api/drag";
  ok.host = "127.0.0.1:8123";
  ok.content_type = "application/json";
  ok.token_header = token;
  EXPECT_FALSE(refusal(ok, 8123, token));
  auto refused = [&](Request_facts f, int status, const std::string& text) {
    const std::optional<Reply> r = refusal(f, 8123, token);
    ASSERT_TRUE(r) << text;
    EXPECT_EQ(r->status, status);
    EXPECT_NE(r->body.find(text), std::string::npos) << r->body;
  };
  Request_facts f = ok;
  f.host = "localhost:8123"; EXPECT_FALSE(refusal(f, 8123, token));
  f.host = "LOCALHOST:8123"; EXPECT_FALSE(refusal(f, 8123, token));
  for(const char* host : {"evil.example:8123", "127.0.0.1:8124", "127.0.0.1", "", "127.0.0.1:8123.evil.example", "0.0.0.0:8123"})
  {
    f = ok; f.host = host;
    refused(f, 403, "is not 127.0.0.1:8123 or localhost:8123");
  }
  f = ok; f.path = "/editor.js"; f.method = "GET"; f.host = "rebind.example:8123";
  refused(f, 403, "the Host header");   // static files too
  f = ok; f.has_origin = true; f.origin = "http://localhost:8123"; EXPECT_FALSE(refusal(f, 8123, token));
  for(const char* origin : {"http://evil.example", "null", "", "https://127.0.0.1:8123", "http://127.0.0.1:8124"})
  {
    f = ok; f.has_origin = true; f.origin = origin;
    refused(f, 403, "from another site");
  }
  f = ok; f.host = "\xff\xfe:8123";
  refused(f, 403, "is not 127.0.0.1:8123");   // not UTF-8: still a JSON message
  EXPECT_TRUE(json::parse(refusal(f, 8123, token)->body, nullptr, false).is_object());
  f = ok; f.token_header = ""; refused(f, 401, "missing token");
  f = ok; f.token_header = token + "x"; refused(f, 401, "wrong token");
  f = ok; f.token_header = ""; f.token_query = token; refused(f, 401, "token");   // a POST needs the header
  f = ok; f.method = "GET"; f.path = "/api/download"; f.token_header = ""; f.token_query = token;
  EXPECT_FALSE(refusal(f, 8123, token));
  f = ok; f.path = "/"; f.method = "GET"; f.token_header = ""; EXPECT_FALSE(refusal(f, 8123, token));   // the page needs none
  f = ok; f.content_type = "application/json; charset=utf-8"; EXPECT_FALSE(refusal(f, 8123, token));
  for(const char* type : {"text/plain", "", "application/x-www-form-urlencoded", "multipart/form-data; boundary=x",
                          "application/jsonx"})
  {
    f = ok; f.content_type = type;
    refused(f, 415, "Content-Type: application/json");
  }
}

struct Http_test : Server_test
{
  httplib::Server http;
  Http_guard guard;
  std::thread thread;
  int port = 0;
  std::unique_ptr<httplib::Client> client;
  httplib::Headers headers;

  void start()
  {
    server = std::make_unique<Deformation_server>(options);
    guard.token = options.token;
    install_routes(http, *server, guard);
    port = http.bind_to_any_port("127.0.0.1");
    ASSERT_GT(port, 0);
    guard.port = port;
    thread = std::thread([this] { http.listen_after_bind(); });
    client = std::make_unique<httplib::Client>("127.0.0.1", port);
    client->set_connection_timeout(5);
    client->set_decompress(false);
    headers = {{"X-Editor-Token", options.token}, {"Accept-Encoding", "br, gzip, deflate"}};
  }
  void TearDown() override
  {
    http.stop();
    if(thread.joinable()) thread.join();
    Server_test::TearDown();
  }
  httplib::Result post(const std::string& path, const std::string& body, httplib::Headers h, const char* type = "application/json")
  {
    return client->Post(path.c_str(), h, body, type);
  }
  std::string error_of(const httplib::Result& r)
  {
    const json j = json::parse(r->body, nullptr, false);
    return j.is_object() && j.contains("error") ? j["error"].get<std::string>() : "(no error member: " + r->body + ")";
  }
};

TEST_F(Http_test, round_trip_over_a_socket_uncompressed_and_cacheable)
{
  start();
  auto created = post("/api/session", R"({"mesh":"default"})", headers);
  ASSERT_TRUE(created);
  EXPECT_EQ(created->status, 200);
  EXPECT_FALSE(created->has_header("Content-Encoding")) << created->get_header_value("Content-Encoding");
  EXPECT_EQ(created->get_header_value("Cache-Control"), "no-store");
  const std::string id = json::parse(created->body)["session"];
  auto bad = post("/api/select", "{\"session\":\"" + id + "\",\"handles\":[99999]}", headers);
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
  EXPECT_NE(bad->body.find("unknown vertex id 99999"), std::string::npos);
  auto garbage = post("/api/drag", std::string("\xff\xfe{", 3), headers);
  ASSERT_TRUE(garbage);
  EXPECT_EQ(garbage->status, 400);
  ASSERT_EQ(post("/api/select", "{\"session\":\"" + id + "\",\"handles\":[840],\"grow\":8}", headers)->status, 200);
  // the drag replies, JSON and binary, are not compressed although the client accepts br and gzip
  for(const char* binary : {"false", "true"})
  {
    auto d = post("/api/drag", "{\"session\":\"" + id + "\",\"translation\":[0,0,0.2],\"binary\":" + binary + "}", headers);
    ASSERT_TRUE(d);
    EXPECT_EQ(d->status, 200);
    EXPECT_FALSE(d->has_header("Content-Encoding")) << binary << ": " << d->get_header_value("Content-Encoding");
    EXPECT_EQ(d->get_header_value("Content-Type"), std::string(binary) == "true" ? "application/octet-stream"
                                                                                 : "application/json; charset=utf-8");
  }
  // static files: uncompressed JavaScript, an ETag and a 304 on revalidation; three.js cached a day
  auto page = client->Get("/", headers);
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_NE(page->get_header_value("Content-Type").find("text/html"), std::string::npos);
  auto js = client->Get("/editor.js", headers);
  ASSERT_TRUE(js);
  EXPECT_EQ(js->status, 200);
  EXPECT_FALSE(js->has_header("Content-Encoding"));
  EXPECT_EQ(js->get_header_value("Cache-Control"), "no-cache");
  httplib::Headers revalidate = headers;
  revalidate.emplace("If-None-Match", js->get_header_value("ETag"));
  auto js304 = client->Get("/editor.js", revalidate);
  ASSERT_TRUE(js304);
  EXPECT_EQ(js304->status, 304);
  if(fs::is_regular_file(fs::path(options.viewer_dir) / "node_modules/three/build/three.core.js"))
  {
    auto three = client->Get("/three/build/three.core.js", headers);
    ASSERT_TRUE(three);
    EXPECT_EQ(three->status, 200);
    EXPECT_FALSE(three->has_header("Content-Encoding"));
    EXPECT_EQ(three->get_header_value("Cache-Control"), "public, max-age=86400");
  }
  auto escape = client->Get("/%2e%2e/CMakeLists.txt", headers);
  ASSERT_TRUE(escape);
  EXPECT_NE(escape->status, 200);
  // a download link carries the token in its query (a link cannot set headers)
  auto file = client->Get(("/api/download?format=def&session=" + id + "&token=" + options.token).c_str());
  ASSERT_TRUE(file);
  EXPECT_EQ(file->status, 200);
  EXPECT_EQ(file->get_header_value("Content-Disposition"), "attachment; filename=\"bumpy_plane.def\"");
  EXPECT_NE(file->body.find("4x4 handle transformation"), std::string::npos);
}

// Every refusal over a real socket: the status and a message in the body, and nothing done.
TEST_F(Http_test, every_refusal_over_a_socket)
{
  options.max_body_bytes = 4096;
  start();
  auto created = post("/api/session", R"({"mesh":"tetra.off"})", headers);
  ASSERT_TRUE(created);
  ASSERT_EQ(created->status, 200);
  const std::size_t sessions = server->number_of_sessions();
  const std::string body = R"({"mesh":"tetra.off"})";
  auto expect = [&](const httplib::Result& r, int status, const std::string& text, const char* what) {
    ASSERT_TRUE(r) << what;
    EXPECT_EQ(r->status, status) << what << ": " << r->body;
    EXPECT_NE(error_of(r).find(text), std::string::npos) << what << ": " << r->body;
  };
  httplib::Headers h = headers;
  h.emplace("Host", "rebind.example:" + std::to_string(port));
  expect(post("/api/session", body, h), 403, "the Host header \"rebind.example", "DNS rebinding Host");
  expect(client->Get("/api/meshes", h), 403, "the Host header", "DNS rebinding Host, GET");
  h = headers;
  h.emplace("Origin", "http://evil.example");
  expect(post("/api/session", body, h), 403, "from another site (Origin \"http://evil.example\")", "foreign Origin");
  h = headers;
  h.emplace("Origin", "null");
  expect(post("/api/session", body, h), 403, "from another site", "null Origin");
  expect(post("/api/session", body, {}), 401, "missing token", "no token");
  expect(client->Get("/api/meshes"), 401, "missing token", "no token, GET");
  expect(post("/api/session", body, {{"X-Editor-Token", "guess"}}), 401, "wrong token", "wrong token");
  expect(client->Get("/api/meshes?token=guess"), 401, "wrong token", "wrong token in the query");
  expect(post("/api/session", body, headers, "text/plain"), 415, "Content-Type: application/json", "text/plain");
  expect(post("/api/session", body, headers, "application/x-www-form-urlencoded"), 415, "application/json", "form");
  expect(post("/api/session", "--x\r\nContent-Disposition: form-data; name=\"a\"\r\n\r\n1\r\n--x--\r\n", headers,
              "multipart/form-data; boundary=x"), 415, "application/json", "multipart");
  expect(post("/api/session", std::string(5000, ' ') + body, headers), 413, "larger than the limit of 4096 bytes", "413");
  expect(post("/api/nothing", "{}", headers), 404, "no such API", "unknown API");
  EXPECT_EQ(server->number_of_sessions(), sessions);   // none of them created a session
  // the page itself is served without a token, but not to another Host
  auto page = client->Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
}

// A port in use is an error naming it, not a second server sharing the port.
TEST_F(Server_test, a_port_in_use_is_an_error)
{
  const int holder = ::socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_GE(holder, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = 0;
  ASSERT_EQ(::bind(holder, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  ASSERT_EQ(::listen(holder, 4), 0);
  socklen_t length = sizeof address;
  ASSERT_EQ(::getsockname(holder, reinterpret_cast<sockaddr*>(&address), &length), 0);
  const int port = ntohs(address.sin_port);
  options.port = port;
  ::testing::internal::CaptureStderr();
  const int status = run_deformation_server(options);
  const std::string text = ::testing::internal::GetCapturedStderr();
  ::close(holder);
  EXPECT_EQ(status, 1);
  EXPECT_NE(text.find("cannot listen on 127.0.0.1:" + std::to_string(port)), std::string::npos) << text;
  EXPECT_NE(text.find("in use"), std::string::npos) << text;
  // and an httplib server holding the port (SO_REUSEPORT, cpp-httplib's default) does not let a
  // second one in either
  httplib::Server first;
  const int p = first.bind_to_any_port("127.0.0.1");
  ASSERT_GT(p, 0);
  httplib::Server second;
  Server_options o = options;
  o.port = p;
  EXPECT_EQ(bind_exclusively(second, o), -1);
}

} // namespace
