# Precompiled headers: Eigen (Core, Geometry) and the standard headers that nearly every file includes are parsed
# once for all libraries (geartopo_pch_library, adds fmt) and once for all test programs (geartopo_pch_program in
# tests/, adds GoogleTest), instead of once per file: a 36-line effect otherwise preprocesses to 150 k lines.
# A target may reuse a precompiled header only when its compile flags and definitions match those it was made with
# (CMake adds -Winvalid-pch, an error under GEARTOPO_WERROR): every library links fmt (FMT_SHARED), and a library
# with other flags (CGAL's -frounding-math in diagnosis) gives its own list with PCH.
set(GEARTOPO_PCH_HEADERS <Eigen/Core> <Eigen/Geometry> <algorithm> <cmath> <memory> <string> <vector>)
if(GEARTOPO_PCH)
  add_library(geartopo_pch_library OBJECT ${PROJECT_SOURCE_DIR}/cmake/pch.cpp)
  set_target_properties(geartopo_pch_library PROPERTIES POSITION_INDEPENDENT_CODE ON)
  target_compile_features(geartopo_pch_library PRIVATE cxx_std_20)
  target_link_libraries(geartopo_pch_library PRIVATE Eigen3::Eigen fmt::fmt)
  target_precompile_headers(geartopo_pch_library PRIVATE ${GEARTOPO_PCH_HEADERS} <fmt/format.h>)
endif()

# Unity builds: each library compiled as one translation unit, its files' common templates (Eigen, fmt, the standard
# library) instantiated once instead of once per file (docs/performance.md, "Build"). In such a unit GCC counts every
# included source file as a header, so a type of an anonymous namespace held by a class trips -Wsubobject-linkage, a
# warning meant for real headers: off for unity targets only.
option(GEARTOPO_UNITY "Compile each library as one translation unit (faster clean builds)" ON)

# geartopo_reuse_pch(<target> library|program): the shared precompiled headers for a library or a program.
function(geartopo_reuse_pch target kind)
  if(GEARTOPO_PCH)
    target_precompile_headers(${target} REUSE_FROM geartopo_pch_${kind})
  endif()
endfunction()

# geartopo_add_library(<name> SOURCES … [PUBLIC …] [PRIVATE …] [PCH <header> …] [UNITY])
# UNITY: one translation unit even with -DGEARTOPO_UNITY=OFF.
# One library of geartopo: target geartopo_<name>, alias geartopo::<name>, public headers included as
# "geartopo/<name>/x.hpp". Two shapes (docs/architecture.md):
#   - under src/: public headers in include/geartopo/<name>/, sources and private headers in src/<name>/;
#   - self-contained at the top level (gears/, surfaces/, evaluation/): <name>/CMakeLists.txt, public headers in
#     <name>/include/geartopo/<name>/, sources and private headers in <name>/src/; the headers are installed to the
#     same include/geartopo/<name>/ as the others'.
# Every library is exported for find_package(geartopo) (cmake/geartopoConfig.cmake.in).
function(geartopo_add_library name)
  cmake_parse_arguments(arg "UNITY" "" "SOURCES;PUBLIC;PRIVATE;PCH" ${ARGN})
  set(target geartopo_${name})
  add_library(${target} STATIC ${arg_SOURCES})
  add_library(geartopo::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name} POSITION_INDEPENDENT_CODE ON)
  if(IS_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include) # self-contained
    set(public_dir ${CMAKE_CURRENT_SOURCE_DIR}/include)
    set(private_dir ${CMAKE_CURRENT_SOURCE_DIR}/src)
    install(DIRECTORY ${public_dir}/geartopo DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  else() # the root CMakeLists.txt installs include/geartopo
    set(public_dir ${PROJECT_SOURCE_DIR}/include)
    set(private_dir ${CMAKE_CURRENT_SOURCE_DIR})
  endif()
  target_include_directories(${target}
    PUBLIC $<BUILD_INTERFACE:${public_dir}> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
    PRIVATE ${private_dir})
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_link_libraries(${target} PUBLIC ${arg_PUBLIC} PRIVATE ${arg_PRIVATE})
  # Precompiled headers: the shared set; a library with its own list (PCH …: heavier headers, or flags the shared set
  # was not made with) precompiles it only when its files are compiled one by one — for one unity unit the header
  # would be compiled once to be read once, 10–14 CPU-s more than parsing it in the unit.
  set(unity OFF)
  if(arg_UNITY OR GEARTOPO_UNITY)
    set(unity ON)
  endif()
  if(GEARTOPO_PCH AND arg_PCH)
    if(NOT unity)
      target_precompile_headers(${target} PRIVATE ${arg_PCH})
    endif()
  else()
    geartopo_reuse_pch(${target} library)
  endif()
  # UNITY: the library's files compiled as one translation unit (many small files sharing heavy templates).
  if(unity)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 0)
    target_compile_options(${target} PRIVATE $<$<CXX_COMPILER_ID:GNU>:-Wno-subobject-linkage>)
  endif()
  install(TARGETS ${target} EXPORT geartopoTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  set_property(GLOBAL APPEND PROPERTY GEARTOPO_LIBRARIES ${target})
endfunction()
