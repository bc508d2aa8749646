// libFuzzer target: Mesh_deformer driven by a small mesh, a selection and targets, all built
// from the fuzzer's bytes (grid size and shape, jitter, collapsed points, dropped faces, quads,
// scale from 1e-30 to 1e30, ROI, controls, targets (NaN and inf included), hard or soft
// constraints and their weight, iterations, tolerance, then a sequence of operations).
// Properties checked after every call: no crash, no sanitizer finding, no CGAL assertion;
// a failed preprocess() / deform() gives a reason and leaves every coordinate bitwise unchanged;
// a successful call writes only finite coordinates; the connectivity never changes.
#include <CGAL/Laplacian_deformation.h>

#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

namespace LD = CGAL::Laplacian_deformation;
typedef CGAL::Simple_cartesian<double> Kernel;
typedef Kernel::Point_3 Point_3;
typedef CGAL::Surface_mesh<Point_3> Mesh;
typedef boost::graph_traits<Mesh>::vertex_descriptor vertex_descriptor;

namespace {

void check(bool condition, const char* what)
{
  if(!condition)
  {
    std::fprintf(stderr, "property violated: %s\n", what);
    std::abort();
  }
}

// reads the input a byte at a time; zeros once exhausted
struct Bytes
{
  const std::uint8_t* data;
  std::size_t size, at = 0;
  std::uint8_t next() { return at < size ? data[at++] : 0; }
  double unit() { return next() / 255.; }                 // [0, 1]
  double signed_unit() { return 2 * unit() - 1; }         // [-1, 1]
  // a coordinate offset; rarely NaN or inf
  double offset(double amplitude)
  {
    const std::uint8_t b = next();
    if(b == 255) return std::numeric_limits<double>::quiet_NaN();
    if(b == 254) return std::numeric_limits<double>::infinity();
    if(b == 253) return -std::numeric_limits<double>::infinity();
    return amplitude * (b / 126. - 1.);
  }
};

// coordinates and connectivity, for bitwise comparison
struct Snapshot
{
  std::vector<std::uint64_t> bits;
  std::size_t vertices = 0, edges = 0, faces = 0;
  explicit Snapshot(const Mesh& m) : vertices(num_vertices(m)), edges(num_edges(m)), faces(num_faces(m))
  {
    for(vertex_descriptor v : m.vertices())
      for(int c = 0; c < 3; ++c)
      {
        const double x = m.point(v)[c];
        std::uint64_t b;
        std::memcpy(&b, &x, sizeof b);
        bits.push_back(b);
      }
  }
  bool operator==(const Snapshot& o) const
  {
    return bits == o.bits && vertices == o.vertices && edges == o.edges && faces == o.faces;
  }
};

bool all_finite(const Mesh& m)
{
  for(vertex_descriptor v : m.vertices())
    if(!std::isfinite(m.point(v).x()) || !std::isfinite(m.point(v).y()) || !std::isfinite(m.point(v).z()))
      return false;
  return true;
}

// a (nx+1) x (ny+1) grid, bent, jittered, scaled; some faces dropped, some points collapsed
bool build_mesh(Bytes& in, Mesh& mesh)
{
  const int nx = 1 + in.next() % 5, ny = 1 + in.next() % 5;
  const std::uint8_t shape = in.next();
  const double jitter = (shape >> 4) / 15.;                       // up to a whole cell
  const double scale = std::pow(10., int(in.next() % 61) - 30);   // 1e-30 .. 1e30
  const bool quads = (shape & 8) != 0 && in.next() % 4 == 0;
  std::vector<Point_3> points;
  for(int j = 0; j <= ny; ++j)
    for(int i = 0; i <= nx; ++i)
    {
      double x = i + jitter * in.signed_unit(), y = j + jitter * in.signed_unit(), z = 0;
      if(shape % 4 == 1)
        z = 0.3 * (i - nx / 2.) * (j - ny / 2.);               // saddle
      else if(shape % 4 == 2)
      {                                                       // half a tube
        const double a = 3.14159265358979 * i / nx;
        x = std::cos(a) * nx / 2;
        z = std::sin(a) * nx / 2;
      }
      else if(shape % 4 == 3)
        z = in.signed_unit();
      points.emplace_back(scale * x, scale * y, scale * z);
    }
  // collapse a few points onto their right neighbour (duplicate points, zero-area triangles)
  for(std::uint8_t k = 0, n = in.next() % 4; k < n; ++k)
  {
    const std::size_t i = in.next() % (points.size() - 1);
    points[i] = points[i + 1];
  }
  std::vector<std::vector<std::size_t>> faces;
  const std::uint8_t drop = in.next();
  std::size_t cell = 0;
  for(int j = 0; j < ny; ++j)
    for(int i = 0; i < nx; ++i, ++cell)
    {
      if(drop != 0 && (drop >> (cell % 8) & 1) && (cell % 3 == 0))
        continue;                                             // holes, isolated vertices
      const std::size_t a = std::size_t(j * (nx + 1) + i), b = a + 1, c = a + std::size_t(nx) + 2, d = c - 1;
      if(quads)
        faces.push_back({a, b, c, d});
      else
      {
        faces.push_back({a, b, c});
        faces.push_back({a, c, d});
      }
    }
  if(faces.empty())
    return false;
  CGAL::Polygon_mesh_processing::orient_polygon_soup(points, faces);   // may duplicate points
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, faces, mesh);
  return num_faces(mesh) > 0;
}

template <class Deformer>
void run(Bytes& in, Mesh& mesh)
{
  Deformer deformer(mesh);
  std::vector<vertex_descriptor> vs(mesh.vertices().begin(), mesh.vertices().end());
  const double scale = [&] {
    double s = 0;
    for(vertex_descriptor v : vs)
      s = (std::max)(s, std::abs(mesh.point(v).x()) + std::abs(mesh.point(v).y()));
    return s > 0 && std::isfinite(s) ? s : 1.;
  }();
  for(vertex_descriptor v : vs)
  {
    const std::uint8_t b = in.next();
    if(b % 3 == 1)
      deformer.insert_roi_vertex(v);
    else if(b % 3 == 2)
    {
      deformer.insert_control_vertex(v);
      const Point_3 p = mesh.point(v);
      deformer.set_target_position(v, Point_3(p.x() + in.offset(scale), p.y() + in.offset(scale), p.z() + in.offset(scale)));
    }
  }
  const std::uint8_t mode = in.next();
  if(mode % 2)
  {
    const double weights[] = {1., 1e-3, 1e3, 0., -1., std::numeric_limits<double>::quiet_NaN(),
                              std::numeric_limits<double>::infinity(), 1e-300};
    deformer.set_soft_constraints(weights[(mode >> 1) % 8]);
  }
  for(int step = 0, steps = 1 + in.next() % 6; step < steps; ++step)
  {
    const std::uint8_t op = in.next();
    const Snapshot before(mesh);
    const bool was_finite = all_finite(mesh);
    bool ok = true, wrote = true;
    switch(op % 8)
    {
    case 0: case 1: case 2:
    {
      const double tolerances[] = {0., 1e-4, -1., std::numeric_limits<double>::quiet_NaN()};
      ok = bool(deformer.deform(in.next() % 8, tolerances[op / 8 % 4]));
      break;
    }
    case 3:
      ok = deformer.preprocess();
      break;
    case 4:                                                   // move a control's target
    {
      const vertex_descriptor v = vs[in.next() % vs.size()];
      deformer.translate(v, std::array<double, 3>{{in.offset(scale), in.offset(scale), in.offset(scale)}});
      wrote = false;
      break;
    }
    case 5:                                                   // change the selection
    {
      const vertex_descriptor v = vs[in.next() % vs.size()];
      if(op & 8) deformer.erase_roi_vertex(v);
      else if(op & 16) deformer.insert_control_vertex(v);
      else if(op & 32) deformer.erase_control_vertex(v);
      else deformer.insert_roi_vertex(v);
      wrote = false;
      break;
    }
    case 6:
      if(op & 8) deformer.set_hard_constraints();
      else deformer.reset();
      wrote = (op & 8) == 0;
      break;
    case 7:
      ok = deformer.start_from_current_positions();
      break;
    }
    const Snapshot after(mesh);
    check(after.vertices == before.vertices && after.edges == before.edges && after.faces == before.faces,
          "the connectivity changed");
    if(!ok)
    {
      check(after == before, "a failed call changed the mesh");
      check(!deformer.last_result().message.empty(), "a failure without a reason");
    }
    if(!wrote)
      check(after == before, "a selection or target change moved the mesh");
    if(was_finite)
      check(all_finite(mesh), "a non-finite coordinate was written");
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  Bytes in{data, size};
  Mesh mesh;
  if(!build_mesh(in, mesh))
    return 0;
  const std::uint8_t policies = in.next();
  switch(policies % 5)
  {
  case 0:
    run<LD::Mesh_deformer<Mesh, LD::Edge_based_representation, LD::Cotangent_weights, CGAL::Default,
                          CGAL::Default, CGAL::Default, CGAL::Sequential_tag>>(in, mesh);
    break;
  case 1:
    run<LD::Mesh_deformer<Mesh, LD::Edge_based_representation, LD::Uniform_weights, CGAL::Default,
                          CGAL::Default, CGAL::Default, CGAL::Sequential_tag>>(in, mesh);
    break;
  case 2:
    run<LD::Mesh_deformer<Mesh, LD::Vertex_based_representation, LD::Cotangent_weights, CGAL::Default,
                          CGAL::Default, CGAL::Default, CGAL::Sequential_tag>>(in, mesh);
    break;
  case 3:
    run<LD::Mesh_deformer<Mesh, LD::Vertex_based_representation, LD::Uniform_weights, LD::Rotation_transform,
                          CGAL::Default, CGAL::Default, CGAL::Sequential_tag>>(in, mesh);
    break;
  case 4:
    run<LD::Mesh_deformer<Mesh, LD::Edge_based_representation, LD::Cotangent_weights, LD::Similarity_transform,
                          CGAL::Default, CGAL::Default, CGAL::Sequential_tag>>(in, mesh);
    break;
  }
  return 0;
}
