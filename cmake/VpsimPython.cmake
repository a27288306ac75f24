# VPSIM_PYTHON: the `vpsim` Python module (src/python, pybind11). On by default when pybind11 and
# the Python development files are found, off under VPSIM_SANITIZE (an ASan-built extension needs
# the ASan runtime preloaded into the interpreter). Debian's own interpreter (/usr/bin/python3, the
# one that sees Debian's numpy and pytest) is used when it exists, whatever python3 comes first on
# the PATH (a pyenv one may lack numpy); -DPython_EXECUTABLE=... chooses another.
if(EXISTS /usr/bin/python3 AND NOT DEFINED Python_EXECUTABLE)
  set(Python_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python interpreter of the vpsim module")
endif()
if(NOT DEFINED PYTHON_EXECUTABLE AND DEFINED Python_EXECUTABLE)
  set(PYTHON_EXECUTABLE "${Python_EXECUTABLE}" CACHE FILEPATH "the same, for pybind11's older mode")
endif()

set(VPSIM_PYTHON_DEFAULT OFF)
if(NOT VPSIM_SANITIZE)
  find_package(Python COMPONENTS Interpreter Development.Module QUIET)
  if(Python_FOUND)
    find_package(pybind11 CONFIG QUIET)
    if(pybind11_FOUND)
      set(VPSIM_PYTHON_DEFAULT ON)
    endif()
  endif()
endif()
option(VPSIM_PYTHON "Build the vpsim Python module (pybind11)" ${VPSIM_PYTHON_DEFAULT})

if(VPSIM_PYTHON)
  if(VPSIM_SANITIZE)
    message(FATAL_ERROR "VPSIM_PYTHON is not supported with VPSIM_SANITIZE (see README)")
  endif()
  find_package(Python COMPONENTS Interpreter Development.Module REQUIRED)
  find_package(pybind11 CONFIG REQUIRED)
  # The module libraries are linked into a shared object: every target is built PIC.
  set(CMAKE_POSITION_INDEPENDENT_CODE ON)
  set(VPSIM_PYTHON_INSTALL_DIR
      "lib/python${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}/dist-packages"
      CACHE STRING "where `cmake --install` puts the vpsim package (relative to the prefix)")
  message(STATUS "vpsim Python module: on (${Python_EXECUTABLE}, pybind11 ${pybind11_VERSION})")
else()
  message(STATUS "vpsim Python module: off")
endif()
