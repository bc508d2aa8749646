// laplacian_deform: every policy combination with CGAL::Laplacian_deformation::Fixed_transform
// (one translation unit per transform policy, see laplacian_deform_run.h).
#include "laplacian_deform_run.h"

namespace laplacian_deform {
LAPLACIAN_DEFORM_INSTANTIATE(LD::Fixed_transform)
} // namespace laplacian_deform
