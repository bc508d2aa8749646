// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// Internal header of the laplacian_deform command-line tool (not part of the package's API): the
// command-line parser (the policy names of policy_names.h, the options of cli_options.h).

#ifndef LAPLACIAN_DEFORM_CLI_PARSE_H
#define LAPLACIAN_DEFORM_CLI_PARSE_H

#include "cli_options.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <iterator>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace laplacian_deform {

namespace detail {

inline bool parse_double(const std::string& text, double& value)
{
  if(text.empty())
    return false;
  std::size_t used = 0;
  try { value = std::stod(text, &used); } catch(...) { return false; }
  return used == text.size() && std::isfinite(value);
}

inline bool parse_unsigned(const std::string& text, unsigned long long& value)
{
  if(text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
    return false;
  try { value = std::stoull(text); } catch(...) { return false; }
  return true;
}

inline std::vector<std::string> split(const std::string& text, char separator)
{
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while(std::getline(in, part, separator))
    parts.push_back(part);
  if(!text.empty() && text.back() == separator)
    parts.push_back("");
  return parts;
}

inline bool parse_doubles(const std::string& text, std::vector<double>& values)
{
  values.clear();
  for(const std::string& part : split(text, ','))
  {
    double x;
    if(!parse_double(part, x))
      return false;
    values.push_back(x);
  }
  return true;
}

// "12,40-45,300" as the ranges [12, 12], [40, 45], [300, 300] (not expanded: a range is checked
// against the mesh's vertex count before it costs any memory)
inline bool parse_ids(const std::string& text, std::vector<std::pair<std::size_t, std::size_t>>& ranges)
{
  for(const std::string& part : split(text, ','))
  {
    const std::size_t dash = part.find('-');
    unsigned long long a, b;
    if(dash == std::string::npos)
    {
      if(!parse_unsigned(part, a))
        return false;
      b = a;
    }
    else if(!parse_unsigned(part.substr(0, dash), a) || !parse_unsigned(part.substr(dash + 1), b) || b < a)
      return false;
    ranges.emplace_back(std::size_t(a), std::size_t(b));
  }
  return true;
}

inline bool one_of(const std::string& value, std::initializer_list<const char*> choices)
{
  for(const char* c : choices)
    if(value == c)
      return true;
  return false;
}

} // namespace detail

/// Parses the arguments (without the program name). Returns `false` with a message in `error`
/// on a bad command line; checks only the command line, no file is opened.
inline bool parse_command_line(const std::vector<std::string>& args, Options& o, std::string& error)
{
  std::vector<std::string> positional;
  bool options_done = false;
  for(std::size_t i = 0; i < args.size(); ++i)
  {
    std::string arg = args[i];
    if(options_done || arg.empty() || arg[0] != '-' || arg == "-")
    {
      positional.push_back(arg);
      continue;
    }
    if(arg == "--")
    {
      options_done = true;
      continue;
    }
    std::string value;
    bool has_inline_value = false;
    if(arg.compare(0, 2, "--") == 0)
    {
      const std::size_t eq = arg.find('=');
      if(eq != std::string::npos)
      {
        value = arg.substr(eq + 1);
        arg = arg.substr(0, eq);
        has_inline_value = true;
      }
    }
    if(arg == "-o")
      arg = "--output";
    if(arg == "-h")
      arg = "--help";

    static const char* const flags[] = {"--help", "--force", "--triangulate", "--compare", "--quiet"};
    static const char* const valued[] = {"--output", "--output-dir", "--report", "--representation", "--weights",
                                         "--transform", "--start", "--rigidity", "--solver", "--iterations", "--tolerance", "--soft",
                                         "--threads", "--handle", "--roi-rings", "--roi-radius", "--translate",
                                         "--rotate", "--progress"};
    const bool is_flag = std::find_if(std::begin(flags), std::end(flags),
                                      [&](const char* f) { return arg == f; }) != std::end(flags);
    const bool is_valued = std::find_if(std::begin(valued), std::end(valued),
                                        [&](const char* f) { return arg == f; }) != std::end(valued);
    if(!is_flag && !is_valued)
    {
      error = "unknown option '" + args[i] + "' (see --help)";
      return false;
    }
    if(std::find(o.given.begin(), o.given.end(), arg) != o.given.end() && arg != "--handle")
    {
      error = "option " + arg + " is given twice";
      return false;
    }
    o.given.push_back(arg);
    if(is_flag)
    {
      if(has_inline_value)
      {
        error = "option " + arg + " takes no value";
        return false;
      }
      if(arg == "--help") o.help = true;
      else if(arg == "--force") o.force = true;
      else if(arg == "--triangulate") o.triangulate = true;
      else if(arg == "--compare") o.compare = true;
      else if(arg == "--quiet") o.quiet = true;
      continue;
    }
    if(!has_inline_value)
    {
      if(i + 1 >= args.size())
      {
        error = "option " + arg + " needs a value (see --help)";
        return false;
      }
      value = args[++i];
    }
    auto bad = [&](const std::string& expected) {
      error = "option " + arg + ": expected " + expected + ", got '" + value + "'";
      return false;
    };
    unsigned long long n = 0;
    double x = 0;
    std::vector<double> xs;
    if(arg == "--output") { if(value.empty()) return bad("a file name"); o.output = value; }
    else if(arg == "--output-dir") { if(value.empty()) return bad("a folder"); o.output_dir = value; }
    else if(arg == "--report") { if(value.empty()) return bad("a file name"); o.report = value; }
    else if(arg == "--representation")   // the names of policy_names.h, kept canonical
    {
      const auto* e = policy_names::find(policy_names::representations(), value);
      if(e == nullptr)
        return bad(policy_names::name_list(policy_names::representations()));
      o.representation = e->name;
    }
    else if(arg == "--weights")
    {
      const auto* e = policy_names::find(policy_names::weight_policies(), value);
      if(e == nullptr)
        return bad(policy_names::name_list(policy_names::weight_policies()));
      o.weights = e->name;
    }
    else if(arg == "--transform")
    {
      const auto* e = policy_names::find(policy_names::transform_policies(), value);
      if(e == nullptr)
        return bad(policy_names::name_list(policy_names::transform_policies()));
      o.transform = e->name;
    }
    else if(arg == "--start")
    {
      if(!detail::one_of(value, {"rotation", "identity"}))
      {
        return bad("rotation or identity");
      }
      o.start = value;
    }
    else if(arg == "--solver")
    {
      if(!detail::one_of(value, {"eigen", "cholmod"}))
      {
        return bad("eigen or cholmod");
      }
      o.solver = value;
    }
    else if(arg == "--progress")
    {
      if(!detail::one_of(value, {"auto", "always", "never"}))
      {
        return bad("auto, always or never");
      }
      o.progress = value;
    }
    else if(arg == "--iterations")
    {
      if(!detail::parse_unsigned(value, n) || n == 0 || n > 1000000)
      {
        return bad("a positive integer");
      }
      o.iterations = static_cast<unsigned int>(n);
    }
    else if(arg == "--threads")
    {
      if(!detail::parse_unsigned(value, n) || n == 0 || n > 4096)
      {
        return bad("a positive integer");
      }
      o.threads = static_cast<unsigned int>(n);
    }
    else if(arg == "--roi-rings")
    {
      if(!detail::parse_unsigned(value, n) || n > 1000000000)
      {
        return bad("a non-negative integer");
      }
      o.roi_rings = long(n);
    }
    else if(arg == "--tolerance")
    { if(!detail::parse_double(value, x) || x < 0) return bad("a non-negative number"); o.tolerance = x; }
    else if(arg == "--rigidity")
    {
      if(!detail::parse_double(value, x) || !(x >= 0) || !std::isfinite(x))
      {
        return bad("a non-negative finite number");
      }
      o.rigidity = x;
    }
    else if(arg == "--soft")
    { if(!detail::parse_double(value, x) || !(x > 0)) return bad("a positive number"); o.soft = true; o.soft_weight = x; }
    else if(arg == "--roi-radius")
    { if(!detail::parse_double(value, x) || !(x > 0)) return bad("a positive distance"); o.roi_radius = x; }
    else if(arg == "--handle")
    { if(!detail::parse_ids(value, o.handles)) return bad("vertex ids and ranges such as 12,40-45,300"); }
    else if(arg == "--translate")
    {
      if(!detail::parse_doubles(value, xs) || xs.size() != 3) return bad("three numbers X,Y,Z");
      o.has_translate = true;
      o.translate = {{xs[0], xs[1], xs[2]}};
    }
    else if(arg == "--rotate")
    {
      if(!detail::parse_doubles(value, xs) || (xs.size() != 4 && xs.size() != 7))
        return bad("AX,AY,AZ,DEGREES or AX,AY,AZ,DEGREES,CX,CY,CZ");
      if(xs[0] == 0 && xs[1] == 0 && xs[2] == 0)
        return bad("a non-zero rotation axis");
      o.has_rotate = true;
      o.axis = {{xs[0], xs[1], xs[2]}};
      o.angle_degrees = xs[3];
      o.has_center = xs.size() == 7;
      if(o.has_center)
        o.center = {{xs[4], xs[5], xs[6]}};
    }
  }
  if(o.help)
    return true;

  if(positional.size() > 3)
  {
    error = "too many arguments: '" + positional[3] + "' (expected MESH [SEL [DEF]])";
    return false;
  }
  if(positional.size() > 0) o.mesh = positional[0];
  if(positional.size() > 1) o.selection = positional[1];
  if(positional.size() > 2) o.transform_file = positional[2];

  auto given = [&](const char* name) { return std::find(o.given.begin(), o.given.end(), name) != o.given.end(); };
  auto conflict = [&](const std::string& message) { error = message; return false; };
  const bool cli_selection = given("--handle") || given("--roi-rings") || given("--roi-radius");
  const bool cli_motion = o.has_translate || o.has_rotate;
  if(o.main_job())
  {
    if(cli_selection || cli_motion)
      return conflict("--handle, --roi-*, --translate and --rotate need a MESH");
    if(given("--triangulate"))
      return conflict("--triangulate needs a MESH (the default task is CGAL's cactus)");
  }
  if(o.comparing())
  {
    if(given("--representation"))
      return conflict(o.main_job() ? "without MESH the tool compares both representations: --representation does not apply"
                                   : "--compare runs both representations: --representation does not apply");
    if(given("--output"))
      return conflict(o.main_job() ? "without MESH the tool writes a comparison: use --output-dir DIR, not --output"
                                   : "--compare writes a folder: use --output-dir DIR, not --output");
  }
  else if(given("--output-dir"))
    return conflict("--output-dir applies to --compare (and to the default task); use --output FILE");
  if(!o.main_job())
  {
    if(!o.transform_file.empty() && cli_motion)
      return conflict("the handle transformation comes from " + o.transform_file + ": do not also give --translate or --rotate");
    if(!o.selection.empty() && cli_selection)
      return conflict("the selection comes from " + o.selection + ": do not also give --handle or --roi-*");
    if(o.selection.empty())
    {
      if(o.handles.empty())
        return conflict("no handle: give a selection file (MESH SEL DEF) or --handle IDS with --roi-rings K or --roi-radius R");
      if(given("--roi-rings") == given("--roi-radius"))
        return conflict("give the region of interest around the handles: one of --roi-rings K or --roi-radius R");
    }
    if(!o.selection.empty() && o.transform_file.empty() && !cli_motion)
      return conflict("no handle motion: give DEF (MESH SEL DEF) or --translate / --rotate");
  }
  return true;
}

} // namespace laplacian_deform

#endif // LAPLACIAN_DEFORM_CLI_PARSE_H
