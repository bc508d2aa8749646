// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_IO_BOTSCH08_H
#define CGAL_LAPLACIAN_DEFORMATION_IO_BOTSCH08_H

#include <Eigen/Core>
#include <Eigen/LU>

#include <cmath>
#include <cstddef>
#include <istream>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

namespace CGAL {
namespace Laplacian_deformation {
namespace IO {

/*!
\ingroup PkgLaplacianDeformationIO
\brief The status of a vertex in a Botsch08 `.sel` file.
*/
enum Botsch08_status { BOTSCH08_FIXED = 0, BOTSCH08_REGION_OF_INTEREST = 1, BOTSCH08_HANDLE = 2 };

namespace internal {

// `text` between single quotes, safe to print: bytes below 0x20 or above 0x7e as \xNN, a quote or
// a backslash escaped; only the first `max_length` bytes, then "..." and the length
inline std::string quoted_excerpt(const std::string& text, std::size_t max_length = 40)
{
  static const char hex[] = "0123456789abcdef";
  std::string q = "'";
  for(std::size_t i = 0; i < text.size() && i < max_length; ++i)
  {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if(c == '\'' || c == '\\')
      q += '\\', q += char(c);
    else if(c < 0x20 || c > 0x7e)
      q += "\\x", q += hex[c >> 4], q += hex[c & 15];
    else
      q += char(c);
  }
  q += '\'';
  if(text.size() > max_length)
    q += "... (" + std::to_string(text.size()) + " bytes)";
  return q;
}

} // namespace internal

/*!
\ingroup PkgLaplacianDeformationIO
\brief reads a Botsch08 selection (`.sel`, the format of CGAL's
`deform_mesh_for_botsch08_format` example): one status per vertex, in the mesh's vertex order,
`0` fixed, `1` region of interest, `2` handle; lines starting with `#` are comments.

Returns `false` and explains in `error` (with the line number and the offending line, quoted with
non-printable bytes escaped as `\xNN` and cut after 40 bytes) if a line holds anything but one
of `0`, `1`, `2`, or if `expected_count` (when not `0`) differs from the number of statuses;
`status` is then left unchanged.
*/
inline bool read_botsch08_selection(std::istream& in, std::vector<int>& status_out, std::string& error,
                                    std::size_t expected_count = 0)
{
  std::vector<int> status;
  std::string line;
  for(std::size_t number = 1; std::getline(in, line); ++number)
  {
    std::istringstream tokens(line);
    std::string token, extra;
    if(!(tokens >> token) || token[0] == '#')
      continue;
    if((token != "0" && token != "1" && token != "2") || (tokens >> extra))
    {
      error = "line " + std::to_string(number) + ": expected one status 0, 1 or 2, got " + internal::quoted_excerpt(line);
      return false;
    }
    status.push_back(token[0] - '0');
  }
  if(expected_count != 0 && status.size() != expected_count)
  {
    error = "the selection has " + std::to_string(status.size()) + " statuses but the mesh has " +
            std::to_string(expected_count) + " vertices";
    return false;
  }
  status_out.swap(status);
  return true;
}

/*!
\ingroup PkgLaplacianDeformationIO
\brief reads a Botsch08 handle transformation (`.def`): after optional `#` comment lines,
sixteen finite numbers, the 4x4 matrix row by row, whose last row must be `0 0 0 1`
(an affine map) and whose linear part (the upper-left 3x3 block) must be invertible: its
determinant, once the block is divided by its root-mean-square column length, must exceed `1e-12`.
Returns `false` and explains in `error` otherwise (an offending token is quoted like the lines of
`read_botsch08_selection()`); `transform` is then left unchanged.
*/
inline bool read_botsch08_transform(std::istream& in, Eigen::Matrix4d& transform_out, std::string& error)
{
  Eigen::Matrix4d transform;
  std::string line, text;
  while(std::getline(in, line))
  {
    const std::size_t first = line.find_first_not_of(" \t\r");
    if(first != std::string::npos && line[first] != '#')
      text += line + '\n';
  }
  std::istringstream numbers(text);
  std::string token;
  for(int k = 0; k < 16; ++k)
  {
    if(!(numbers >> token))
    {
      error = "expected 16 numbers (a 4x4 matrix), got " + std::to_string(k);
      return false;
    }
    std::size_t used = 0;
    double value = 0;
    try { value = std::stod(token, &used); } catch(...) { used = 0; }
    if(used != token.size() || !std::isfinite(value))
    {
      error = "entry " + std::to_string(k + 1) + " of the matrix is not a finite number: " + internal::quoted_excerpt(token);
      return false;
    }
    transform(k / 4, k % 4) = value;
  }
  if(numbers >> token)
  {
    error = "more than 16 numbers: " + internal::quoted_excerpt(token);
    return false;
  }
  if(transform.row(3) != Eigen::RowVector4d(0, 0, 0, 1))
  {
    error = "the last row of the matrix must be 0 0 0 1";
    return false;
  }
  // the determinant of the block scaled to unit root-mean-square column length; dividing by the
  // largest entry first keeps the norm from overflowing or underflowing
  const double largest = transform.topLeftCorner<3, 3>().cwiseAbs().maxCoeff();
  const Eigen::Matrix3d linear = transform.topLeftCorner<3, 3>() / (largest > 0 ? largest : 1.);
  const double scale = linear.norm() / std::sqrt(3.);
  if(!(largest > 0) || !(std::abs((linear / scale).determinant()) > 1e-12))
  {
    error = "the matrix is singular (its upper-left 3x3 block is not invertible)";
    return false;
  }
  transform_out = transform;
  return true;
}

/*!
\ingroup PkgLaplacianDeformationIO
\brief writes a Botsch08 selection; returns the stream's state.
*/
inline bool write_botsch08_selection(std::ostream& out, const std::vector<int>& status)
{
  out << "# per vertex status: 0=fixed, 1=deformable-region, 2=handle\n# " << status.size() << " vertices\n";
  for(int s : status)
    out << s << '\n';
  return bool(out);
}

/*!
\ingroup PkgLaplacianDeformationIO
\brief writes a Botsch08 handle transformation; returns the stream's state.
*/
inline bool write_botsch08_transform(std::ostream& out, const Eigen::Matrix4d& transform)
{
  out << "# 4x4 handle transformation matrix\n";
  out.precision(17);
  for(int i = 0; i < 4; ++i)
    out << transform(i, 0) << ' ' << transform(i, 1) << ' ' << transform(i, 2) << ' ' << transform(i, 3) << '\n';
  return bool(out);
}

} // namespace IO
} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_IO_BOTSCH08_H
