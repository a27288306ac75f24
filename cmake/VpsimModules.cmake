# vpsim_add_module(NAME [DEPENDS module...] [SHADERS shader...] [LIBS target...])
# Builds src/NAME/**/*.cpp (subfolders group concepts inside a module; vpsim_module_sources in
# cmake/VpsimSources.cmake) into the static library vpsim_NAME. DEPENDS names other vpsim modules,
# SHADERS names shaders/*.comp whose embedded SPIR-V headers the module includes, LIBS names
# third-party targets used privately (OpenVDB::openvdb, TBB::tbb, ...).
include(VpsimSources)
set(VPSIM_MODULE_TARGETS "" CACHE INTERNAL "")
function(vpsim_add_module name)
  cmake_parse_arguments(ARG "" "" "DEPENDS;SHADERS;LIBS;PUBLIC_LIBS" ${ARGN})
  vpsim_module_sources(sources ${name})
  set(target vpsim_${name})
  add_library(${target} STATIC ${sources})
  target_include_directories(${target}
    PUBLIC "${PROJECT_SOURCE_DIR}/include"
    PRIVATE "${PROJECT_SOURCE_DIR}/src" "${PROJECT_SOURCE_DIR}/shaders/include")
  target_compile_definitions(${target} PUBLIC VPSIM_VERSION="${PROJECT_VERSION}")
  target_link_libraries(${target} PUBLIC nlohmann_json::nlohmann_json glm::glm ${ARG_PUBLIC_LIBS}
                                   PRIVATE vpsim_warnings ${ARG_LIBS})
  foreach(dep ${ARG_DEPENDS})
    target_link_libraries(${target} PUBLIC vpsim_${dep})
  endforeach()
  foreach(shader ${ARG_SHADERS})
    vpsim_use_shader(${target} ${shader})
  endforeach()
  set(VPSIM_MODULE_TARGETS ${VPSIM_MODULE_TARGETS} ${target} CACHE INTERNAL "")
endfunction()
