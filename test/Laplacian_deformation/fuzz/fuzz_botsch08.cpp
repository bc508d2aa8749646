// libFuzzer target: the Botsch08 .sel/.def readers of IO/Botsch08.h.
// The first byte chooses the reader (even: .sel, odd: .def) and, for .sel, the expected
// vertex count (0: any). Properties checked on every input: no crash or sanitizer finding;
// a failed read explains itself (non-empty error); a successful read gives only statuses 0-2
// (.sel) or sixteen finite numbers with last row 0 0 0 1 and an invertible linear part (.def), and survives a write/read
// round trip unchanged.
#include <CGAL/Laplacian_deformation/IO/Botsch08.h>

#include <Eigen/LU>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace IO = CGAL::Laplacian_deformation::IO;

static void check(bool condition, const char* what)
{
  if(!condition)
  {
    std::fprintf(stderr, "property violated: %s\n", what);
    std::abort();
  }
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  if(size == 0)
    return 0;
  const std::uint8_t selector = data[0];
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  std::istringstream in(text);
  std::string error;
  if(selector % 2 == 0)
  {
    std::vector<int> status;
    const std::size_t expected = selector / 2 % 8;          // 0 (any) .. 7
    if(!IO::read_botsch08_selection(in, status, error, expected))
    {
      check(!error.empty(), ".sel failure without an error message");
      return 0;
    }
    check(expected == 0 || status.size() == expected, ".sel count differs from the expected one");
    for(int s : status)
      check(s >= 0 && s <= 2, ".sel status out of 0..2");
    std::stringstream round_trip;
    check(IO::write_botsch08_selection(round_trip, status), ".sel write failed");
    std::vector<int> again;
    check(IO::read_botsch08_selection(round_trip, again, error, status.size()) && again == status,
          ".sel round trip differs");
  }
  else
  {
    Eigen::Matrix4d m;
    if(!IO::read_botsch08_transform(in, m, error))
    {
      check(!error.empty(), ".def failure without an error message");
      return 0;
    }
    check(m.allFinite(), ".def accepted a non-finite entry");
    check(m.row(3) == Eigen::RowVector4d(0, 0, 0, 1), ".def accepted a last row other than 0 0 0 1");
    check(m.topLeftCorner<3, 3>().determinant() != 0, ".def accepted a singular matrix");
    std::stringstream round_trip;
    check(IO::write_botsch08_transform(round_trip, m), ".def write failed");
    Eigen::Matrix4d again;
    check(IO::read_botsch08_transform(round_trip, again, error) && again == m, ".def round trip differs");
  }
  return 0;
}
