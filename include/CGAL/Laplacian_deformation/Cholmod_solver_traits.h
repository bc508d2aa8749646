// Copyright (c) 2026 Laplacian_deformation contributors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
// Author(s): Laplacian_deformation team

#ifndef CGAL_LAPLACIAN_DEFORMATION_CHOLMOD_SOLVER_TRAITS_H
#define CGAL_LAPLACIAN_DEFORMATION_CHOLMOD_SOLVER_TRAITS_H

// Needs SuiteSparse's CHOLMOD: link the CMake target CGAL::Laplacian_deformation_cholmod.
#include <CGAL/Eigen_solver_traits.h>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

namespace CGAL {
namespace Laplacian_deformation {

/*!
\ingroup PkgLaplacianDeformationSolver
\brief Solver traits for CHOLMOD's supernodal sparse Cholesky (SuiteSparse, through Eigen's
`CholmodSupport`), to be passed as the `SolverTraits` parameter of `Mesh_deformer` or
`Least_squares_solver`.
Include this header only when CHOLMOD is available and link `CGAL::Laplacian_deformation_cholmod`.
*/
typedef CGAL::Eigen_solver_traits<
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower>> Cholmod_solver_traits;

} // namespace Laplacian_deformation
} // namespace CGAL

#endif // CGAL_LAPLACIAN_DEFORMATION_CHOLMOD_SOLVER_TRAITS_H
