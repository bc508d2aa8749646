// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// laplacian_deform --serve, requests and replies: the reply type, the checks of a request's JSON
// members (every refusal names the member), file names, the generated default mesh, k-rings (the
// tools' tool_regions.h), and the encodings of positions (JSON arrays, or the binary frame of the
// drag replies).
#ifndef LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_REQUESTS_H
#define LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_REQUESTS_H

#include "deformation_server/deformer.h"
#include "tool_mesh_io.h"
#include "tool_regions.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace Laplacian_deformation_server {

namespace fs = std::filesystem;
using json = nlohmann::json;

/// The content types of the replies. cpp-httplib compresses a reply when the client accepts it and
/// its type is exactly "application/json" or "application/javascript" or starts with "text/"
/// (Debian's build: Brotli at its slowest quality, seconds per megabyte). On the loopback
/// interface compression only costs time, so the large replies use types it leaves alone:
/// "...; charset=utf-8" and the binary frame (test_server checks the Content-Encoding header).
inline const char* json_type() { return "application/json; charset=utf-8"; }
inline const char* javascript_type() { return "application/javascript; charset=utf-8"; }
inline const char* binary_type() { return "application/octet-stream"; }

/// An answer: HTTP status, body and its type; `filename` makes it a download; `cache_control` and
/// `etag` are the HTTP headers (API replies are never cached).
struct Reply
{
  int status = 200;
  std::string body;
  std::string content_type = json_type();
  std::string filename;
  std::string cache_control = "no-store";
  std::string etag;
};

// (bytes that are not UTF-8, as a URL or a header echoed in an error message may hold, are
// replaced by U+FFFD: nlohmann-json would throw)
inline std::string dump(const json& j) { return j.dump(-1, ' ', false, json::error_handler_t::replace); }

inline Reply json_reply(const json& j, int status = 200)
{
  Reply r;
  r.status = status;
  r.body = dump(j);
  return r;
}
inline Reply error_reply(int status, const std::string& message) { return json_reply(json{{"error", message}}, status); }

/// A request error: becomes a 4xx reply with {"error": message}.
struct Request_error
{
  int status;
  std::string message;
};

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

inline bool boolean_member(const json& body, const char* key, bool fallback)
{
  if(!body.contains(key))
    return fallback;
  if(!body[key].is_boolean())
    throw Request_error{400, std::string(key) + " must be true or false"};
  return body[key].get<bool>();
}

// letters, digits, '_', '-' (and '.' if allowed); not empty, at most 128, not starting with '.' or
// '-' (a name must never look like an option of a command it is later given to)
inline bool is_plain_name(const std::string& s, bool allow_dot)
{
  if(s.empty() || s.size() > 128 || s[0] == '.' || s[0] == '-')
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

// a plain file name with an extension of the tools' mesh reader (tool_mesh_io.h)
inline bool is_mesh_file_name(const std::string& name)
{
  return is_plain_name(name, true) &&
         Laplacian_deformation_tools::is_mesh_extension(Laplacian_deformation_tools::extension_of(fs::path(name)));
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

// vertices within k rings of `seeds`, in breadth-first order (the tools' k-ring of tool_regions.h,
// as laplacian_deform --roi-rings)
inline std::vector<vertex_descriptor> grow(const Mesh& m, const std::vector<vertex_descriptor>& seeds, int k)
{
  return Laplacian_deformation_tools::k_ring_vertices(m, seeds, std::size_t(std::max(k, 0)));
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

// the positions of `vertices` of `m` (x, y, z each), as a JSON array
inline json positions_json(const Mesh& m, const std::vector<vertex_descriptor>& vertices)
{
  json a = json::array();
  for(vertex_descriptor v : vertices)
  {
    const Point_3& p = m.point(v);
    a.push_back(p.x());
    a.push_back(p.y());
    a.push_back(p.z());
  }
  return a;
}

inline void append_le32(std::string& out, std::uint32_t x)
{
  for(int k = 0; k < 4; ++k)
    out.push_back(char((x >> (8 * k)) & 0xffu));
}

// `bytes` little-endian bytes of `frame` from `at`
inline std::uint64_t read_le(const std::string& frame, std::size_t at, int bytes)
{
  std::uint64_t x = 0;
  for(int k = 0; k < bytes; ++k)
    x |= std::uint64_t(static_cast<unsigned char>(frame[at + std::size_t(k)])) << (8 * k);
  return x;
}

// The start of a binary frame: a little-endian uint32 L and L bytes of `header` as JSON, padded
// with spaces so that the payload starts at a multiple of `alignment`; `payload` bytes are
// reserved after it.
inline std::string frame_start(const json& header, std::size_t alignment, std::size_t payload)
{
  std::string text = dump(header);
  while((4 + text.size()) % alignment != 0)
    text.push_back(' ');
  std::string out;
  out.reserve(4 + text.size() + payload);
  append_le32(out, std::uint32_t(text.size()));
  out += text;
  return out;
}

// Reads the start of a frame made by frame_start(): its header (a JSON object) and the offset of
// its payload, or 0 if `frame` does not start with one.
inline std::size_t frame_header(const std::string& frame, std::size_t alignment, json& header)
{
  if(frame.size() < 4)
    return 0;
  const std::size_t n = std::size_t(read_le(frame, 0, 4));
  if(n > frame.size() - 4 || (4 + n) % alignment != 0)
    return 0;
  header = json::parse(frame.substr(4, n), nullptr, false);
  return header.is_object() ? 4 + n : 0;
}

} // namespace internal

/// The binary frame of a drag reply (`"binary": true`): a little-endian uint32 L, L bytes of a
/// JSON object (`header`, padded with spaces so that the floats start at a multiple of 4), then
/// x, y, z as little-endian float32 for each of `vertices` (the session's moving vertices, in the
/// order of the selection reply's "moving").
inline std::string encode_frame(const json& header, const Mesh& m, const std::vector<vertex_descriptor>& vertices)
{
  std::string out = internal::frame_start(header, 4, 12 * vertices.size());
  for(vertex_descriptor v : vertices)
  {
    const Point_3& p = m.point(v);
    for(double c : {p.x(), p.y(), p.z()})
    {
      const float f = float(c);
      std::uint32_t bits;
      std::memcpy(&bits, &f, 4);
      internal::append_le32(out, bits);
    }
  }
  return out;
}

/// The binary frame of a session reply (`"binary": true`): a little-endian uint32 L, L bytes of a
/// JSON object (`header`, padded with spaces so that the coordinates start at a multiple of 8),
/// then x, y, z as little-endian float64 for every vertex of `m` in index order, then the three
/// vertex ids of every face as little-endian uint32. A page views them as typed arrays, without
/// parsing millions of numbers (a 416k-vertex mesh is 39 MB of JSON, 17 MB in this frame).
/// `m` must have no garbage and triangle faces only.
inline std::string encode_mesh_frame(const json& header, const Mesh& m)
{
  if(!CGAL::is_triangle_mesh(m) || m.has_garbage())
    throw std::logic_error("encode_mesh_frame: the mesh has garbage or a face that is not a triangle");
  std::string out = internal::frame_start(header, 8, 0);
  std::size_t at = out.size();
  out.resize(at + 24 * num_vertices(m) + 12 * num_faces(m));
  const auto put = [&](std::uint64_t bits, int bytes) {   // little-endian, whatever the host's order
    for(int k = 0; k < bytes; ++k)
      out[at++] = char((bits >> (8 * k)) & 0xffu);
  };
  for(vertex_descriptor v : m.vertices())
  {
    const Point_3& p = m.point(v);
    for(double c : {p.x(), p.y(), p.z()})
    {
      std::uint64_t bits;
      std::memcpy(&bits, &c, 8);
      put(bits, 8);
    }
  }
  for(auto f : m.faces())
    for(vertex_descriptor v : CGAL::vertices_around_face(m.halfedge(f), m))
      put(std::uint32_t(v), 4);
  return out;
}

/// Decodes `encode_mesh_frame` (for tests): false if `frame` is not one, with the header's
/// "vertex_count" and "face_count".
inline bool decode_mesh_frame(const std::string& frame, json& header, std::vector<double>& xyz,
                              std::vector<std::uint32_t>& faces)
{
  const std::size_t at = internal::frame_header(frame, 8, header);
  if(at == 0 || !header.contains("vertex_count") || !header.contains("face_count") ||
     !header["vertex_count"].is_number_unsigned() || !header["face_count"].is_number_unsigned())
    return false;
  const std::size_t nv = header["vertex_count"].get<std::size_t>(), nf = header["face_count"].get<std::size_t>();
  const std::size_t payload = frame.size() - at;
  if(nv > payload / 24 || nf > payload / 12 || payload != 24 * nv + 12 * nf)
    return false;
  xyz.resize(3 * nv);
  for(std::size_t i = 0; i < xyz.size(); ++i)
  {
    const std::uint64_t bits = internal::read_le(frame, at + 8 * i, 8);
    std::memcpy(&xyz[i], &bits, 8);
  }
  faces.resize(3 * nf);
  for(std::size_t i = 0; i < faces.size(); ++i)
    faces[i] = std::uint32_t(internal::read_le(frame, at + 24 * nv + 4 * i, 4));
  return true;
}

/// Decodes `encode_frame` (for tests and the fuzz target): false if `frame` is not one.
inline bool decode_frame(const std::string& frame, json& header, std::vector<float>& xyz)
{
  const std::size_t at = internal::frame_header(frame, 4, header);
  if(at == 0 || (frame.size() - at) % 12 != 0)
    return false;
  xyz.resize((frame.size() - at) / 4);
  for(std::size_t i = 0; i < xyz.size(); ++i)
  {
    const std::uint32_t bits = std::uint32_t(internal::read_le(frame, at + 4 * i, 4));
    std::memcpy(&xyz[i], &bits, 4);
  }
  return true;
}

} // namespace Laplacian_deformation_server

#endif // LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_REQUESTS_H
