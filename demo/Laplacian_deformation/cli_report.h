// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// Internal header of the laplacian_deform command-line tool (not part of the package's API): the
// progress indicator, the per-run records and their measures (metrics.h), and the names the
// summary and the report give to statuses, warnings and transforms.

#ifndef LAPLACIAN_DEFORM_CLI_REPORT_H
#define LAPLACIAN_DEFORM_CLI_REPORT_H

#include "cli_task.h"

#include <CGAL/Laplacian_deformation/Deformation_result.h>
#include <CGAL/Laplacian_deformation/metrics.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstddef>
#include <iostream>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

namespace laplacian_deform {

/// Progress on stderr: a stage ("preprocessing", "iteration 2/4") shown once the run is longer
/// than `delay` seconds. On a terminal one line is refreshed with the elapsed time; otherwise
/// one line is printed per stage.
class Progress
{
public:
  Progress(bool enabled, double delay, std::ostream& out = std::cerr)
    : m_enabled(enabled), m_delay(delay), m_out(out), m_tty(enabled && ::isatty(2)),
      m_start(std::chrono::steady_clock::now())
  {
    if(m_enabled)
      m_thread = std::thread([this] { loop(); });
  }
  ~Progress() { stop(); }
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void stage(const std::string& text)
  {
    if(!m_enabled)
      return;
    std::lock_guard<std::mutex> lock(m_mutex);
    m_stage = text;
    m_shown = false;
    if(elapsed() >= m_delay)
      show();
  }
  /// clears the progress line; call before printing anything else
  void stop()
  {
    if(!m_enabled)
      return;
    {
      std::lock_guard<std::mutex> lock(m_mutex);
      m_done = true;
    }
    m_wake.notify_all();
    if(m_thread.joinable())
      m_thread.join();
    std::lock_guard<std::mutex> lock(m_mutex);
    if(m_tty && m_line_open)
      m_out << '\r' << std::string(m_width, ' ') << '\r' << std::flush;
    m_line_open = false;
    m_enabled = false;
  }

private:
  double elapsed() const
  { return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count(); }
  void show()   // with the mutex held
  {
    std::ostringstream line;
    line.setf(std::ios::fixed);
    line.precision(1);
    line << "laplacian_deform: " << m_stage << " (" << elapsed() << " s)";
    if(m_tty)
    {
      std::string text = line.str();
      m_width = (std::max)(m_width, text.size());
      text.resize(m_width, ' ');
      m_out << '\r' << text << std::flush;
      m_line_open = true;
    }
    else if(!m_shown)
      m_out << line.str() << std::endl;
    m_shown = true;
  }
  void loop()
  {
    std::unique_lock<std::mutex> lock(m_mutex);
    while(!m_done)
    {
      m_wake.wait_for(lock, std::chrono::milliseconds(200));
      if(!m_done && !m_stage.empty() && elapsed() >= m_delay && (m_tty || !m_shown))
        show();
    }
  }

  bool m_enabled;
  double m_delay;
  std::ostream& m_out;
  bool m_tty;
  std::chrono::steady_clock::time_point m_start;
  std::mutex m_mutex;
  std::condition_variable m_wake;
  std::thread m_thread;
  std::string m_stage;
  bool m_done = false, m_shown = false, m_line_open = false;
  std::size_t m_width = 0;
};

/// one iteration of a run
struct Iteration_record
{
  double seconds = 0, local_step_seconds = 0, right_hand_side_seconds = 0, solve_seconds = 0;
  double energy = 0, change = 0;
};

/// one deformation of the task with one set of policies
struct Run_record
{
  std::string representation, weights, transform, solver;
  bool ok = false;
  std::string status, message;
  double preprocess_seconds = 0, deform_seconds = 0;
  std::size_t row_nodes = 0, factorizations = 0;
  std::vector<Iteration_record> iterations;
  double energy = 0, last_change = 0, max_constraint_residual = 0, max_handle_distance = 0;
  LD::Deformation_quality quality;     // metrics.h, over the non-fixed vertices
  std::vector<LD::Deformation_warning> warnings;   // of the last deform() call
  Mesh mesh;
  std::string name() const { return representation + "-based"; }
};

/// the quality metrics of metrics.h over the non-fixed vertices (region of interest and handles),
/// and the largest distance between a handle and its target
inline void measure(const Task& task, Run_record& run)
{
  std::vector<vertex_descriptor> region;
  for(vertex_descriptor v : vertices(task.mesh))
    if(task.status[v] != LD::IO::BOTSCH08_FIXED)
      region.push_back(v);
  // run.mesh is a copy of task.mesh: same vertex indices, so the task's points are the rest map
  run.quality = LD::deformation_quality(run.mesh, get(CGAL::vertex_point, task.mesh), region);
  run.max_handle_distance = 0;
  for(vertex_descriptor v : vertices(task.mesh))
    if(task.status[v] == LD::IO::BOTSCH08_HANDLE)
    {
      const Point_3& p = task.mesh.point(v);
      const Eigen::Vector4d t = task.transform * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.);
      run.max_handle_distance = (std::max)(run.max_handle_distance,
                                           std::sqrt(CGAL::squared_distance(run.mesh.point(v), Point_3(t.x(), t.y(), t.z()))));
    }
}

inline const char* status_name(LD::Deformation_status s)
{
  switch(s)
  {
    case LD::SUCCESS: return "SUCCESS";
    case LD::EMPTY_REGION_OF_INTEREST: return "EMPTY_REGION_OF_INTEREST";
    case LD::UNANCHORED_REGION: return "UNANCHORED_REGION";
    case LD::FACTORIZATION_FAILED: return "FACTORIZATION_FAILED";
    case LD::SOLVE_FAILED: return "SOLVE_FAILED";
    case LD::NON_FINITE_INPUT: return "NON_FINITE_INPUT";
    case LD::NON_FINITE_RESULT: return "NON_FINITE_RESULT";
    case LD::INVALID_PARAMETER: return "INVALID_PARAMETER";
    case LD::TOPOLOGY_CHANGED: return "TOPOLOGY_CHANGED";
    case LD::INVALID_MESH: return "INVALID_MESH";
  }
  return "UNKNOWN";
}

inline const char* warning_name(LD::Deformation_warning_kind k) { return LD::warning_kind_name(k); }

inline const char* transform_label(const std::string& t)
{
  const auto* e = policy_names::find(policy_names::transform_policies(), t);
  return e ? e->label : "unknown";
}

} // namespace laplacian_deform

#endif // LAPLACIAN_DEFORM_CLI_REPORT_H
