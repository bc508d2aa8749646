// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// laplacian_deform --serve (demo/Laplacian_deformation/deformation_server.h): the JSON API through
// its handler layer (no sockets): malformed requests get 4xx with a clear error and change
// nothing, a drag never refactors, policies re-apply the same drag, downloads and saves stay in
// their folder, the static file guard; then a few requests over a real socket (httplib::Client).
#include "deformation_server.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

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
  EXPECT_NE(error("/api/reset", "{" + s + ",\"selection\":\"yes\"}").find("selection must be true or false"),
            std::string::npos);
  EXPECT_NE(error("/api/nothing", "{}", 404).find("no such API"), std::string::npos);
  EXPECT_EQ(server->get("/api/download", {{"session", id}, {"format", "exe"}}).status, 400);
  EXPECT_EQ(server->get("/api/download", {{"format", "off"}}).status, 400);

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
  for(const char* bad : {"../secret.off", "/etc/passwd", "..", "data/tetra.off", "tetra.exe", ".off"})
    EXPECT_NE(error("/api/session", json{{"mesh", bad}}.dump()).find("mesh must be \"default\" or a file name"),
              std::string::npos) << bad;
  EXPECT_NE(error("/api/session", R"({"mesh":"missing.off"})").find("cannot read a mesh from missing.off"),
            std::string::npos);
  EXPECT_NE(error("/api/session", R"({"mesh":3})").find("mesh must be a string"), std::string::npos);
}

TEST_F(Server_test, sessions_are_bounded)
{
  options.max_sessions = 3;
  server = std::make_unique<Deformation_server>(options);
  std::vector<std::string> ids;
  for(int i = 0; i < 5; ++i)
    ids.push_back(post("/api/session", {{"mesh", "tetra.off"}})["session"]);
  EXPECT_EQ(server->number_of_sessions(), 3u);
  EXPECT_EQ(server->post("/api/reset", json{{"session", ids[0]}}.dump()).status, 404);   // the oldest went
  EXPECT_EQ(server->post("/api/reset", json{{"session", ids[4]}}.dump()).status, 200);
}

TEST_F(Server_test, drags_move_targets_without_refactoring)
{
  json sel;
  const std::string id = selected_session(&sel);
  EXPECT_EQ(sel["handles"], json::array({20 * 41 + 20}));
  EXPECT_GT(sel["roi"].size(), 60u);   // 6 rings around one vertex of a triangulated grid
  EXPECT_EQ(sel["factorizations"], 1);
  EXPECT_EQ(server->number_of_factorizations(id), 1u);

  const json rest = post("/api/session", {{"mesh", "default"}})["vertices"];
  const std::size_t h = 20 * 41 + 20;
  for(int step = 1; step <= 5; ++step)
  {
    const double dz = 0.02 * step;
    const json d = post("/api/drag", {{"session", id}, {"translation", {0, 0, dz}}, {"iterations", 2}});
    EXPECT_EQ(d["factorizations"], 1);
    EXPECT_EQ(server->number_of_factorizations(id), 1u);
    EXPECT_LT(d["handle_error"].get<double>(), 1e-9);
    EXPECT_NEAR(d["positions"][3 * h + 2].get<double>(), rest[3 * h + 2].get<double>() + dz, 1e-9);
    EXPECT_GE(d["seconds"].get<double>(), d["solve_seconds"].get<double>());
    EXPECT_EQ(d["iterations"], 2);
  }
  // a rotation about the handle's own centre leaves a single handle where it is
  const json r = post("/api/drag", {{"session", id}, {"rotation", {{"axis", {0, 0, 1}}, {"angle", 0.5}}}});
  EXPECT_NEAR(r["positions"][3 * h + 2].get<double>(), rest[3 * h + 2].get<double>(), 1e-9);
  const json rt = post("/api/drag", {{"session", id}, {"translation", {0, 0, 0.1}},
                                     {"rotation", {{"axis", {1, 0, 0}}, {"angle", 0.3}, {"center", {0.5, 0, 0}}}}});
  EXPECT_LT(rt["handle_error"].get<double>(), 1e-9);
  EXPECT_EQ(server->number_of_factorizations(id), 1u);

  // a vertex outside the ROI never moves
  EXPECT_EQ(rt["positions"][0], rest[0]);
  // the same drag with other policies: a new deformer (one factorisation), a different shape
  const json p = post("/api/policy", {{"session", id}, {"representation", "vertex"}, {"weights", "uniform"},
                                      {"transform", "rotation"}});
  EXPECT_EQ(p["policy"]["representation"], "vertex");
  EXPECT_EQ(p["factorizations"], 1);
  EXPECT_LT(p["handle_error"].get<double>(), 1e-9);
  EXPECT_NE(p["positions"], rt["positions"]);
  // reset: back to rest, selection kept, still one factorisation
  const json z = post("/api/reset", {{"session", id}});
  EXPECT_EQ(z["positions"], rest);
  EXPECT_EQ(z["factorizations"], 1);
  EXPECT_LT(post("/api/drag", {{"session", id}, {"translation", {0.1, 0, 0}}})["handle_error"].get<double>(), 1e-9);
  // reset with the selection: no deformer, drags refused
  post("/api/reset", {{"session", id}, {"selection", true}});
  EXPECT_NE(error("/api/drag", json{{"session", id}}.dump()).find("select a region of interest"), std::string::npos);
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
  for(const char* bad : {"../evil", "/tmp/evil", "a/b", "", ".hidden"})
    EXPECT_NE(error("/api/save", json{{"session", id}, {"name", bad}}.dump()).find("name must be"), std::string::npos)
        << bad;
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
  EXPECT_TRUE(server->static_file("/").has_value());
  EXPECT_TRUE(server->static_file("/editor.js").has_value());
  EXPECT_TRUE(server->static_file("/lib/mesh.js").has_value());
  EXPECT_EQ(server->get_static("/lib/mesh.js").content_type, "text/javascript; charset=utf-8");
  EXPECT_NE(server->get_static("/").body.find("<html"), std::string::npos);
  for(const char* bad : {"/../CMakeLists.txt", "/lib/../editor.html", "/three/../../package.json", "/lib/x%00.js",
                         "/test/unit.mjs", "/package.json", "/serve.mjs", "/lib/", "/three/..", "\\lib\\mesh.js",
                         "/lib/missing.js", std::string("/lib/a\0.js", 10).c_str()})
    EXPECT_EQ(server->get_static(bad).status, 404) << bad;
}

TEST_F(Server_test, http_round_trip_over_a_socket)
{
  httplib::Server http;
  install_routes(http, *server);
  const int port = http.bind_to_any_port("127.0.0.1");
  ASSERT_GT(port, 0);
  std::thread thread([&http] { http.listen_after_bind(); });
  httplib::Client client("127.0.0.1", port);
  client.set_connection_timeout(5);
  auto created = client.Post("/api/session", R"({"mesh":"default"})", "application/json");
  ASSERT_TRUE(created);
  EXPECT_EQ(created->status, 200);
  const std::string id = json::parse(created->body)["session"];
  auto bad = client.Post("/api/select", "{\"session\":\"" + id + "\",\"handles\":[99999]}", "application/json");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
  EXPECT_NE(bad->body.find("unknown vertex id 99999"), std::string::npos);
  auto garbage = client.Post("/api/drag", std::string("\xff\xfe{", 3), "application/json");
  ASSERT_TRUE(garbage);
  EXPECT_EQ(garbage->status, 400);
  auto page = client.Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_NE(page->get_header_value("Content-Type").find("text/html"), std::string::npos);
  auto escape = client.Get("/%2e%2e/CMakeLists.txt");
  ASSERT_TRUE(escape);
  EXPECT_NE(escape->status, 200);
  auto file = client.Get(("/api/download?format=def&session=" + id).c_str());
  ASSERT_TRUE(file);
  EXPECT_EQ(file->status, 200);
  EXPECT_EQ(file->get_header_value("Content-Disposition"), "attachment; filename=\"bumpy_plane.def\"");
  EXPECT_NE(file->body.find("4x4 handle transformation"), std::string::npos);
  http.stop();
  thread.join();
}

} // namespace
