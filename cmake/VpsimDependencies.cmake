# All third-party packages come from Debian (tools/install-deps.sh installs them).
find_package(Threads REQUIRED)
find_package(Vulkan REQUIRED COMPONENTS glslangValidator)
find_package(glm REQUIRED)
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(CLI11 REQUIRED)
find_package(TBB REQUIRED)
find_package(PNG REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(POLYCLIPPING REQUIRED IMPORTED_TARGET polyclipping)
add_library(vpsim_polyclipping INTERFACE)
target_link_libraries(vpsim_polyclipping INTERFACE PkgConfig::POLYCLIPPING)

# Debian ships FindOpenVDB.cmake under its cmake folder rather than a config package.
list(APPEND CMAKE_MODULE_PATH "/usr/lib/x86_64-linux-gnu/cmake/OpenVDB" "/usr/lib/cmake/OpenVDB"
     "/usr/local/lib/cmake/OpenVDB")
find_package(OpenVDB REQUIRED)

add_library(vpsim_warnings INTERFACE)
target_compile_options(vpsim_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wno-unused-parameter)

# Open MPI (Debian's libopenmpi-dev) is optional: with it, mpirun/srun spread a job's Monte Carlo
# and a batch's jobs over ranks (src/cluster); without it vpsim is one process. On where found.
option(VPSIM_MPI "Use MPI where found" ON)
set(VPSIM_WITH_MPI OFF)
if(VPSIM_MPI)
  enable_language(C)  # FindMPI's C component compiles a C test program
  find_package(MPI COMPONENTS C)
  if(MPI_C_FOUND)
    set(VPSIM_WITH_MPI ON)
  endif()
endif()
message(STATUS "vpsim: MPI ${VPSIM_WITH_MPI}")
