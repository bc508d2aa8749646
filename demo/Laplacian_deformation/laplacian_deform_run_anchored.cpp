// laplacian_deform: every policy combination with CGAL::Laplacian_deformation::Scaled_rotation_transform
// (one translation unit per transform policy, see laplacian_deform_run.h).
#include "laplacian_deform_run.h"

namespace laplacian_deform {
LAPLACIAN_DEFORM_INSTANTIATE(LD::Anchored_scaled_rotation_transform)
} // namespace laplacian_deform
