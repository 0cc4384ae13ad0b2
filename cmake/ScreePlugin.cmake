# scree_add_plugin(<name> KIND <material|boundary|writer|functionObject|...>
#                  SOURCES <files...> [LINK <targets...>] [NO_INSTALL] [CUDA_KERNELS])
#
# Builds lib<name>.so as a Scree plugin: a module library with hidden symbols that
# exports one entry point (see scree/plugin/plugin_api.hpp). Sources of material
# plugins contain kernels: when Scree has CUDA, they are compiled as CUDA so that the
# kernels exist for both backends. The plugin goes to <libdir>/scree/plugins, where
# `scree` looks by default.
function(scree_add_plugin name)
  cmake_parse_arguments(P "NO_INSTALL;CUDA_KERNELS" "KIND" "SOURCES;LINK" ${ARGN})
  if(NOT P_KIND)
    message(FATAL_ERROR "scree_add_plugin(${name}): KIND is required")
  endif()
  set(target scree_plugin_${name})
  add_library(${target} MODULE ${P_SOURCES})
  set_target_properties(${target} PROPERTIES
    OUTPUT_NAME ${name}
    LIBRARY_OUTPUT_DIRECTORY "${CMAKE_BINARY_DIR}/${SCREE_PLUGIN_SUBDIR}"
    CXX_VISIBILITY_PRESET hidden CUDA_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON
    INSTALL_RPATH "$ORIGIN/../..")
  # Materials carry kernels (their particle passes): compile them as CUDA when Scree
  # has the CUDA backend. Other kinds are host code unless they ask with CUDA_KERNELS.
  if(SCREE_WITH_CUDA AND (P_KIND STREQUAL "material" OR P_CUDA_KERNELS))
    set_source_files_properties(${P_SOURCES} TARGET_DIRECTORY ${target} PROPERTIES LANGUAGE CUDA)
  endif()
  target_link_libraries(${target} PRIVATE Scree::scree ${P_LINK})
  if(NOT P_NO_INSTALL)
    install(TARGETS ${target} LIBRARY DESTINATION ${SCREE_PLUGIN_SUBDIR})
  endif()
endfunction()
