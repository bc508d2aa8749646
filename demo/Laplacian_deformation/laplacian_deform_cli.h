// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// Internal header of the laplacian_deform command-line tool (not part of the package's API), shared
// by the tool and its GoogleTest suite: every part of the tool, by concern.
//   cli_options.h   the tool's types, its options (with the defaults of tool_defaults.h), the help
//   cli_parse.h     the command-line parser (the policy names of policy_names.h)
//   cli_task.h      the task: mesh, selection, handle motion; the checks of the outputs
//   cli_report.h    the progress indicator, the per-run records and their measures
// on the tools' shared layer: tool_mesh_io.h (the checked reader, the mesh writer), tool_files.h
// (atomic writes), tool_regions.h (k-ring and geodesic regions), tool_defaults.h.

#ifndef LAPLACIAN_DEFORM_CLI_H
#define LAPLACIAN_DEFORM_CLI_H

#include "cli_options.h"
#include "cli_parse.h"
#include "cli_task.h"
#include "cli_report.h"

#endif // LAPLACIAN_DEFORM_CLI_H
