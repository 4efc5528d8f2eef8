# geartopo_add_library(<name> SOURCES … [PUBLIC …] [PRIVATE …] [PCH <header> …])
# One library of geartopo: target geartopo_<name>, alias geartopo::<name>, public headers under
# include/geartopo/<name>/ (included as "geartopo/<name>/x.hpp"), sources and private headers under src/<name>/.
# Every library is exported for find_package(geartopo) (cmake/geartopoConfig.cmake.in).
function(geartopo_add_library name)
  cmake_parse_arguments(arg "" "" "SOURCES;PUBLIC;PRIVATE;PCH" ${ARGN})
  set(target geartopo_${name})
  add_library(${target} STATIC ${arg_SOURCES})
  add_library(geartopo::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name} POSITION_INDEPENDENT_CODE ON)
  target_include_directories(${target}
    PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
    PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_link_libraries(${target} PUBLIC ${arg_PUBLIC} PRIVATE ${arg_PRIVATE})
  # Heavy third-party headers (Eigen's dense module, fmt) parsed once per library instead of once per file.
  if(GEARTOPO_PCH AND arg_PCH)
    target_precompile_headers(${target} PRIVATE ${arg_PCH})
  endif()
  install(TARGETS ${target} EXPORT geartopoTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  set_property(GLOBAL APPEND PROPERTY GEARTOPO_LIBRARIES ${target})
endfunction()
