// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_H
#define CGAL_LAPLACIAN_DEFORMATION_H

/// \file Laplacian_deformation.h
/// Includes every public header of the package (but `Cholmod_solver_traits.h`, which needs CHOLMOD).

#include <CGAL/Laplacian_deformation/Edge_midpoint_graph.h>
#include <CGAL/Laplacian_deformation/Vertex_based_representation.h>
#include <CGAL/Laplacian_deformation/Edge_based_representation.h>
#include <CGAL/Laplacian_deformation/Uniform_weights.h>
#include <CGAL/Laplacian_deformation/Cotangent_weights.h>
#include <CGAL/Laplacian_deformation/Fixed_transform.h>
#include <CGAL/Laplacian_deformation/Rotation_transform.h>
#include <CGAL/Laplacian_deformation/Similarity_transform.h>
#include <CGAL/Laplacian_deformation/Scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Principal_scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Rotation_scale_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Anchored_scaled_rotation_transform.h>
#include <CGAL/Laplacian_deformation/Any_weights.h>
#include <CGAL/Laplacian_deformation/Any_transform.h>
#include <CGAL/Laplacian_deformation/Least_squares_solver.h>
#include <CGAL/Laplacian_deformation/laplacian_matrix.h>
#include <CGAL/Laplacian_deformation/Deformation_start.h>
#include <CGAL/Laplacian_deformation/Mesh_deformer.h>
#include <CGAL/Laplacian_deformation/deform_mesh.h>
#include <CGAL/Laplacian_deformation/metrics.h>
#include <CGAL/Laplacian_deformation/IO/read_triangle_mesh.h>
#include <CGAL/Laplacian_deformation/IO/Botsch08.h>

#endif // CGAL_LAPLACIAN_DEFORMATION_H
