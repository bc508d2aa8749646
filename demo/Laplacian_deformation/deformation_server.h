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
// Layers: `Deformation_server` answers requests given as a path and a body (testable without
// sockets); `install_routes()` maps them onto an httplib::Server; `run_deformation_server()`
// binds, prints the address and serves until killed. The API is described in the user manual
// (section "Interactive Editor").
#ifndef LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_H
#define LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_H

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/Laplacian_deformation/Mesh_deformer.h>
#include <CGAL/Laplacian_deformation/Edge_based_representation.h>
#include <CGAL/Laplacian_deformation/Vertex_based_representation.h>
#include <CGAL/Laplacian_deformation/Cotangent_weights.h>
#include <CGAL/Laplacian_deformation/Uniform_weights.h>
#include <CGAL/Laplacian_deformation/Rotation_transform.h>
#include <CGAL/Laplacian_deformation/Scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Similarity_transform.h>
#include <CGAL/Laplacian_deformation/IO/Botsch08.h>

#include <Eigen/Geometry>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace Laplacian_deformation_server {

namespace LD = CGAL::Laplacian_deformation;
namespace fs = std::filesystem;
using json = nlohmann::json;

typedef CGAL::Simple_cartesian<double>               Kernel;
typedef Kernel::Point_3                              Point_3;
typedef CGAL::Surface_mesh<Point_3>                  Mesh;
typedef boost::graph_traits<Mesh>::vertex_descriptor vertex_descriptor;

/// What `laplacian_deform --serve` is given.
struct Server_options
{
  std::string mesh;            ///< the mesh named "default" (empty: data_dir/cactus.off, or a generated bumpy plane)
  std::string data_dir;        ///< the only folder whose meshes a page may open by name
  std::string viewer_dir;      ///< viewer/: editor.html, editor.js, lib/, node_modules/three
  std::string output_dir = "laplacian_deform_output"; ///< the only folder the server writes to (POST /api/save)
  std::string host = "127.0.0.1";
  int port = 8080;             ///< 0: any free port
  std::size_t max_sessions = 8;          ///< the least recently used session goes when a new one exceeds this
  std::size_t max_vertices = 2000000;    ///< larger meshes are refused
};

/// An answer: HTTP status, body and its type; `filename` makes it a download.
struct Reply
{
  int status = 200;
  std::string body;
  std::string content_type = "application/json";
  std::string filename;
};

inline Reply json_reply(const json& j, int status = 200)
{
  Reply r;
  r.status = status;
  r.body = j.dump();
  return r;
}
inline Reply error_reply(int status, const std::string& message) { return json_reply(json{{"error", message}}, status); }

/// A request error: becomes a 4xx reply with {"error": message}.
struct Request_error
{
  int status;
  std::string message;
};

// ---------------------------------------------------------------------------------------------
// The deformer behind a type-erased interface: representation x weights x transform chosen at run time.

/// The policies a session deforms with.
struct Policy
{
  std::string representation = "edge";      ///< "edge" or "vertex"
  std::string weights = "cotangent";        ///< "cotangent" or "uniform"
  std::string transform = "scaled_rotation";///< "scaled_rotation" (S*R1), "rotation" or "similarity"
};

class Deformer_interface
{
public:
  virtual ~Deformer_interface() = default;
  virtual void insert_roi_vertex(vertex_descriptor v) = 0;
  virtual void insert_control_vertex(vertex_descriptor v) = 0;
  virtual bool preprocess() = 0;
  virtual void set_target_position(vertex_descriptor v, const Point_3& p) = 0;
  virtual LD::Deformation_result deform(unsigned int iterations, double tolerance) = 0;
  virtual void reset() = 0;
  virtual const LD::Deformation_result& last_result() const = 0;
  virtual std::size_t number_of_factorizations() const = 0;
};

template <class Representation, class Weights, class Transform>
class Deformer_model : public Deformer_interface
{
public:
  explicit Deformer_model(Mesh& mesh) : m_deformer(mesh) {}
  void insert_roi_vertex(vertex_descriptor v) override { m_deformer.insert_roi_vertex(v); }
  void insert_control_vertex(vertex_descriptor v) override { m_deformer.insert_control_vertex(v); }
  bool preprocess() override { return m_deformer.preprocess(); }
  void set_target_position(vertex_descriptor v, const Point_3& p) override { m_deformer.set_target_position(v, p); }
  LD::Deformation_result deform(unsigned int iterations, double tolerance) override
  {
    return m_deformer.deform(iterations, tolerance);
  }
  void reset() override { m_deformer.reset(); }
  const LD::Deformation_result& last_result() const override { return m_deformer.last_result(); }
  std::size_t number_of_factorizations() const override { return m_deformer.number_of_factorizations(); }

private:
  LD::Mesh_deformer<Mesh, Representation, Weights, Transform> m_deformer;
};

namespace internal {

template <class R, class W>
std::unique_ptr<Deformer_interface> make_deformer_t(Mesh& mesh, const std::string& transform)
{
  if(transform == "rotation")
    return std::make_unique<Deformer_model<R, W, LD::Rotation_transform> >(mesh);
  if(transform == "similarity")
    return std::make_unique<Deformer_model<R, W, LD::Similarity_transform> >(mesh);
  return std::make_unique<Deformer_model<R, W, LD::Scaled_rotation_transform> >(mesh);
}
template <class R>
std::unique_ptr<Deformer_interface> make_deformer_w(Mesh& mesh, const Policy& p)
{
  return p.weights == "uniform" ? make_deformer_t<R, LD::Uniform_weights>(mesh, p.transform)
                                : make_deformer_t<R, LD::Cotangent_weights>(mesh, p.transform);
}

} // namespace internal

/// A deformer for `mesh` (whose current positions become the rest positions) with the policies of `p`
/// (assumed valid; see `validate_policy`).
inline std::unique_ptr<Deformer_interface> make_deformer(Mesh& mesh, const Policy& p)
{
  return p.representation == "vertex" ? internal::make_deformer_w<LD::Vertex_based_representation>(mesh, p)
                                      : internal::make_deformer_w<LD::Edge_based_representation>(mesh, p);
}

// ---------------------------------------------------------------------------------------------
// Request validation.

namespace internal {

inline json parse_object(const std::string& body)
{
  json j = json::parse(body, nullptr, false);
  if(j.is_discarded())
    throw Request_error{400, "the request body is not valid JSON"};
  if(!j.is_object())
    throw Request_error{400, "the request body must be a JSON object"};
  return j;
}

inline double finite_number(const json& j, const std::string& what)
{
  if(!j.is_number())
    throw Request_error{400, what + " must be a number"};
  const double x = j.get<double>();
  if(!std::isfinite(x))
    throw Request_error{400, what + " must be finite"};
  return x;
}

inline Eigen::Vector3d vector3(const json& j, const std::string& what)
{
  if(!j.is_array() || j.size() != 3)
    throw Request_error{400, what + " must be an array of 3 numbers"};
  return Eigen::Vector3d(finite_number(j[0], what + "[0]"), finite_number(j[1], what + "[1]"),
                         finite_number(j[2], what + "[2]"));
}

inline long long integer(const json& j, const std::string& what, long long lo, long long hi)
{
  if(!j.is_number_integer())
    throw Request_error{400, what + " must be an integer"};
  const long long k = j.get<long long>();
  if(k < lo || k > hi)
    throw Request_error{400, what + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]"};
  return k;
}

inline std::vector<vertex_descriptor> vertex_ids(const json& body, const char* key, std::size_t n)
{
  std::vector<vertex_descriptor> ids;
  if(!body.contains(key))
    return ids;
  const json& a = body[key];
  if(!a.is_array())
    throw Request_error{400, std::string(key) + " must be an array of vertex ids"};
  ids.reserve(a.size());
  for(std::size_t i = 0; i < a.size(); ++i)
  {
    const std::string what = std::string(key) + "[" + std::to_string(i) + "]";
    if(!a[i].is_number_integer())
      throw Request_error{400, what + " must be an integer vertex id"};
    const long long k = a[i].get<long long>();
    if(k < 0 || std::size_t(k) >= n)
      throw Request_error{400, what + ": unknown vertex id " + std::to_string(k) + " (the mesh has " +
                                   std::to_string(n) + " vertices)"};
    ids.push_back(vertex_descriptor(static_cast<Mesh::size_type>(k)));
  }
  return ids;
}

inline std::string string_member(const json& body, const char* key)
{
  if(!body.contains(key))
    throw Request_error{400, std::string("missing \"") + key + "\""};
  if(!body[key].is_string())
    throw Request_error{400, std::string(key) + " must be a string"};
  return body[key].get<std::string>();
}

inline bool is_plain_name(const std::string& s, bool allow_dot)
{
  if(s.empty() || s.size() > 128 || s[0] == '.')
    return false;
  for(char c : s)
    if(!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || (allow_dot && c == '.')))
      return false;
  return true;
}

inline std::string lower_extension(const fs::path& p)
{
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return e;
}

inline bool is_mesh_file_name(const std::string& name)
{
  const std::string e = lower_extension(name);
  return is_plain_name(name, true) && (e == ".off" || e == ".obj" || e == ".ply" || e == ".stl");
}

// a wavy square, 41 x 41 vertices: the default mesh when the cactus is absent
inline Mesh bumpy_plane(int n = 40)
{
  Mesh m;
  const double pi = 3.14159265358979323846;
  std::vector<vertex_descriptor> v;
  for(int j = 0; j <= n; ++j)
    for(int i = 0; i <= n; ++i)
    {
      const double x = double(i) / n, y = double(j) / n;
      v.push_back(m.add_vertex(Point_3(x, y, 0.08 * std::sin(2 * pi * x) * std::cos(2 * pi * y))));
    }
  auto at = [&](int i, int j) { return v[std::size_t(j * (n + 1) + i)]; };
  for(int j = 0; j < n; ++j)
    for(int i = 0; i < n; ++i)
    {
      m.add_face(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      m.add_face(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return m;
}

// vertices within k rings of `seeds`
inline std::vector<vertex_descriptor> grow(const Mesh& m, const std::vector<vertex_descriptor>& seeds, int k)
{
  std::vector<int> ring(num_vertices(m), -1);
  std::vector<vertex_descriptor> out, front;
  for(vertex_descriptor v : seeds)
    if(ring[v] < 0)
    {
      ring[v] = 0;
      out.push_back(v);
      front.push_back(v);
    }
  for(int r = 1; r <= k && !front.empty(); ++r)
  {
    std::vector<vertex_descriptor> next;
    for(vertex_descriptor v : front)
      for(vertex_descriptor w : CGAL::vertices_around_target(m.halfedge(v), m))
        if(ring[w] < 0)
        {
          ring[w] = r;
          out.push_back(w);
          next.push_back(w);
        }
    front.swap(next);
  }
  return out;
}

inline json positions_json(const Mesh& m)
{
  json a = json::array();
  for(vertex_descriptor v : m.vertices())
  {
    const Point_3& p = m.point(v);
    a.push_back(p.x());
    a.push_back(p.y());
    a.push_back(p.z());
  }
  return a;
}

} // namespace internal

/// The handle motion of the last drag: `p -> R (p - center) + center + translation`.
struct Drag
{
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double angle = 0;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  unsigned int iterations = 4;

  /// the 4x4 affine matrix (Botsch08 .def).
  Eigen::Matrix4d matrix() const
  {
    const Eigen::Matrix3d r = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.topLeftCorner<3, 3>() = r;
    m.topRightCorner<3, 1>() = translation + center - r * center;
    return m;
  }
};

/// One browser session: its mesh, selection, deformer and last drag.
struct Session
{
  std::string mesh_name;
  std::string stem;                               // the downloads' file names
  Mesh rest, mesh;
  Policy policy;
  std::unique_ptr<Deformer_interface> deformer;   // null until a selection is preprocessed
  std::vector<vertex_descriptor> roi, handles;    // roi excludes the handles
  std::optional<Drag> drag;
  std::uint64_t last_used = 0;
};

// ---------------------------------------------------------------------------------------------

/// The server's logic: sessions and the JSON API, without sockets. Thread-safe (one mutex).
class Deformation_server
{
public:
  explicit Deformation_server(Server_options options) : m_options(std::move(options)), m_random(std::random_device{}()) {}

  const Server_options& options() const { return m_options; }

  /// answers POST `path` with `body`.
  Reply post(const std::string& path, const std::string& body)
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    try
    {
      if(path == "/api/session") return create_session(internal::parse_object(body));
      if(path == "/api/select") return select(internal::parse_object(body));
      if(path == "/api/drag") return drag(internal::parse_object(body));
      if(path == "/api/policy") return set_policy(internal::parse_object(body));
      if(path == "/api/reset") return reset(internal::parse_object(body));
      if(path == "/api/save") return save(internal::parse_object(body));
      return error_reply(404, "no such API: POST " + path);
    }
    catch(const Request_error& e) { return error_reply(e.status, e.message); }
    catch(const std::exception& e) { return error_reply(500, std::string("internal error: ") + e.what()); }
  }

  /// answers GET `path` with the query parameters `params`.
  Reply get(const std::string& path, const std::map<std::string, std::string>& params)
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    try
    {
      if(path == "/api/meshes") return meshes();
      if(path == "/api/download") return download(params);
      return error_reply(404, "no such API: GET " + path);
    }
    catch(const Request_error& e) { return error_reply(e.status, e.message); }
    catch(const std::exception& e) { return error_reply(500, std::string("internal error: ") + e.what()); }
  }

  /// the number of factorisations of a session's deformer (0 without one); for tests.
  std::size_t number_of_factorizations(const std::string& id)
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    auto it = m_sessions.find(id);
    return it != m_sessions.end() && it->second->deformer ? it->second->deformer->number_of_factorizations() : 0;
  }
  /// the number of live sessions.
  std::size_t number_of_sessions()
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_sessions.size();
  }

  /// The file behind a static URL path, or nothing: `/` and `/editor.html`, `/editor.js`, `/lib/*.js`
  /// from the viewer folder, `/three/...` from viewer/node_modules/three. No `..`, no NUL, no
  /// backslash, and the resolved file (symbolic links followed) must stay inside its root.
  std::optional<fs::path> static_file(const std::string& url) const
  {
    if(url.find("..") != std::string::npos || url.find('\0') != std::string::npos ||
       url.find('\\') != std::string::npos || url.empty() || url[0] != '/')
      return std::nullopt;
    const fs::path viewer(m_options.viewer_dir);
    fs::path root, file;
    if(url == "/" || url == "/editor.html") { root = viewer; file = viewer / "editor.html"; }
    else if(url == "/editor.js") { root = viewer; file = viewer / "editor.js"; }
    else if(url.rfind("/lib/", 0) == 0 && internal::lower_extension(url) == ".js")
    {
      root = viewer / "lib";
      file = root / url.substr(5);
    }
    else if(url.rfind("/three/", 0) == 0)
    {
      root = viewer / "node_modules" / "three";
      file = root / url.substr(7);
    }
    else
      return std::nullopt;
    std::error_code ec;
    const fs::path real_root = fs::canonical(root, ec);
    if(ec) return std::nullopt;
    const fs::path real = fs::canonical(file, ec);
    if(ec || !fs::is_regular_file(real)) return std::nullopt;
    const std::string r = real_root.string() + "/";
    if(real.string().compare(0, r.size(), r) != 0) return std::nullopt;
    return real;
  }

  /// serves a static file (see `static_file`).
  Reply get_static(const std::string& url) const
  {
    const std::optional<fs::path> file = static_file(url);
    if(!file)
      return error_reply(404, "not found: " + url);
    std::ifstream in(*file, std::ios::binary);
    std::ostringstream data;
    data << in.rdbuf();
    Reply r;
    r.body = data.str();
    const std::string e = internal::lower_extension(*file);
    r.content_type = e == ".html" ? "text/html; charset=utf-8"
                     : e == ".js" || e == ".mjs" ? "text/javascript; charset=utf-8"
                     : e == ".json" ? "application/json"
                     : e == ".css" ? "text/css" : "application/octet-stream";
    return r;
  }

private:
  // ---- sessions
  Session& session(const json& body)
  {
    const std::string id = internal::string_member(body, "session");
    auto it = m_sessions.find(id);
    if(it == m_sessions.end())
      throw Request_error{404, "unknown session \"" + id + "\" (expired or never created: reload the page)"};
    it->second->last_used = ++m_clock;
    return *it->second;
  }

  Mesh load_mesh(const std::string& name, std::string& stem)
  {
    Mesh m;
    fs::path file;
    if(name == "default")
    {
      file = !m_options.mesh.empty() ? fs::path(m_options.mesh) : fs::path(m_options.data_dir) / "cactus.off";
      if(m_options.mesh.empty() && !fs::is_regular_file(file))
      {
        stem = "bumpy_plane";
        return internal::bumpy_plane();
      }
    }
    else
    {
      if(!internal::is_mesh_file_name(name))
        throw Request_error{400, "mesh must be \"default\" or a file name (.off, .obj, .ply, .stl) of the data folder, got \"" + name + "\""};
      file = fs::path(m_options.data_dir) / name;
    }
    if(!fs::is_regular_file(file) || !CGAL::IO::read_polygon_mesh(file.string(), m) || is_empty(m))
      throw Request_error{400, "cannot read a mesh from " + (name == "default" ? file.string() : name)};
    if(!CGAL::is_triangle_mesh(m))
      throw Request_error{400, name + ": the mesh has non-triangle faces"};
    if(num_vertices(m) > m_options.max_vertices)
      throw Request_error{400, name + ": more than " + std::to_string(m_options.max_vertices) + " vertices"};
    if(m.has_garbage())
      m.collect_garbage();
    // only the geometry: colours or normals read with the file would go into the downloads
    Mesh clean;
    for(vertex_descriptor v : m.vertices())
      clean.add_vertex(m.point(v));
    for(auto f : m.faces())
    {
      std::vector<vertex_descriptor> corners;
      for(vertex_descriptor v : CGAL::vertices_around_face(m.halfedge(f), m))
        corners.push_back(v);
      clean.add_face(corners);
    }
    m = std::move(clean);
    stem = file.stem().string();
    if(!internal::is_plain_name(stem, false))
      stem = "mesh";
    return m;
  }

  Reply meshes()
  {
    json names = json::array({"default"});
    std::error_code ec;
    std::vector<std::string> found;
    for(fs::directory_iterator it(m_options.data_dir, ec), end; !ec && it != end; it.increment(ec))
      if(it->is_regular_file() && internal::is_mesh_file_name(it->path().filename().string()))
        found.push_back(it->path().filename().string());
    std::sort(found.begin(), found.end());
    for(const std::string& f : found) names.push_back(f);
    return json_reply(json{{"meshes", names}});
  }

  Reply create_session(const json& body)
  {
    const std::string name = body.contains("mesh") ? internal::string_member(body, "mesh") : "default";
    auto s = std::make_unique<Session>();
    s->mesh_name = name;
    s->rest = load_mesh(name, s->stem);
    s->mesh = s->rest;
    s->last_used = ++m_clock;
    while(m_sessions.size() >= std::max<std::size_t>(1, m_options.max_sessions))
    {
      auto oldest = std::min_element(m_sessions.begin(), m_sessions.end(), [](const auto& a, const auto& b) {
        return a.second->last_used < b.second->last_used;
      });
      m_sessions.erase(oldest);
    }
    char id[17];
    std::snprintf(id, sizeof id, "%016llx", static_cast<unsigned long long>(m_random()));
    json faces = json::array();
    for(auto f : s->mesh.faces())
      for(vertex_descriptor v : CGAL::vertices_around_face(s->mesh.halfedge(f), s->mesh))
        faces.push_back(std::size_t(v));
    json reply{{"session", id}, {"mesh", name}, {"vertices", internal::positions_json(s->mesh)},
               {"faces", faces}, {"policy", policy_json(s->policy)}};
    m_sessions[id] = std::move(s);
    return json_reply(reply);
  }

  static json policy_json(const Policy& p)
  {
    return json{{"representation", p.representation}, {"weights", p.weights}, {"transform", p.transform}};
  }

  // builds the session's deformer on its rest mesh and preprocesses its selection (if any)
  void rebuild(Session& s)
  {
    s.deformer.reset();
    s.mesh = s.rest;
    if(s.handles.empty())
      return;
    auto d = make_deformer(s.mesh, s.policy);
    for(vertex_descriptor v : s.roi) d->insert_roi_vertex(v);
    for(vertex_descriptor v : s.handles) d->insert_control_vertex(v);
    if(!d->preprocess())
    {
      const std::string message = d->last_result().message;
      s.roi.clear();
      s.handles.clear();
      s.drag.reset();
      throw Request_error{400, "cannot preprocess this selection: " + message};
    }
    s.deformer = std::move(d);
  }

  json result_json(const Session& s, const LD::Deformation_result& r, double handler_seconds) const
  {
    return json{{"seconds", r.seconds}, {"local_step_seconds", r.local_step_seconds},
                {"right_hand_side_seconds", r.right_hand_side_seconds}, {"solve_seconds", r.solve_seconds},
                {"iterations", r.iterations}, {"energy", r.energy}, {"handler_seconds", handler_seconds},
                {"factorizations", s.deformer ? s.deformer->number_of_factorizations() : 0}};
  }

  Reply select(const json& body)
  {
    const auto t0 = std::chrono::steady_clock::now();
    Session& s = session(body);
    const std::size_t n = num_vertices(s.mesh);
    std::vector<vertex_descriptor> roi = internal::vertex_ids(body, "roi", n);
    std::vector<vertex_descriptor> handles = internal::vertex_ids(body, "handles", n);
    int k = body.contains("grow") ? int(internal::integer(body["grow"], "grow", 0, 1000)) : 0;
    if(handles.empty())
      throw Request_error{400, "handles must hold at least one vertex id"};
    std::vector<char> is_handle(n, 0), is_roi(n, 0);
    for(vertex_descriptor v : handles) is_handle[v] = 1;
    std::vector<vertex_descriptor> seeds = roi;
    seeds.insert(seeds.end(), handles.begin(), handles.end());
    if(k > 0) roi = internal::grow(s.rest, seeds, k);
    s.roi.clear();
    s.handles.clear();
    for(vertex_descriptor v : roi)
      if(!is_handle[v] && !is_roi[v]) { is_roi[v] = 1; s.roi.push_back(v); }
    for(vertex_descriptor v : handles)
      if(is_handle[v] == 1) { is_handle[v] = 2; s.handles.push_back(v); }
    s.drag.reset();
    rebuild(s);
    json roi_ids = json::array();
    for(vertex_descriptor v : s.roi) roi_ids.push_back(std::size_t(v));
    json handle_ids = json::array();
    for(vertex_descriptor v : s.handles) handle_ids.push_back(std::size_t(v));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return json_reply(json{{"roi", roi_ids}, {"handles", handle_ids},
                           {"preprocess_seconds", s.deformer->last_result().seconds}, {"handler_seconds", seconds},
                           {"factorizations", s.deformer->number_of_factorizations()}});
  }

  Eigen::Vector3d handle_centroid(const Session& s) const
  {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for(vertex_descriptor v : s.handles)
    {
      const Point_3& p = s.rest.point(v);
      c += Eigen::Vector3d(p.x(), p.y(), p.z());
    }
    return s.handles.empty() ? c : Eigen::Vector3d(c / double(s.handles.size()));
  }

  // sets the targets of the drag and deforms; the reply holds the new positions
  json apply_drag(Session& s, const Drag& d, std::chrono::steady_clock::time_point t0)
  {
    const Eigen::Matrix4d m = d.matrix();
    for(vertex_descriptor v : s.handles)
    {
      const Point_3& p = s.rest.point(v);
      const Eigen::Vector4d q = m * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.);
      s.deformer->set_target_position(v, Point_3(q.x(), q.y(), q.z()));
    }
    const LD::Deformation_result r = s.deformer->deform(d.iterations, 0.);
    if(!r)
      throw Request_error{400, "the deformation failed: " + r.message};
    s.drag = d;
    double error = 0;
    for(vertex_descriptor v : s.handles)
    {
      const Point_3& p = s.rest.point(v);
      const Eigen::Vector4d q = m * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.);
      error = (std::max)(error, std::sqrt(CGAL::squared_distance(s.mesh.point(v), Point_3(q.x(), q.y(), q.z()))));
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    json reply = result_json(s, r, seconds);
    reply["positions"] = internal::positions_json(s.mesh);
    reply["handle_error"] = error;
    return reply;
  }

  Reply drag(const json& body)
  {
    const auto t0 = std::chrono::steady_clock::now();
    Session& s = session(body);
    if(!s.deformer)
      throw Request_error{400, "select a region of interest and handles first (POST /api/select)"};
    Drag d;
    d.center = handle_centroid(s);
    if(body.contains("translation"))
      d.translation = internal::vector3(body["translation"], "translation");
    if(body.contains("rotation"))
    {
      const json& r = body["rotation"];
      if(!r.is_object())
        throw Request_error{400, "rotation must be an object {axis, angle, center}"};
      d.axis = internal::vector3(r.contains("axis") ? r["axis"] : json(), "rotation.axis");
      if(!(d.axis.norm() > 1e-12))
        throw Request_error{400, "rotation.axis must not be zero"};
      d.angle = internal::finite_number(r.contains("angle") ? r["angle"] : json(), "rotation.angle");
      if(r.contains("center"))
        d.center = internal::vector3(r["center"], "rotation.center");
    }
    if(body.contains("iterations"))
      d.iterations = unsigned(internal::integer(body["iterations"], "iterations", 1, 100));
    return json_reply(apply_drag(s, d, t0));
  }

  static void validate_policy(const Policy& p)
  {
    if(p.representation != "edge" && p.representation != "vertex")
      throw Request_error{400, "representation must be \"edge\" or \"vertex\", got \"" + p.representation + "\""};
    if(p.weights != "cotangent" && p.weights != "uniform")
      throw Request_error{400, "weights must be \"cotangent\" or \"uniform\", got \"" + p.weights + "\""};
    if(p.transform != "scaled_rotation" && p.transform != "rotation" && p.transform != "similarity")
      throw Request_error{400, "transform must be \"scaled_rotation\", \"rotation\" or \"similarity\", got \"" +
                                   p.transform + "\""};
  }

  Reply set_policy(const json& body)
  {
    const auto t0 = std::chrono::steady_clock::now();
    Session& s = session(body);
    Policy p = s.policy;
    if(body.contains("representation")) p.representation = internal::string_member(body, "representation");
    if(body.contains("weights")) p.weights = internal::string_member(body, "weights");
    if(body.contains("transform")) p.transform = internal::string_member(body, "transform");
    validate_policy(p);
    s.policy = p;
    const std::optional<Drag> d = s.drag;
    rebuild(s);
    json reply;
    if(s.deformer && d)
      reply = apply_drag(s, *d, t0);   // the same drag with the new policies
    else
      reply = json{{"positions", internal::positions_json(s.mesh)}};
    reply["policy"] = policy_json(s.policy);
    reply["factorizations"] = s.deformer ? s.deformer->number_of_factorizations() : 0;
    return json_reply(reply);
  }

  Reply reset(const json& body)
  {
    Session& s = session(body);
    if(body.contains("selection"))
    {
      if(!body["selection"].is_boolean())
        throw Request_error{400, "selection must be true or false"};
      if(body["selection"].get<bool>())
      {
        s.roi.clear();
        s.handles.clear();
      }
    }
    s.drag.reset();
    if(s.deformer && !s.handles.empty())
      s.deformer->reset();
    else
      rebuild(s);
    return json_reply(json{{"positions", internal::positions_json(s.mesh)},
                           {"factorizations", s.deformer ? s.deformer->number_of_factorizations() : 0}});
  }

  std::vector<int> statuses(const Session& s) const
  {
    std::vector<int> status(num_vertices(s.mesh), LD::IO::BOTSCH08_FIXED);
    for(vertex_descriptor v : s.roi) status[v] = LD::IO::BOTSCH08_REGION_OF_INTEREST;
    for(vertex_descriptor v : s.handles) status[v] = LD::IO::BOTSCH08_HANDLE;
    return status;
  }

  // the session's mesh (off, ply), selection (sel) or handle transformation (def) as text
  std::string file_text(const Session& s, const std::string& format) const
  {
    std::ostringstream out;
    out.precision(17);
    bool ok = false;
    if(format == "off")
      ok = CGAL::IO::write_OFF(out, s.mesh, CGAL::parameters::stream_precision(17));
    else if(format == "ply")
      ok = CGAL::IO::write_PLY(out, s.mesh, CGAL::parameters::use_binary_mode(false).stream_precision(17));
    else if(format == "sel")
      ok = LD::IO::write_botsch08_selection(out, statuses(s));
    else if(format == "def")
      ok = LD::IO::write_botsch08_transform(out, s.drag ? s.drag->matrix() : Eigen::Matrix4d::Identity().eval());
    else
      throw Request_error{400, "format must be off, ply, sel or def, got \"" + format + "\""};
    if(!ok)
      throw Request_error{500, "cannot write the " + format + " file"};
    return out.str();
  }

  Reply download(const std::map<std::string, std::string>& params)
  {
    auto p = params.find("session");
    auto f = params.find("format");
    if(p == params.end() || f == params.end())
      throw Request_error{400, "download needs ?session=ID&format=off|ply|sel|def"};
    Session& s = session(json{{"session", p->second}});
    Reply r;
    r.body = file_text(s, f->second);
    r.content_type = "application/octet-stream";
    r.filename = s.stem + (f->second == "sel" || f->second == "def" ? "." : "_deformed.") + f->second;
    return r;
  }

  // writes NAME.off, NAME.sel and NAME.def into the output folder (and nowhere else)
  Reply save(const json& body)
  {
    Session& s = session(body);
    const std::string name = internal::string_member(body, "name");
    if(!internal::is_plain_name(name, false) || name.size() > 64)
      throw Request_error{400, "name must be 1 to 64 letters, digits, '_' or '-', got \"" + name + "\""};
    const fs::path folder(m_options.output_dir);
    std::error_code ec;
    fs::create_directories(folder, ec);
    if(ec)
      throw Request_error{500, "cannot create the output folder " + folder.string() + ": " + ec.message()};
    json files = json::array();
    for(const char* format : {"off", "sel", "def"})
    {
      const std::string text = file_text(s, format);
      const fs::path path = folder / (name + "." + format), tmp = folder / (".tmp." + name + "." + format);
      {
        std::ofstream out(tmp, std::ios::binary);
        out << text;
        if(!out)
          throw Request_error{500, "cannot write " + tmp.string()};
      }
      fs::rename(tmp, path, ec);
      if(ec)
        throw Request_error{500, "cannot write " + path.string() + ": " + ec.message()};
      files.push_back(path.string());
    }
    return json_reply(json{{"files", files}});
  }

  Server_options m_options;
  std::mutex m_mutex;
  std::map<std::string, std::unique_ptr<Session> > m_sessions;
  std::mt19937_64 m_random;
  std::uint64_t m_clock = 0;
};

// ---------------------------------------------------------------------------------------------
// HTTP.

inline void send(const Reply& r, httplib::Response& res)
{
  res.status = r.status;
  if(!r.filename.empty())
    res.set_header("Content-Disposition", "attachment; filename=\"" + r.filename + "\"");
  res.set_header("Cache-Control", "no-store");
  res.set_content(r.body, r.content_type.c_str());
}

/// Routes every request of `http` to `server`.
inline void install_routes(httplib::Server& http, Deformation_server& server)
{
  http.set_payload_max_length(64u << 20);
  http.Post(R"(/api/.*)", [&server](const httplib::Request& req, httplib::Response& res) {
    send(server.post(req.path, req.body), res);
  });
  http.Get(R"(/api/.*)", [&server](const httplib::Request& req, httplib::Response& res) {
    std::map<std::string, std::string> params;
    for(const auto& p : req.params) params[p.first] = p.second;
    send(server.get(req.path, params), res);
  });
  http.Get(R"(/.*)", [&server](const httplib::Request& req, httplib::Response& res) {
    send(server.get_static(req.path), res);
  });
  http.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
    send(error_reply(500, "internal error"), res);
  });
}

/// Serves until the process is stopped; returns a process exit status (1 if the port cannot be bound).
inline int run_deformation_server(const Server_options& options)
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
  Deformation_server server(options);
  {   // the default mesh must load: fail now rather than in the page
    const Reply r = server.post("/api/session", R"({"mesh":"default"})");
    if(r.status != 200)
    {
      std::cerr << "error: " << json::parse(r.body)["error"].get<std::string>() << std::endl;
      return 1;
    }
  }
  httplib::Server http;
  install_routes(http, server);
  const int port = options.port == 0 ? http.bind_to_any_port(options.host) :
                   (http.bind_to_port(options.host, options.port) ? options.port : -1);
  if(port < 0)
  {
    std::cerr << "error: cannot listen on " << options.host << ":" << options.port << std::endl;
    return 1;
  }
  std::cout << "laplacian_deform: editor at http://" << options.host << ":" << port << "/ (Ctrl-C stops)" << std::endl;
  return http.listen_after_bind() ? 0 : 1;
}

/// Parses `--serve [MESH] [--port N] [--output DIR]` (argv[1] is "--serve"); returns the exit status.
inline int serve_main(int argc, char** argv, const std::string& data_dir, const std::string& viewer_dir)
{
  Server_options o;
  o.data_dir = data_dir;
  o.viewer_dir = viewer_dir;
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
    else if(a == "--viewer") o.viewer_dir = argv[++i];
    else if(a == "--help" || a == "-h")
    {
      std::cout << "usage: laplacian_deform --serve [MESH] [--port N] [--output DIR] [--viewer DIR]\n"
                   "  Interactive editor at http://127.0.0.1:N/ (default 8080; 0: any free port).\n"
                   "  MESH is the default mesh (default: CGAL's cactus); the page may also open the meshes\n"
                   "  of the data folder. Saved files go to DIR only (default laplacian_deform_output).\n";
      return 0;
    }
    else if(!a.empty() && a[0] != '-' && o.mesh.empty()) o.mesh = a;
    else
    {
      std::cerr << "error: unexpected argument \"" << a << "\" (laplacian_deform --serve --help)" << std::endl;
      return 2;
    }
  }
  return run_deformation_server(o);
}

} // namespace Laplacian_deformation_server

#endif // LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_H
