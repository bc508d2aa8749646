// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// laplacian_deform --serve, the API without sockets: browser sessions, each owning one
// Mesh_deformer, kept across its selections (a selection is factored once, a drag only moves the
// targets and re-solves, a change of transform or start re-solves without refactoring).
// Each session has its own lock: a long drag of one session never blocks another session, and the
// session table is locked only to find, add or remove a session. A drag carries a sequence number;
// a drag that waited behind the session's lock while a newer one arrived is dropped unsolved
// (409, "superseded"), and an older drag is never applied after a newer one.
#ifndef LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_SESSIONS_H
#define LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_SESSIONS_H

#include "deformation_server/session.h"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <mutex>
#include <random>

namespace Laplacian_deformation_server {

/// What `laplacian_deform --serve` is given.
struct Server_options
{
  std::string mesh;            ///< the mesh named "default" (empty: data_dir/cactus.off, or a generated bumpy plane)
  std::string data_dir;        ///< the only folder whose meshes a page may open by name
  std::string viewer_dir;      ///< viewer/: editor.html, editor.js, lib/, node_modules/three
  std::string output_dir = Laplacian_deformation_tool_defaults::output_dir(); ///< the only folder the server writes to (POST /api/save)
  std::string host = "127.0.0.1";
  int port = 8080;             ///< 0: any free port
  std::string token;           ///< required on every API call (empty: a random one per run)
  std::size_t max_sessions = 8;          ///< more are refused (503) unless one has been idle for session_idle_seconds
  double session_idle_seconds = 600;     ///< an idle session may make room for a new one
  std::size_t max_vertices = 2000000;    ///< larger meshes are refused
  std::size_t max_body_bytes = 64u << 20; ///< larger request bodies get 413
};

/// The server's logic: sessions and the JSON API, without sockets. Thread-safe.
class Deformation_server
{
  typedef std::chrono::steady_clock Clock;

public:
  explicit Deformation_server(Server_options options) : m_options(std::move(options)), m_random(std::random_device{}()) {}

  const Server_options& options() const { return m_options; }

  /// answers POST `path` with `body`.
  Reply post(const std::string& path, const std::string& body)
  {
    try
    {
      if(path == "/api/session") return create_session(internal::parse_object(body));
      if(path == "/api/close") return close_session(internal::parse_object(body));
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
    try
    {
      if(path == "/api/meshes") return json_reply(json{{"meshes", mesh_names(m_options.data_dir)}});
      if(path == "/api/download") return download(params);
      return error_reply(404, "no such API: GET " + path);
    }
    catch(const Request_error& e) { return error_reply(e.status, e.message); }
    catch(const std::exception& e) { return error_reply(500, std::string("internal error: ") + e.what()); }
  }

  /// the number of factorisations of a session's selection (0 without one); for tests.
  std::size_t number_of_factorizations(const std::string& id)
  {
    std::shared_ptr<Session> s = find(id);
    if(!s) return 0;
    std::lock_guard<std::mutex> lock(s->mutex);
    return Laplacian_deformation_server::factorizations(*s);
  }
  /// the deformers a session has built, and the factorisations of its deformer in all; for tests.
  std::pair<std::size_t, std::size_t> deformer_counts(const std::string& id)
  {
    std::shared_ptr<Session> s = find(id);
    if(!s) return {0, 0};
    std::lock_guard<std::mutex> lock(s->mutex);
    return {s->deformers_built, s->deformer ? s->deformer->number_of_factorizations() : 0};
  }
  /// the number of live sessions.
  std::size_t number_of_sessions()
  {
    std::lock_guard<std::mutex> lock(m_sessions_mutex);
    return m_sessions.size();
  }
  /// For tests: how many sessions got their mesh from the cache of meshes read last.
  std::size_t mesh_cache_hits() { return m_meshes.hits(); }
  /// For tests: holds the lock of session `id` (its requests wait until the lock is released).
  /// (Its time of last use is left as it is.)
  std::unique_lock<std::mutex> hold_session(const std::string& id)
  {
    std::shared_ptr<Session> s;
    {
      std::lock_guard<std::mutex> lock(m_sessions_mutex);
      auto it = m_sessions.find(id);
      if(it != m_sessions.end()) s = it->second;
    }
    return s ? std::unique_lock<std::mutex>(s->mutex) : std::unique_lock<std::mutex>();
  }
  /// For tests: the highest drag sequence number session `id` has received (0: none, or no such session).
  std::uint64_t newest_drag(const std::string& id)
  {
    std::shared_ptr<Session> s = find(id);
    return s ? s->newest_drag.load() : 0;
  }

private:
  // ---- the session table
  std::shared_ptr<Session> find(const std::string& id)
  {
    std::lock_guard<std::mutex> lock(m_sessions_mutex);
    auto it = m_sessions.find(id);
    if(it == m_sessions.end())
      return nullptr;
    it->second->last_used = Clock::now().time_since_epoch().count();
    return it->second;
  }
  std::shared_ptr<Session> session(const json& body)
  {
    const std::string id = internal::string_member(body, "session");
    std::shared_ptr<Session> s = find(id);
    if(!s)
      throw Request_error{404, "unknown session \"" + id + "\" (closed, or never created: reload the page)"};
    return s;
  }

  // with m_sessions_mutex held: makes room for one more session by removing the least recently
  // used session idle for session_idle_seconds (and not in use now); refuses if there is none
  void make_room()
  {
    const std::size_t limit = std::max<std::size_t>(1, m_options.max_sessions);
    if(m_sessions.size() < limit)
      return;
    const Clock::rep now = Clock::now().time_since_epoch().count();
    const Clock::rep idle = std::chrono::duration_cast<Clock::duration>(
                              std::chrono::duration<double>(m_options.session_idle_seconds)).count();
    std::vector<std::map<std::string, std::shared_ptr<Session> >::iterator> candidates;
    for(auto it = m_sessions.begin(); it != m_sessions.end(); ++it)
      if(now - it->second->last_used >= idle)
        candidates.push_back(it);
    std::sort(candidates.begin(), candidates.end(),
              [](const auto& a, const auto& b) { return a->second->last_used < b->second->last_used; });
    for(auto it : candidates)
      if(std::unique_lock<std::mutex>(it->second->mutex, std::try_to_lock).owns_lock())   // not in use now
      {
        m_sessions.erase(it);
        return;
      }
    throw Request_error{503, "too many sessions: " + std::to_string(m_sessions.size()) + " editor pages are open (at most " +
                                 std::to_string(limit) + "); close one, or wait until one has been idle for " +
                                 std::to_string(int(m_options.session_idle_seconds)) + " s"};
  }

  Reply create_session(const json& body)
  {
    const std::string name = body.contains("mesh") ? internal::string_member(body, "mesh") : "default";
    const bool binary = internal::boolean_member(body, "binary", false);
    {
      std::lock_guard<std::mutex> lock(m_sessions_mutex);
      make_room();   // refuse before reading the mesh
    }
    auto s = std::make_shared<Session>();
    s->mesh_name = name;
    s->rest = *m_meshes.get(m_options, name, s->stem);
    s->mesh = s->rest;
    s->last_used = Clock::now().time_since_epoch().count();
    json reply{{"mesh", name}, {"policy", policy_json(s->policy)}};
    if(!binary)
    {
      json faces = json::array();
      for(auto f : s->mesh.faces())
        for(vertex_descriptor v : CGAL::vertices_around_face(s->mesh.halfedge(f), s->mesh))
          faces.push_back(std::size_t(v));
      reply["vertices"] = internal::positions_json(s->mesh);
      reply["faces"] = std::move(faces);
    }
    const std::shared_ptr<const Session> created = s;
    {
      std::lock_guard<std::mutex> lock(m_sessions_mutex);
      make_room();
      std::string id;
      do
      {
        char text[17];
        std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(m_random()));
        id = text;
      } while(m_sessions.count(id));
      m_sessions[id] = std::move(s);
      reply["session"] = id;
    }
    if(!binary)
      return json_reply(reply);
    // (outside the table's lock: the session's rest mesh never changes)
    reply["vertex_count"] = num_vertices(created->rest);
    reply["face_count"] = num_faces(created->rest);
    Reply r;
    r.body = encode_mesh_frame(reply, created->rest);
    r.content_type = binary_type();
    return r;
  }

  Reply close_session(const json& body)
  {
    const std::string id = internal::string_member(body, "session");
    std::lock_guard<std::mutex> lock(m_sessions_mutex);
    const bool closed = m_sessions.erase(id) > 0;
    return json_reply(json{{"closed", closed}});
  }

  // ---- a session's requests (each under the session's lock)
  Reply select(const json& body)
  {
    const auto t0 = Clock::now();
    std::shared_ptr<Session> sp = session(body);
    Session& s = *sp;
    std::lock_guard<std::mutex> lock(s.mutex);
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
    json roi_ids = json::array(), handle_ids = json::array(), moving = json::array();
    for(vertex_descriptor v : s.roi) roi_ids.push_back(std::size_t(v));
    for(vertex_descriptor v : s.handles) handle_ids.push_back(std::size_t(v));
    for(vertex_descriptor v : s.moving) moving.push_back(std::size_t(v));
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return json_reply(json{{"roi", roi_ids}, {"handles", handle_ids}, {"moving", moving},
                           {"preprocess_seconds", s.deformer->last_result().seconds}, {"handler_seconds", seconds},
                           {"factorizations", factorizations(s)}});
  }

  // the reply of a deformation: JSON with "positions" of the moving vertices, or the binary frame
  static Reply deformation_reply(const Session& s, json header, bool binary)
  {
    header["count"] = s.moving.size();
    if(!binary)
    {
      header["positions"] = internal::positions_json(s.mesh, s.moving);
      return json_reply(header);
    }
    Reply r;
    r.body = encode_frame(header, s.mesh, s.moving);
    r.content_type = binary_type();
    return r;
  }

  Reply drag(const json& body)
  {
    const auto t0 = Clock::now();
    std::shared_ptr<Session> sp = session(body);
    Session& s = *sp;
    // the sequence number is registered before waiting for the lock: a drag queued behind a
    // long one sees a newer one arrive
    std::uint64_t seq;
    if(body.contains("seq"))
    {
      seq = std::uint64_t(internal::integer(body["seq"], "seq", 1, 1LL << 53));
      std::uint64_t newest = s.newest_drag.load();
      while(newest < seq && !s.newest_drag.compare_exchange_weak(newest, seq)) {}
    }
    else
      seq = s.newest_drag.fetch_add(1) + 1;
    Drag d = parse_drag(body);
    const bool binary = internal::boolean_member(body, "binary", false);
    std::lock_guard<std::mutex> lock(s.mutex);
    if(seq < s.newest_drag.load() || seq <= s.applied_drag)
      return json_reply(json{{"error", "superseded: drag " + std::to_string(seq) + " of this session was overtaken by drag " +
                                           std::to_string(std::max(s.newest_drag.load(), s.applied_drag)) + " (not solved)"},
                             {"superseded", true}, {"seq", seq}}, 409);
    if(!s.ready)
      throw Request_error{400, "select a region of interest and handles first (POST /api/select)"};
    if(!body.contains("rotation") || !body["rotation"].contains("center"))
      d.center = handle_centroid(s);
    json header = apply_drag(s, d, t0);
    s.applied_drag = seq;
    header["seq"] = seq;
    return deformation_reply(s, header, binary);
  }

  Reply set_policy(const json& body)
  {
    const auto t0 = Clock::now();
    std::shared_ptr<Session> sp = session(body);
    Session& s = *sp;
    const bool binary = internal::boolean_member(body, "binary", false);
    std::lock_guard<std::mutex> lock(s.mutex);
    Policy p = s.policy;
    if(body.contains("representation")) p.representation = internal::string_member(body, "representation");
    if(body.contains("weights")) p.weights = internal::string_member(body, "weights");
    if(body.contains("transform")) p.transform = internal::string_member(body, "transform");
    if(body.contains("start")) p.start = internal::string_member(body, "start");
    validate_policy(p);
    const std::optional<Drag> d = s.drag;
    change_policy(s, p);
    json header = s.ready && d ? apply_drag(s, *d, t0) : json::object();   // the same drag with the new policies
    header["policy"] = policy_json(s.policy);
    header["factorizations"] = factorizations(s);
    return deformation_reply(s, header, binary);
  }

  Reply reset(const json& body)
  {
    std::shared_ptr<Session> sp = session(body);
    Session& s = *sp;
    std::lock_guard<std::mutex> lock(s.mutex);
    if(internal::boolean_member(body, "selection", false))
    {
      s.roi.clear();
      s.handles.clear();
    }
    s.drag.reset();
    if(s.ready && !s.handles.empty())
      s.deformer->reset();
    else
      rebuild(s);
    return deformation_reply(s, json{{"factorizations", factorizations(s)}}, false);
  }

  Reply download(const std::map<std::string, std::string>& params)
  {
    auto p = params.find("session");
    auto f = params.find("format");
    if(p == params.end() || f == params.end())
      throw Request_error{400, "download needs ?session=ID&format=off|ply|sel|def"};
    std::shared_ptr<Session> sp = session(json{{"session", p->second}});
    std::lock_guard<std::mutex> lock(sp->mutex);
    Reply r;
    r.body = file_text(*sp, f->second);
    r.content_type = binary_type();
    r.filename = sp->stem + (f->second == "sel" || f->second == "def" ? "." : "_deformed.") + f->second;
    return r;
  }

  Reply save(const json& body)
  {
    std::shared_ptr<Session> sp = session(body);
    const std::string name = internal::string_member(body, "name");
    std::lock_guard<std::mutex> lock(sp->mutex);
    return json_reply(json{{"files", save_files(*sp, m_options.output_dir, name)}});
  }

  Server_options m_options;
  std::mutex m_sessions_mutex;   // guards m_sessions and m_random only
  std::map<std::string, std::shared_ptr<Session> > m_sessions;
  Mesh_cache m_meshes;           // the meshes read last (its own lock)
  std::mt19937_64 m_random;
};

} // namespace Laplacian_deformation_server

#endif // LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_SESSIONS_H
