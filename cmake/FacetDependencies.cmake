# Every dependency comes from a Debian 12 package; nothing is downloaded at configure or build time.
# tools/lib/setup.sh installs the packages named here.

find_package(Eigen3 3.4 REQUIRED NO_MODULE)   # libeigen3-dev
find_package(TBB REQUIRED)                    # libtbb-dev
find_package(nlohmann_json 3.10 REQUIRED)     # nlohmann-json3-dev
find_package(tinyobjloader REQUIRED)          # libtinyobjloader-dev (shared library, no IMPLEMENTATION macro)
find_package(PNG REQUIRED)                    # libpng-dev
find_package(JPEG REQUIRED)                   # libjpeg62-turbo-dev (JPEG textures)
find_package(embree 3 REQUIRED)               # libembree-dev 3.13: target `embree` (ray-cast shadows)
find_package(meshoptimizer REQUIRED)          # libmeshoptimizer-dev 0.18: glTF EXT_meshopt_compression
find_package(draco REQUIRED)                  # libdraco-dev 1.5: glTF KHR_draco_mesh_compression
find_package(OpenEXR 3 REQUIRED)              # libopenexr-dev 3.1: float images (write_exr: baked lightmaps, HDR frames)
find_package(CLI11 REQUIRED)                  # libcli11-dev 2.1 (header-only): the facet program's options
# stb_image decodes TGA and BMP textures (PNG goes through libpng, JPEG through libjpeg-turbo);
# Debian's libstb.so holds the implementations.
find_package(PkgConfig REQUIRED)
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)  # libstb-dev

# Debian's xsimd 8.1 exports INTERFACE_LINK_LIBRARIES "xtl", a library nothing provides: linking
# the target fails with `cannot find -lxtl` (Debian's xsimd 8.1 package). xsimd only needs
# xtl for xtensor interop, so an empty interface target of that name satisfies it. Consumers link
# xsimd as $<BUILD_INTERFACE:xsimd> so it never leaks into an installed package.
if(NOT TARGET xtl)
  add_library(xtl INTERFACE IMPORTED)
endif()
find_package(xsimd 8.1 REQUIRED)              # libxsimd-dev

if(FACET_BUILD_TESTS)
  find_package(GTest REQUIRED)                # libgtest-dev
endif()
if(FACET_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)            # libbenchmark-dev
endif()
