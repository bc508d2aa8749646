// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// laplacian_deform --serve, one browser session: its mesh, selection, deformer and last drag, and
// what is done to it (the caller holds the session's lock): open a mesh (the tools' checked reader,
// tool_mesh_io.h), rebuild and preprocess the deformer, apply a drag, write the mesh and the
// Botsch08 task as files (atomically, tool_files.h).
#ifndef LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_SESSION_H
#define LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_SESSION_H

#include "deformation_server/requests.h"
#include "tool_files.h"
#include "tool_mesh_io.h"

#include <CGAL/boost/graph/IO/polygon_mesh_io.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/Laplacian_deformation/IO/Botsch08.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <list>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>

namespace Laplacian_deformation_server {

/// One browser session. `mutex` is held for the whole of each request on the session.
struct Session
{
  std::mutex mutex;
  std::atomic<std::uint64_t> newest_drag{0};      // the highest drag sequence number received
  std::uint64_t applied_drag = 0;                 // the sequence number of the drag applied last
  std::atomic<std::chrono::steady_clock::rep> last_used{0};
  std::string mesh_name;
  std::string stem;                               // the downloads' file names
  Mesh rest, mesh;
  Policy policy;
  // built on the session's rest mesh at the first selection, then kept for every later selection
  // and policy of the same representation: a new selection costs what the selection costs (no
  // copy of the mesh, no new deformer with its per-vertex arrays; the library reuses its operator
  // where it covers the new region of interest)
  std::unique_ptr<Deformer_interface> deformer;
  Policy deformer_policy;                         // the policies `deformer` holds
  bool ready = false;                             // `deformer` holds the selection, preprocessed
  std::size_t factorizations_before = 0;          // the deformer's factorisations before the selection's
  std::size_t deformers_built = 0;                // in the session's life (for tests)
  std::vector<vertex_descriptor> roi, handles;    // roi excludes the handles
  std::vector<vertex_descriptor> moving;          // roi then handles: the order of the drag replies' positions
  std::optional<Drag> drag;
};

/// the factorisations of the session's selection since it was made or its policies changed (0 without one)
inline std::size_t factorizations(const Session& s)
{
  return s.ready ? s.deformer->number_of_factorizations() - s.factorizations_before : 0;
}

/// The file names of the meshes a page may open: "default", then those of `data_dir`.
inline json mesh_names(const std::string& data_dir)
{
  json names = json::array({"default"});
  std::error_code ec;
  std::vector<std::string> found;
  for(fs::directory_iterator it(data_dir, ec), end; !ec && it != end; it.increment(ec))
    if(it->is_regular_file() && internal::is_mesh_file_name(it->path().filename().string()))
      found.push_back(it->path().filename().string());
  std::sort(found.begin(), found.end());
  for(const std::string& f : found) names.push_back(f);
  return names;
}

/// The mesh `name` ("default" or a file name of the data folder), geometry only; `stem` gets the
/// downloads' base name.
template <class Options>
Mesh load_mesh(const Options& options, const std::string& name, std::string& stem)
{
  Mesh m;
  fs::path file;
  if(name == "default")
  {
    file = !options.mesh.empty() ? fs::path(options.mesh) : fs::path(options.data_dir) / "cactus.off";
    if(options.mesh.empty() && !fs::is_regular_file(file))
    {
      stem = "bumpy_plane";
      return internal::bumpy_plane();
    }
  }
  else
  {
    if(!internal::is_mesh_file_name(name))
      throw Request_error{400, "mesh must be \"default\" or a file name (.off, .obj, .ply, .stl) of the data folder, got \"" + name + "\""};
    file = fs::path(options.data_dir) / name;
  }
  // the tools' checked reader (tool_mesh_io.h, as laplacian_deform's); its reason names no folder
  std::string error, reason;
  if(!Laplacian_deformation_tools::read_mesh_file(file, m, error, &reason))
    throw Request_error{400, "cannot read a mesh from " + (name == "default" ? file.string() : name) + ": " + reason};
  if(!CGAL::is_triangle_mesh(m))
    throw Request_error{400, name + ": the mesh has non-triangle faces"};
  if(num_vertices(m) > options.max_vertices)
    throw Request_error{400, name + ": more than " + std::to_string(options.max_vertices) + " vertices"};
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
  stem = file.stem().string();
  if(!internal::is_plain_name(stem, false))
    stem = "mesh";
  return clean;
}

/// The meshes read last, so that opening the same mesh again (a reload of the page, a second
/// page, the server's own check of its default mesh at start-up) costs a copy, not a read of the
/// file: reading and checking a 416k-vertex OFF file takes seconds. An entry is used only while
/// its file has the same size and modification time; at most `capacity` meshes are kept (the least
/// recently used goes first). Thread-safe; a mesh is read outside the lock.
class Mesh_cache
{
public:
  explicit Mesh_cache(std::size_t capacity = 2) : m_capacity(capacity) {}

  /// load_mesh(options, name, stem), or the mesh kept from an earlier call for the same file
  template <class Options>
  std::shared_ptr<const Mesh> get(const Options& options, const std::string& name, std::string& stem)
  {
    const std::optional<Key> key = key_of(options, name);
    if(key)
    {
      std::lock_guard<std::mutex> lock(m_mutex);
      for(auto it = m_entries.begin(); it != m_entries.end(); ++it)
        if(it->key == *key)
        {
          m_entries.splice(m_entries.begin(), m_entries, it);   // most recently used first
          stem = it->stem;
          ++m_hits;
          return it->mesh;
        }
    }
    auto mesh = std::make_shared<const Mesh>(load_mesh(options, name, stem));
    if(key && m_capacity > 0)
    {
      std::lock_guard<std::mutex> lock(m_mutex);
      m_entries.remove_if([&](const Entry& e) { return e.key == *key; });
      m_entries.push_front(Entry{*key, stem, mesh});
      while(m_entries.size() > m_capacity)
        m_entries.pop_back();
    }
    return mesh;
  }

  /// For tests: how many calls were answered from the cache.
  std::size_t hits()
  {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_hits;
  }

private:
  struct Key
  {
    std::string file;
    std::uintmax_t size = 0;
    fs::file_time_type::rep modified = 0;
    bool operator==(const Key& o) const { return file == o.file && size == o.size && modified == o.modified; }
  };
  struct Entry
  {
    Key key;
    std::string stem;
    std::shared_ptr<const Mesh> mesh;
  };

  // the file `name` stands for, with its size and time; none for the generated plane, a bad name
  // or a file that cannot be examined (load_mesh() then says why, uncached)
  template <class Options>
  static std::optional<Key> key_of(const Options& options, const std::string& name)
  {
    fs::path file;
    if(name == "default")
    {
      if(options.mesh.empty())
        file = fs::path(options.data_dir) / "cactus.off";
      else
        file = fs::path(options.mesh);
    }
    else if(internal::is_mesh_file_name(name))
      file = fs::path(options.data_dir) / name;
    else
      return std::nullopt;
    std::error_code ec;
    const fs::path canonical = fs::canonical(file, ec);
    if(ec || !fs::is_regular_file(canonical, ec) || ec)
      return std::nullopt;
    Key key;
    key.file = canonical.string();
    key.size = fs::file_size(canonical, ec);
    if(ec)
      return std::nullopt;
    const fs::file_time_type time = fs::last_write_time(canonical, ec);
    if(ec)
      return std::nullopt;
    key.modified = time.time_since_epoch().count();
    return key;
  }

  std::size_t m_capacity;
  std::mutex m_mutex;
  std::list<Entry> m_entries;
  std::size_t m_hits = 0;
};

inline json policy_json(const Policy& p)
{
  return json{{"representation", p.representation}, {"weights", p.weights}, {"transform", p.transform},
              {"start", p.start}};
}

inline void validate_policy(const Policy& p)
{
  // the names of policy_names.h (a transform's alias too: S*R1 is "scaled_rotation" in the editor)
  if(!policy_names::find(policy_names::representations(), p.representation))
    throw Request_error{400, "representation must be " + policy_names::name_list(policy_names::representations(), "\"") +
                                 ", got \"" + p.representation + "\""};
  if(!policy_names::find(policy_names::weight_policies(), p.weights))
    throw Request_error{400, "weights must be " + policy_names::name_list(policy_names::weight_policies(), "\"") +
                                 ", got \"" + p.weights + "\""};
  if(!policy_names::find(policy_names::transform_policies(), p.transform))
    throw Request_error{400, "transform must be " + policy_names::name_list(policy_names::transform_policies(), "\"", true) +
                                 ", got \"" + p.transform + "\""};
  if(p.start != "identity" && p.start != "rotation")
    throw Request_error{400, "start must be \"identity\" or \"rotation\", got \"" + p.start + "\""};
}

/// preprocesses the session's selection (if it has handles) on its deformer, from the rest mesh:
/// the vertices the previous selection moved go back to rest (the deformer writes no other), the
/// deformer is kept if its representation is the policy's (its weights, transform and start set to
/// the policy's), else a new one is built on the rest mesh. A failed preprocess clears the selection
/// and leaves the mesh at rest.
inline void rebuild(Session& s)
{
  s.ready = false;
  if(s.deformer)
  {
    s.deformer->reset();            // its ROI at rest, its targets too
    s.deformer->clear_roi_vertices();
  }
  for(vertex_descriptor v : s.moving)
    s.mesh.point(v) = s.rest.point(v);
  s.moving = s.roi;
  s.moving.insert(s.moving.end(), s.handles.begin(), s.handles.end());
  if(s.handles.empty())
    return;
  if(!s.deformer || s.deformer_policy.representation != s.policy.representation)
  {
    s.deformer.reset();
    s.deformer = make_deformer(s.mesh, s.policy);
    ++s.deformers_built;
  }
  else
  {
    if(s.deformer_policy.weights != s.policy.weights)
      s.deformer->set_weight_policy(policy_names::weight_policy(s.policy.weights));
    if(s.deformer_policy.transform != s.policy.transform)
      s.deformer->set_transform_policy(policy_names::transform_policy(s.policy.transform));
    s.deformer->set_start(s.policy.start == "rotation" ? LD::ROTATION_START : LD::IDENTITY_START);
  }
  s.deformer_policy = s.policy;
  Deformer_interface& d = *s.deformer;
  for(vertex_descriptor v : s.roi) d.insert_roi_vertex(v);
  for(vertex_descriptor v : s.handles) d.insert_control_vertex(v);
  s.factorizations_before = d.number_of_factorizations();
  if(!d.preprocess())
  {
    const std::string message = d.last_result().message;
    d.clear_roi_vertices();
    s.roi.clear();
    s.handles.clear();
    s.moving.clear();
    s.drag.reset();
    throw Request_error{400, "cannot preprocess this selection: " + message};
  }
  s.ready = true;
}

/// the session's policies become `p`: a change of the transform or the start alone keeps the
/// factorisation (the deformer restarts from the rest pose with them), any other change rebuilds
/// the selection (rebuild())
inline void change_policy(Session& s, const Policy& p)
{
  s.policy = p;
  if(s.ready && p.representation == s.deformer_policy.representation && p.weights == s.deformer_policy.weights)
  {
    s.deformer->reset();
    if(p.transform != s.deformer_policy.transform)
      s.deformer->set_transform_policy(policy_names::transform_policy(p.transform));
    s.deformer->set_start(p.start == "rotation" ? LD::ROTATION_START : LD::IDENTITY_START);
    s.deformer_policy = p;
    return;
  }
  rebuild(s);
}

/// The drag described by a request body (`center` left at 0: the caller sets the default).
inline Drag parse_drag(const json& body)
{
  Drag d;
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
  return d;
}

inline Eigen::Vector3d handle_centroid(const Session& s)
{
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for(vertex_descriptor v : s.handles)
  {
    const Point_3& p = s.rest.point(v);
    c += Eigen::Vector3d(p.x(), p.y(), p.z());
  }
  return s.handles.empty() ? c : Eigen::Vector3d(c / double(s.handles.size()));
}

/// sets the targets of the drag and deforms; returns the timings (the positions are in s.mesh)
inline json apply_drag(Session& s, const Drag& d, std::chrono::steady_clock::time_point t0)
{
  const Eigen::Matrix4d m = d.matrix();
  auto target = [&m, &s](vertex_descriptor v) {
    const Point_3& p = s.rest.point(v);
    const Eigen::Vector4d q = m * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.);
    return Point_3(q.x(), q.y(), q.z());
  };
  for(vertex_descriptor v : s.handles)
    s.deformer->set_target_position(v, target(v));
  const LD::Deformation_result r = s.deformer->deform(d.iterations, 0.);
  if(!r)
    throw Request_error{400, "the deformation failed: " + r.message};
  s.drag = d;
  double error = 0;
  for(vertex_descriptor v : s.handles)
    error = (std::max)(error, std::sqrt(CGAL::squared_distance(s.mesh.point(v), target(v))));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  json warnings = json::array();        // the result is a success; these say it may not be what was meant
  for(const LD::Deformation_warning& w : r.warnings)
    warnings.push_back({{"kind", LD::warning_kind_name(w.kind)}, {"count", w.count}, {"message", w.message}});
  return json{{"seconds", r.seconds}, {"local_step_seconds", r.local_step_seconds}, {"warnings", warnings},
              {"right_hand_side_seconds", r.right_hand_side_seconds}, {"solve_seconds", r.solve_seconds},
              {"iterations", r.iterations}, {"energy", r.energy}, {"handler_seconds", seconds},
              {"factorizations", factorizations(s)}, {"handle_error", error}};
}

/// the session's mesh (off, ply), selection (sel) or handle transformation (def) as text
inline std::string file_text(const Session& s, const std::string& format)
{
  std::ostringstream out;
  out.precision(17);
  bool ok = false;
  if(format == "off")
    ok = CGAL::IO::write_OFF(out, s.mesh, CGAL::parameters::stream_precision(17));
  else if(format == "ply")
    ok = CGAL::IO::write_PLY(out, s.mesh, CGAL::parameters::use_binary_mode(false).stream_precision(17));
  else if(format == "sel")
  {
    std::vector<int> status(num_vertices(s.mesh), LD::IO::BOTSCH08_FIXED);
    for(vertex_descriptor v : s.roi) status[v] = LD::IO::BOTSCH08_REGION_OF_INTEREST;
    for(vertex_descriptor v : s.handles) status[v] = LD::IO::BOTSCH08_HANDLE;
    ok = LD::IO::write_botsch08_selection(out, status);
  }
  else if(format == "def")
    ok = LD::IO::write_botsch08_transform(out, s.drag ? s.drag->matrix() : Eigen::Matrix4d::Identity().eval());
  else
    throw Request_error{400, "format must be off, ply, sel or def, got \"" + format + "\""};
  if(!ok)
    throw Request_error{500, "cannot write the " + format + " file"};
  return out.str();
}

/// writes NAME.off, NAME.sel and NAME.def into `folder` (and nowhere else); returns their paths.
/// NAME: 1 to 64 letters, digits, '_' or '-', not starting with '-' (no '.', no path separator:
/// the three extensions are the server's).
inline json save_files(const Session& s, const std::string& folder_name, const std::string& name)
{
  if(!internal::is_plain_name(name, false) || name.size() > 64)
    throw Request_error{400, "name must be 1 to 64 letters, digits, '_' or '-' (not first; no '.', no '/': the server adds "
                             ".off, .sel and .def), got \"" + name + "\""};
  const fs::path folder(folder_name);
  std::error_code ec;
  fs::create_directories(folder, ec);
  if(ec)
    throw Request_error{500, "cannot create the output folder " + folder.string() + ": " + ec.message()};
  json files = json::array();
  for(const char* format : {"off", "sel", "def"})
  {
    const fs::path path = folder / (name + "." + format);
    std::string error;
    if(!Laplacian_deformation_tools::write_text_atomically(path, file_text(s, format), error))   // tool_files.h
      throw Request_error{500, error};
    files.push_back(path.string());
  }
  return files;
}

} // namespace Laplacian_deformation_server

#endif // LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_SESSION_H
