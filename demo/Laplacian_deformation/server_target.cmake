# The browser editor's server (laplacian_deform --serve, deformation_server.h) as the interface
# target Laplacian_deformation_server: cpp-httplib and nlohmann-json from Debian (scripts/setup.sh
# installs them). Included by this folder's CMakeLists.txt and by the fuzz targets' (which are built
# without the tool): the packages are found in each including folder, the target is defined once.
find_package(nlohmann_json 3.2 REQUIRED)
find_path(HTTPLIB_INCLUDE_DIR httplib.h REQUIRED)
# Debian builds cpp-httplib as a shared library with OpenSSL, zlib and Brotli support: the same
# macros must be defined here, or the classes' layout would differ from the library's.
find_library(HTTPLIB_LIBRARY cpp-httplib REQUIRED)
find_package(Threads REQUIRED)
if(NOT TARGET Laplacian_deformation_server)
  add_library(Laplacian_deformation_server INTERFACE)
  target_include_directories(Laplacian_deformation_server INTERFACE ${CMAKE_CURRENT_LIST_DIR} ${HTTPLIB_INCLUDE_DIR})
  target_link_libraries(Laplacian_deformation_server INTERFACE CGAL::Laplacian_deformation nlohmann_json::nlohmann_json
                        ${HTTPLIB_LIBRARY} Threads::Threads)
  target_compile_definitions(Laplacian_deformation_server INTERFACE
    CPPHTTPLIB_OPENSSL_SUPPORT CPPHTTPLIB_ZLIB_SUPPORT CPPHTTPLIB_BROTLI_SUPPORT)
endif()

