# Compiles shaders/NAME.comp to SPIR-V at build time and embeds it as a C array:
# <build>/generated/vpsim/shaders/NAME_spv.h declares `const uint32_t NAME_spv[]`.
# No shader file is looked up at run time. A target that includes the header calls
# vpsim_use_shader(target NAME) (vpsim_add_module does this for its SHADERS).
set(VPSIM_SHADER_DIR "${CMAKE_CURRENT_SOURCE_DIR}/shaders")
set(VPSIM_SHADER_OUT "${CMAKE_CURRENT_BINARY_DIR}/generated/vpsim/shaders")
file(MAKE_DIRECTORY "${VPSIM_SHADER_OUT}")
file(GLOB VPSIM_SHADER_INCLUDES CONFIGURE_DEPENDS "${VPSIM_SHADER_DIR}/include/*.glsl")

function(vpsim_use_shader target name)
  set(shader "${VPSIM_SHADER_DIR}/${name}.comp")
  set(header "${VPSIM_SHADER_OUT}/${name}_spv.h")
  if(NOT TARGET vpsim_shader_${name})
    add_custom_command(
      OUTPUT "${header}"
      COMMAND Vulkan::glslangValidator --quiet -V --target-env vulkan1.1
              -I${VPSIM_SHADER_DIR}/include --vn ${name}_spv -o "${header}" "${shader}"
      DEPENDS "${shader}" ${VPSIM_SHADER_INCLUDES}
      COMMENT "Compiling shader ${name}.comp to SPIR-V"
      VERBATIM)
    add_custom_target(vpsim_shader_${name} DEPENDS "${header}")
  endif()
  add_dependencies(${target} vpsim_shader_${name})
  target_include_directories(${target} PRIVATE "${CMAKE_BINARY_DIR}/generated")
endfunction()
