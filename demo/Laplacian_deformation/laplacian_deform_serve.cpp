// laplacian_deform --serve [MESH] [--port N] [--output DIR] [--viewer DIR]: the browser editor
// (deformation_server.h), in its own translation unit (its two deformer instantiations, one per
// representation, with run-time weights and transforms).
#include "deformation_server.h"

int laplacian_deform_serve(int argc, char** argv)
{
  return Laplacian_deformation_server::serve_main(argc, argv, LAPLACIAN_DEFORMATION_DATA_DIR);
}
