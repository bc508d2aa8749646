// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// The tools' one atomic writer (not part of the package's API): every file the tools write (the
// laplacian_deform results, summaries and reports, the editor's saved tasks, the harness's tables,
// the viewer's figure folders) goes through a temporary file in the same folder, then a rename, so
// that a reader never sees a half-written file and a failure leaves no output.

#ifndef LAPLACIAN_DEFORMATION_TOOL_FILES_H
#define LAPLACIAN_DEFORMATION_TOOL_FILES_H

#include <atomic>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <system_error>

#include <unistd.h>

namespace Laplacian_deformation_tools {

namespace fs = std::filesystem;

/// `p` between single quotes, as the tools' messages name files
inline std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

/// the temporary file `write_atomically()` writes before renaming it to `path`: in the same folder,
/// hidden, unique to the process and to the call (two threads of the editor's server writing the
/// same file never share one)
inline fs::path temporary_path(const fs::path& path)
{
  static std::atomic<unsigned long> counter{0};
  return path.parent_path() / (".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++) + "." +
                               path.filename().string());
}

/// Writes through a temporary file in the same folder, then renames it to `path`: a reader never
/// sees a half-written file and a failure leaves no output (nor the temporary file).
/// `write(tmp)` writes the temporary file and returns whether it succeeded. Returns `false` with
/// a message naming `path` in `error` otherwise.
inline bool write_atomically(const fs::path& path, const std::function<bool(const fs::path&)>& write,
                             std::string& error)
{
  const fs::path tmp = temporary_path(path);
  std::error_code ec;
  bool written = false;
  try { written = write(tmp); } catch(...) { written = false; }
  if(!written)
  {
    fs::remove(tmp, ec);
    return error = "cannot write " + quoted(path), false;
  }
  fs::rename(tmp, path, ec);
  if(ec)
  {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    return error = "cannot rename the temporary file to " + quoted(path) + ": " + ec.message(), false;
  }
  return true;
}

/// writes `text` to `path` atomically (as bytes: no newline conversion)
inline bool write_text_atomically(const fs::path& path, const std::string& text, std::string& error)
{
  return write_atomically(path, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    out.close();
    return bool(out);
  }, error);
}

} // namespace Laplacian_deformation_tools

#endif // LAPLACIAN_DEFORMATION_TOOL_FILES_H
