# The one detection of SuiteSparse's CHOLMOD, for the build tree (CMakeLists.txt) and for the
# installed package (CGAL_Laplacian_deformationConfig.cmake, next to which this file is installed).
#
#   laplacian_deformation_find_cholmod(<core target> <cholmod target> <use as default> [IMPORTED])
#
# When CHOLMOD and suitesparseconfig are found: creates <cholmod target> (an interface target, or an
# imported one with IMPORTED) that links <core target> and CHOLMOD and defines
# CGAL_LAPLACIAN_DEFORMATION_HAS_CHOLMOD (Cholmod_solver_traits.h can be used); with <use as
# default> ON, also gives <core target> CHOLMOD and CGAL_LAPLACIAN_DEFORMATION_USE_CHOLMOD (CHOLMOD
# is Default_solver_traits). Sets LAPLACIAN_DEFORMATION_HAS_CHOLMOD (ON/OFF) in the caller's scope.
function(laplacian_deformation_find_cholmod core cholmod use_default)
  find_path(LAPLACIAN_DEFORMATION_CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
  find_library(LAPLACIAN_DEFORMATION_CHOLMOD_LIBRARY cholmod)
  find_library(LAPLACIAN_DEFORMATION_SUITESPARSE_CONFIG_LIBRARY suitesparseconfig)
  if(NOT (LAPLACIAN_DEFORMATION_CHOLMOD_INCLUDE_DIR AND LAPLACIAN_DEFORMATION_CHOLMOD_LIBRARY AND
          LAPLACIAN_DEFORMATION_SUITESPARSE_CONFIG_LIBRARY))
    set(LAPLACIAN_DEFORMATION_HAS_CHOLMOD OFF PARENT_SCOPE)
    return()
  endif()
  set(include_dir ${LAPLACIAN_DEFORMATION_CHOLMOD_INCLUDE_DIR})
  set(libraries ${LAPLACIAN_DEFORMATION_CHOLMOD_LIBRARY} ${LAPLACIAN_DEFORMATION_SUITESPARSE_CONFIG_LIBRARY})
  if("${ARGN}" STREQUAL "IMPORTED")
    add_library(${cholmod} INTERFACE IMPORTED)
    set_target_properties(${cholmod} PROPERTIES
      INTERFACE_INCLUDE_DIRECTORIES "${include_dir}"
      INTERFACE_LINK_LIBRARIES "${core};${libraries}"
      INTERFACE_COMPILE_DEFINITIONS CGAL_LAPLACIAN_DEFORMATION_HAS_CHOLMOD)
    if(use_default)
      set_property(TARGET ${core} APPEND PROPERTY INTERFACE_INCLUDE_DIRECTORIES "${include_dir}")
      set_property(TARGET ${core} APPEND PROPERTY INTERFACE_LINK_LIBRARIES ${libraries})
      set_property(TARGET ${core} APPEND PROPERTY INTERFACE_COMPILE_DEFINITIONS CGAL_LAPLACIAN_DEFORMATION_USE_CHOLMOD)
    endif()
  else()
    add_library(${cholmod} INTERFACE)
    add_library(CGAL::${cholmod} ALIAS ${cholmod})
    target_include_directories(${cholmod} INTERFACE ${include_dir})
    target_link_libraries(${cholmod} INTERFACE ${core} ${libraries})
    target_compile_definitions(${cholmod} INTERFACE CGAL_LAPLACIAN_DEFORMATION_HAS_CHOLMOD)
    if(use_default)
      # build tree only (the core target is exported: the installed config does this on the
      # consumer's machine)
      target_include_directories(${core} INTERFACE $<BUILD_INTERFACE:${include_dir}>)
      foreach(library ${libraries})
        target_link_libraries(${core} INTERFACE $<BUILD_INTERFACE:${library}>)
      endforeach()
      target_compile_definitions(${core} INTERFACE $<BUILD_INTERFACE:CGAL_LAPLACIAN_DEFORMATION_USE_CHOLMOD>)
    endif()
  endif()
  set(LAPLACIAN_DEFORMATION_HAS_CHOLMOD ON PARENT_SCOPE)
endfunction()
