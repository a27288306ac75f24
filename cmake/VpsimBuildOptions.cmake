# Developer build options (README "Developing"):
#   VPSIM_WERROR    warnings of our own targets (vpsim_warnings) are errors.
#   VPSIM_SANITIZE  every target built and linked with AddressSanitizer + UndefinedBehaviorSanitizer;
#                   UB aborts at the first report (-fno-sanitize-recover) so ctest sees a failure.
#                   tools/run-sanitized-tests.sh builds ./build-asan with it and runs the suite.
option(VPSIM_WERROR "Treat compiler warnings in vpsim's own code as errors" OFF)
option(VPSIM_SANITIZE "Build with AddressSanitizer and UndefinedBehaviorSanitizer" OFF)

if(VPSIM_WERROR)
  target_compile_options(vpsim_warnings INTERFACE -Werror)
endif()

if(VPSIM_SANITIZE)
  set(VPSIM_SANITIZER_FLAGS -fsanitize=address,undefined -fno-omit-frame-pointer
                            -fno-sanitize-recover=undefined)
  add_compile_options(${VPSIM_SANITIZER_FLAGS})
  add_link_options(${VPSIM_SANITIZER_FLAGS})
endif()
