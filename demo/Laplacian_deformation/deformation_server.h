// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// laplacian_deform --serve: interactive editing in the browser. A local HTTP server (cpp-httplib,
// 127.0.0.1 only) serves the editor page (viewer/editor.html, viewer/editor.js, viewer/lib/ and
// three.js from viewer/node_modules) and a JSON API (nlohmann-json). Each browser session owns one
// Mesh_deformer: a selection is preprocessed (factored) once, and each drag only moves the handle
// targets and re-solves. Not part of the library: a demo tool's header.
//
// Parts (deformation_server/): `deformer.h` the type-erased deformer and the drag's motion;
// `requests.h` the checks of the requests' members and the encodings of the replies; `session.h`
// one session's state and operations; `sessions.h` `Deformation_server`, the API without sockets
// (per-session locks, drag coalescing, bounded sessions); `http.h` the guard (Host, Origin,
// token, content type), the static files and the routes of an httplib::Server. This file:
// finding the viewer files, binding, and the command line. The API is described in the user
// manual (section "Interactive Editor").
#ifndef LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_H
#define LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_H

#include "deformation_server/http.h"

#include <sys/socket.h>

#include <cstdlib>
#include <iostream>

namespace Laplacian_deformation_server {

/// The folder holding editor.html: `explicit_dir` (--viewer) if given; else the environment
/// variable LAPLACIAN_DEFORM_VIEWER_DIR (`env`, may be null); else `viewer` next to the executable
/// (`executable`: its path; the build tree links it there); else
/// `../share/laplacian_deformation/viewer` from the executable's folder (the installed layout).
/// Empty if none holds editor.html; `tried` gets the folders looked at.
inline std::string find_viewer_dir(const std::string& explicit_dir, const char* env, const fs::path& executable,
                                   std::vector<std::string>* tried = nullptr)
{
  std::vector<fs::path> candidates;
  if(!explicit_dir.empty()) candidates.push_back(explicit_dir);
  else
  {
    if(env && *env) candidates.push_back(env);
    if(!executable.empty())
    {
      const fs::path bin = executable.parent_path();
      candidates.push_back(bin / "viewer");
      candidates.push_back(bin / ".." / "share" / "laplacian_deformation" / "viewer");
    }
  }
  for(const fs::path& c : candidates)
  {
    if(tried) tried->push_back(c.lexically_normal().string());
    if(fs::is_regular_file(c / "editor.html"))
      return c.lexically_normal().string();
  }
  return std::string();
}

/// The running executable's path (/proc/self/exe; else `argv0`).
inline fs::path executable_path(const char* argv0)
{
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if(!ec) return self;
  return argv0 ? fs::absolute(argv0, ec) : fs::path();
}

/// Binds `http` to options.host:options.port (0: any free port) with TCP_NODELAY, without SO_REUSEPORT (cpp-httplib
/// sets it by default: a second server on a taken port would then start, and the kernel would
/// split the connections between the two). Returns the port, or -1 if it is taken or unusable.
inline int bind_exclusively(httplib::Server& http, const Server_options& options)
{
  http.set_socket_options([](socket_t sock) {
    int yes = 1;   // SO_REUSEADDR alone: a restart may reuse a port in TIME_WAIT, not a listening one
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, reinterpret_cast<void*>(&yes), sizeof(yes));
  });
  // and no Nagle delay: a reply's header and body are written separately, and the second write
  // would wait for the client's (delayed) acknowledgement of the first
  http.set_tcp_nodelay(true);
  if(options.port == 0)
    return http.bind_to_any_port(options.host);
  return http.bind_to_port(options.host, options.port) ? options.port : -1;
}

/// Serves until the process is stopped; returns a process exit status (1 if the port cannot be bound).
inline int run_deformation_server(Server_options options)
{
  if(!options.mesh.empty() && !fs::is_regular_file(options.mesh))
  {
    std::cerr << "error: cannot read a mesh from \"" << options.mesh << "\"" << std::endl;
    return 1;
  }
  if(!fs::is_regular_file(fs::path(options.viewer_dir) / "editor.html"))
  {
    std::cerr << "error: no editor page in \"" << options.viewer_dir << "\"" << std::endl;
    return 1;
  }
  if(!fs::is_regular_file(fs::path(options.viewer_dir) / "node_modules/three/build/three.module.js"))
    std::cerr << "warning: three.js is missing: run `npm ci` in " << options.viewer_dir << std::endl;
  if(options.token.empty())
    options.token = random_token();
  httplib::Server http;
  const int port = bind_exclusively(http, options);
  if(port <= 0)
  {
    std::cerr << "error: cannot listen on " << options.host << ":" << options.port
              << (options.port ? " (is the port in use? another laplacian_deform --serve, or choose one with --port N; "
                                 "--port 0 takes any free port)"
                               : "") << std::endl;
    return 1;
  }
  Deformation_server server(options);
  {   // the default mesh must load: fail now rather than in the page (the server keeps the mesh
      // it has read, so the page's first session does not read it again; the binary reply skips
      // the JSON of every coordinate)
    const Reply r = server.post("/api/session", R"({"mesh":"default","binary":true})");
    if(r.status != 200)
    {
      std::cerr << "error: " << json::parse(r.body)["error"].get<std::string>() << std::endl;
      return 1;
    }
    json header;   // only the frame's header: its session
    internal::frame_header(r.body, 8, header);
    server.post("/api/close", json{{"session", header.value("session", std::string())}}.dump());
  }
  Http_guard guard;
  guard.token = options.token;
  guard.port = port;
  install_routes(http, server, guard);
  std::cout << "laplacian_deform: editor at http://" << options.host << ":" << port << "/#token=" << options.token
            << " (Ctrl-C stops)" << std::endl;
  return http.listen_after_bind() ? 0 : 1;
}

/// Parses `--serve [MESH] [--port N] [--output DIR] [--viewer DIR]` (argv[1] is "--serve");
/// returns the exit status.
inline int serve_main(int argc, char** argv, const std::string& data_dir)
{
  Server_options o;
  o.data_dir = data_dir;
  std::string viewer;
  for(int i = 2; i < argc; ++i)
  {
    const std::string a = argv[i];
    if((a == "--port" || a == "--output" || a == "--viewer") && i + 1 >= argc)
    {
      std::cerr << "error: " << a << " needs a value" << std::endl;
      return 2;
    }
    if(a == "--port")
    {
      const std::string v = argv[++i];
      char* end = nullptr;
      const long p = std::strtol(v.c_str(), &end, 10);
      if(v.empty() || *end != '\0' || p < 0 || p > 65535)
      {
        std::cerr << "error: --port needs a number in [0, 65535], got \"" << v << "\"" << std::endl;
        return 2;
      }
      o.port = int(p);
    }
    else if(a == "--output") o.output_dir = argv[++i];
    else if(a == "--viewer") viewer = argv[++i];
    else if(a == "--help" || a == "-h")
    {
      std::cout << "usage: laplacian_deform --serve [MESH] [--port N] [--output DIR] [--viewer DIR]\n"
                   "  Interactive editor at http://127.0.0.1:N/#token=... (default N 8080; 0: any free port);\n"
                   "  open the printed address (its token is required by every API call).\n"
                   "  MESH is the default mesh (default: CGAL's cactus); the page may also open the meshes\n"
                   "  of the data folder. Saved files go to DIR only (default laplacian_deform_output).\n"
                   "  The page's files: --viewer DIR, else $LAPLACIAN_DEFORM_VIEWER_DIR, else viewer/ next to\n"
                   "  the executable, else ../share/laplacian_deformation/viewer from its folder.\n";
      return 0;
    }
    else if(!a.empty() && a[0] != '-' && o.mesh.empty()) o.mesh = a;
    else
    {
      std::cerr << "error: unexpected argument \"" << a << "\" (laplacian_deform --serve --help)" << std::endl;
      return 2;
    }
  }
  std::vector<std::string> tried;
  o.viewer_dir = find_viewer_dir(viewer, std::getenv("LAPLACIAN_DEFORM_VIEWER_DIR"), executable_path(argv[0]), &tried);
  if(o.viewer_dir.empty())
  {
    std::cerr << "error: no editor page (editor.html) in";
    for(const std::string& t : tried) std::cerr << " " << t;
    std::cerr << " (give the viewer folder with --viewer DIR or LAPLACIAN_DEFORM_VIEWER_DIR)" << std::endl;
    return 1;
  }
  return run_deformation_server(o);
}

} // namespace Laplacian_deformation_server

#endif // LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_H
