// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team
//
// Internal header of the laplacian_deform tool: one deformation of a task with policies chosen
// at run time (laplacian_deform_run.cpp).

#ifndef LAPLACIAN_DEFORM_RUN_H
#define LAPLACIAN_DEFORM_RUN_H

#include "laplacian_deform_cli.h"

namespace laplacian_deform {

/// Deforms `task` into `run.mesh` with the policies named in `run` (set its representation,
/// weights, transform and solver first; the names of policy_names.h), and measures the result.
void run_deformation(const Task& task, const Options& o, Run_record& run, Progress& progress);

} // namespace laplacian_deform

#endif // LAPLACIAN_DEFORM_RUN_H
