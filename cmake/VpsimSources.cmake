# Where a module's sources are, for the main build (cmake/VpsimModules.cmake) and for builds of
# parts of modules with other flags (fuzz/CMakeLists.txt), so both take the same files.
get_filename_component(VPSIM_ROOT "${CMAKE_CURRENT_LIST_DIR}/.." ABSOLUTE)

# vpsim_module_sources(OUT MODULE [FILES name.cpp...])
# OUT = src/MODULE/**/*.cpp (subfolders group concepts inside a module), or with FILES only the
# files of those names, wherever in the module they are (an error when a name is missing or
# appears twice), so moving a file between a module's folders needs no edit of the caller.
function(vpsim_module_sources out module)
  cmake_parse_arguments(ARG "" "" "FILES" ${ARGN})
  file(GLOB_RECURSE sources CONFIGURE_DEPENDS "${VPSIM_ROOT}/src/${module}/*.cpp")
  if(ARG_FILES)
    set(picked "")
    foreach(name ${ARG_FILES})
      set(found "")
      foreach(source ${sources})
        get_filename_component(base "${source}" NAME)
        if(base STREQUAL name)
          list(APPEND found "${source}")
        endif()
      endforeach()
      list(LENGTH found count)
      if(NOT count EQUAL 1)
        message(FATAL_ERROR "vpsim_module_sources: ${name} is in src/${module} ${count} times")
      endif()
      list(APPEND picked ${found})
    endforeach()
    set(sources ${picked})
  endif()
  set(${out} ${sources} PARENT_SCOPE)
endfunction()
