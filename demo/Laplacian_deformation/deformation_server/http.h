// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// laplacian_deform --serve, the HTTP layer: who may talk to the server (`refusal`: the Host and
// Origin checks against DNS rebinding and other sites, the per-run token, the content type of API
// calls), the static files of the page (cacheable, revalidated by ETag), and the routes of an
// httplib::Server onto a Deformation_server.
#ifndef LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_HTTP_H
#define LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_HTTP_H

#include "deformation_server/sessions.h"

#include <httplib.h>

#include <atomic>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <string>

namespace Laplacian_deformation_server {

/// What the guard looks at in a request (header values are empty when absent).
struct Request_facts
{
  std::string method, path, host, origin, content_type, token_header, token_query;
  bool has_origin = false;
};

namespace internal {

inline std::string lower(std::string s)
{
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

inline bool same_secret(const std::string& a, const std::string& b)   // compares in time independent of the content
{
  if(a.size() != b.size() || a.empty())
    return false;
  unsigned char d = 0;
  for(std::size_t i = 0; i < a.size(); ++i)
    d |= static_cast<unsigned char>(a[i] ^ b[i]);
  return d == 0;
}

} // namespace internal

/// A random token of 32 hex digits (128 bits).
inline std::string random_token()
{
  std::random_device device;
  std::string t;
  for(int i = 0; i < 4; ++i)
  {
    char part[9];
    std::snprintf(part, sizeof part, "%08x", static_cast<unsigned>(device()));
    t += part;
  }
  return t;
}

/// Nothing if the request may go on; else the refusal. Every request: the Host header must be
/// 127.0.0.1:PORT or localhost:PORT (a DNS-rebinding page sends its own host name), and an Origin,
/// if present, http://127.0.0.1:PORT or http://localhost:PORT (another site's page). API calls
/// (/api/...) also need the token (header X-Editor-Token; a GET may pass ?token=), and a POST the
/// content type application/json (a page of another site can post text/plain or a form blindly).
inline std::optional<Reply> refusal(const Request_facts& r, int port, const std::string& token)
{
  const std::string p = std::to_string(port), host = internal::lower(r.host);
  if(host != "127.0.0.1:" + p && host != "localhost:" + p)
    return error_reply(403, "refused: the Host header \"" + r.host + "\" is not 127.0.0.1:" + p + " or localhost:" + p +
                                " (the editor answers only to its own address)");
  const std::string origin = internal::lower(r.origin);
  if(r.has_origin && origin != "http://127.0.0.1:" + p && origin != "http://localhost:" + p)
    return error_reply(403, "refused: the request comes from another site (Origin \"" + r.origin + "\")");
  if(r.path.rfind("/api/", 0) != 0)
    return std::nullopt;
  const bool header_ok = internal::same_secret(r.token_header, token);
  if(!header_ok && !(r.method == "GET" && internal::same_secret(r.token_query, token)))
    return error_reply(401, std::string(r.token_header.empty() && r.token_query.empty() ? "missing" : "wrong") +
                                " token: API calls need the token of the address the tool printed "
                                "(header X-Editor-Token; open http://127.0.0.1:" + p + "/#token=...)");
  if(r.method == "POST")
  {
    std::string type = internal::lower(r.content_type.substr(0, r.content_type.find(';')));
    type.erase(std::remove(type.begin(), type.end(), ' '), type.end());
    if(type != "application/json")
      return error_reply(415, "API calls must be sent as Content-Type: application/json, got \"" + r.content_type + "\"");
  }
  return std::nullopt;
}

/// The file behind a static URL path, or nothing: `/` and `/editor.html`, `/editor.js`, `/lib/*.js`
/// from the viewer folder, `/three/...` from viewer/node_modules/three. No `..`, no NUL, no
/// backslash, and the resolved file (symbolic links followed) must stay inside its root.
inline std::optional<fs::path> static_file(const std::string& viewer_dir, const std::string& url)
{
  if(url.find("..") != std::string::npos || url.find('\0') != std::string::npos ||
     url.find('\\') != std::string::npos || url.empty() || url[0] != '/')
    return std::nullopt;
  const fs::path viewer(viewer_dir);
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

/// Serves a static file (see `static_file`) with an ETag (size and modification time): the page's
/// own files are revalidated on each load ("no-cache": 304 when unchanged), three.js is cached for
/// a day. `if_none_match` is the request's If-None-Match header (304 when it names the ETag).
inline Reply get_static(const std::string& viewer_dir, const std::string& url, const std::string& if_none_match = "")
{
  const std::optional<fs::path> file = static_file(viewer_dir, url);
  if(!file)
    return error_reply(404, "not found: " + url);
  std::error_code ec;
  const auto size = fs::file_size(*file, ec);
  const auto time = fs::last_write_time(*file, ec).time_since_epoch().count();
  char etag[64];
  std::snprintf(etag, sizeof etag, "\"%llx-%llx\"", static_cast<unsigned long long>(size),
                static_cast<unsigned long long>(time));
  Reply r;
  r.etag = etag;
  r.cache_control = url.rfind("/three/", 0) == 0 ? "public, max-age=86400" : "no-cache";
  const std::string e = internal::lower_extension(*file);
  r.content_type = e == ".html" ? "text/html; charset=utf-8"
                   : e == ".js" || e == ".mjs" ? javascript_type()
                   : e == ".json" ? json_type() : binary_type();
  if(!if_none_match.empty() && if_none_match == r.etag)
  {
    r.status = 304;
    return r;
  }
  std::ifstream in(*file, std::ios::binary);
  std::ostringstream data;
  data << in.rdbuf();
  r.body = data.str();
  return r;
}

inline void send(const Reply& r, httplib::Response& res)
{
  res.status = r.status;
  if(!r.filename.empty())
    res.set_header("Content-Disposition", "attachment; filename=\"" + r.filename + "\"");
  res.set_header("Cache-Control", r.cache_control);
  if(!r.etag.empty())
    res.set_header("ETag", r.etag);
  res.set_header("X-Content-Type-Options", "nosniff");
  if(r.status != 304)
    res.set_content(r.body, r.content_type.c_str());
}

/// Who may talk to the server: its token and (once bound) its port.
struct Http_guard
{
  std::string token;
  std::atomic<int> port{0};
};

/// Routes every request of `http` to `server`, each checked by `guard` first (`refusal`).
inline void install_routes(httplib::Server& http, Deformation_server& server, Http_guard& guard)
{
  const std::size_t limit = server.options().max_body_bytes;
  http.set_payload_max_length(limit);
  http.set_pre_routing_handler([&guard](const httplib::Request& req, httplib::Response& res) {
    Request_facts f;
    f.method = req.method;
    f.path = req.path;
    f.host = req.get_header_value("Host");
    f.has_origin = req.has_header("Origin");
    f.origin = req.get_header_value("Origin");
    f.content_type = req.get_header_value("Content-Type");
    f.token_header = req.get_header_value("X-Editor-Token");
    f.token_query = req.has_param("token") ? req.get_param_value("token") : std::string();
    const std::optional<Reply> refused = refusal(f, guard.port.load(), guard.token);
    if(!refused)
      return httplib::Server::HandlerResponse::Unhandled;
    send(*refused, res);
    return httplib::Server::HandlerResponse::Handled;
  });
  http.Post(R"(/api/.*)", [&server](const httplib::Request& req, httplib::Response& res) {
    send(server.post(req.path, req.body), res);
  });
  http.Get(R"(/api/.*)", [&server](const httplib::Request& req, httplib::Response& res) {
    std::map<std::string, std::string> params;
    for(const auto& p : req.params) params[p.first] = p.second;
    send(server.get(req.path, params), res);
  });
  http.Get(R"(/.*)", [&server](const httplib::Request& req, httplib::Response& res) {
    send(get_static(server.options().viewer_dir, req.path, req.get_header_value("If-None-Match")), res);
  });
  // errors found by httplib itself (a body over the limit, a broken multipart body, no route)
  // get a message too
  http.set_error_handler(httplib::Server::HandlerWithResponse([limit](const httplib::Request& req, httplib::Response& res) {
    if(!res.body.empty())
      return httplib::Server::HandlerResponse::Unhandled;
    const std::string message =
      res.status == 413 ? "the request body is larger than the limit of " + std::to_string(limit) + " bytes"
      : res.status == 404 ? "not found: " + req.method + " " + req.path
      : res.status == 400 ? "malformed HTTP request (its headers, body length or multipart body cannot be read)"
      : "HTTP status " + std::to_string(res.status);
    send(error_reply(res.status, message), res);
    return httplib::Server::HandlerResponse::Handled;
  }));
  http.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
    send(error_reply(500, "internal error"), res);
  });
}

} // namespace Laplacian_deformation_server

#endif // LAPLACIAN_DEFORMATION_DEMO_DEFORMATION_SERVER_HTTP_H
