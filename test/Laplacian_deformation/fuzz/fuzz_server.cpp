// libFuzzer target: the request handling of `laplacian_deform --serve`
// (demo/Laplacian_deformation/deformation_server.h) without sockets. The first byte picks what the
// rest is: a JSON body POSTed to one of the API paths, a GET query string, a static URL, the
// headers the guard looks at, or a binary frame to decode. In bodies and queries "$S" stands for
// the id of a live session that has a selection (recreated when the input closed it).
// Properties: no crash, no sanitizer finding, no status 500; every refusal is a JSON object with
// an "error" string; a drag, policy or reset reply holds 3 finite coordinates per moving vertex
// (JSON or the binary frame); a static file found lies inside the viewer folder; the guard lets a
// request through only with a loopback Host on the server's port and, for the API, the token.
#include "deformation_server.h"

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

using namespace Laplacian_deformation_server;

namespace {

void check(bool condition, const char* what, const std::string& detail = std::string())
{
  if(!condition)
  {
    std::fprintf(stderr, "property violated: %s %s\n", what, detail.substr(0, 400).c_str());
    std::abort();
  }
}

const int port = 8123;
const std::string token = "0123456789abcdef0123456789abcdef";
fs::path root;
std::unique_ptr<Deformation_server> server;
std::string session_id;

void ensure_session()
{
  if(!session_id.empty() && server->post("/api/reset", json{{"session", session_id}}.dump()).status == 200)
    return;
  const Reply r = server->post("/api/session", R"({"mesh":"default"})");
  check(r.status == 200, "the default session opens", r.body);
  session_id = json::parse(r.body)["session"].get<std::string>();
  const Reply s = server->post("/api/select", json{{"session", session_id}, {"handles", {420}}, {"grow", 2}}.dump());
  check(s.status == 200, "the selection is preprocessed", s.body);
}

std::string with_session(std::string text)
{
  for(std::size_t at = text.find("$S"); at != std::string::npos; at = text.find("$S", at + session_id.size()))
    text.replace(at, 2, session_id);
  return text;
}

void check_reply(const Reply& r, const std::string& path)
{
  check(r.status != 500, "no internal error", path + " -> " + r.body);
  if(r.status != 200)
  {
    const json j = json::parse(r.body, nullptr, false);
    check(j.is_object() && j.contains("error") && j["error"].is_string(), "a refusal carries a message", r.body);
    return;
  }
  if(path != "/api/drag" && path != "/api/policy" && path != "/api/reset")
    return;
  json header;
  std::vector<float> xyz;
  if(r.content_type == binary_type())
  {
    check(decode_frame(r.body, header, xyz), "a binary reply is a frame");
    check(header.contains("count") && xyz.size() == 3 * header["count"].get<std::size_t>(), "a frame holds count vertices");
    for(float x : xyz) check(std::isfinite(x), "finite coordinates");
  }
  else
  {
    header = json::parse(r.body);
    check(header["positions"].size() == 3 * header["count"].get<std::size_t>(), "positions of count vertices", r.body);
    for(const json& x : header["positions"]) check(x.is_number() && std::isfinite(x.get<double>()), "finite coordinates");
  }
}

std::vector<std::string> lines(const std::string& text, std::size_t n)
{
  std::vector<std::string> out(n);
  std::size_t start = 0;
  for(std::size_t i = 0; i < n && start <= text.size(); ++i)
  {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    out[i] = text.substr(start, end - start);
    start = end + 1;
  }
  return out;
}

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
  root = fs::temp_directory_path() / ("fuzz_server_" + std::to_string(::getpid()));
  fs::create_directories(root / "data");
  fs::create_directories(root / "viewer" / "lib");
  std::ofstream(root / "data" / "tetra.off") << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
  std::ofstream(root / "viewer" / "editor.html") << "<html>";
  std::ofstream(root / "viewer" / "lib" / "mesh.js") << "export {};";
  std::ofstream(root / "secret.js") << "secret";
  Server_options o;
  o.data_dir = (root / "data").string();
  o.output_dir = (root / "out").string();
  o.viewer_dir = (root / "viewer").string();
  o.max_sessions = 4;
  o.session_idle_seconds = 0;
  o.token = token;
  server = std::make_unique<Deformation_server>(o);
  std::atexit([] { server.reset(); std::error_code ec; fs::remove_all(root, ec); });
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  if(size < 2 || size > 4096)
    return 0;
  static const char* const paths[] = {"/api/session", "/api/select", "/api/drag", "/api/policy", "/api/reset",
                                      "/api/save", "/api/close", "/api/nothing"};
  const std::string text(reinterpret_cast<const char*>(data) + 2, size - 2);
  ensure_session();
  switch(data[0] % 5)
  {
  case 0:   // a POST body
  {
    const std::string path = paths[data[1] % 8];
    check_reply(server->post(path, with_session(text)), path);
    break;
  }
  case 1:   // a GET query: k=v&k=v
  {
    std::map<std::string, std::string> params;
    const std::string query = lines(with_session(text), 1)[0];
    for(std::size_t start = 0; start < query.size();)
    {
      const std::size_t end = std::min(query.find('&', start), query.size());
      const std::string kv = query.substr(start, end - start);
      const std::size_t eq = kv.find('=');
      params[kv.substr(0, eq)] = eq == std::string::npos ? std::string() : kv.substr(eq + 1);
      start = end + 1;
    }
    const std::string path = data[1] % 2 ? "/api/download" : "/api/meshes";
    check_reply(server->get(path, params), path);
    break;
  }
  case 2:   // a static URL
  {
    const std::optional<fs::path> file = static_file(server->options().viewer_dir, text);
    if(file)
    {
      const std::string inside = fs::canonical(server->options().viewer_dir).string() + "/";
      check(file->string().compare(0, inside.size(), inside) == 0, "a static file stays in the viewer folder", file->string());
    }
    const Reply r = get_static(server->options().viewer_dir, text, data[1] % 2 ? "\"x\"" : "");
    check(r.status == 200 || r.status == 404, "static: 200 or 404", text);
    break;
  }
  case 3:   // the guard: method, path, host, origin, content type, token header, token query
  {
    const std::vector<std::string> l = lines(text, 6);
    Request_facts f;
    f.method = data[1] % 2 ? "POST" : "GET";
    f.path = l[0];
    f.host = l[1];
    f.has_origin = !l[2].empty();
    f.origin = l[2];
    f.content_type = l[3];
    f.token_header = l[4] == "$T" ? token : l[4];
    f.token_query = l[5] == "$T" ? token : l[5];
    const std::optional<Reply> refused = refusal(f, port, token);
    if(!refused)
    {
      const std::string host = internal::lower(f.host);
      check(host == "127.0.0.1:8123" || host == "localhost:8123", "allowed only with a loopback Host", f.host);
      if(f.path.rfind("/api/", 0) == 0)
        check(f.token_header == token || (f.method == "GET" && f.token_query == token), "API only with the token");
    }
    else
      check(refused->status >= 400 && json::parse(refused->body).contains("error"), "a refusal carries a message");
    break;
  }
  default:   // a binary frame
  {
    json header;
    std::vector<float> xyz;
    if(decode_frame(text, header, xyz))
      check(header.is_object() && text.size() >= 4 + 4 * xyz.size(), "a decoded frame fits its bytes");
    break;
  }
  }
  return 0;
}
