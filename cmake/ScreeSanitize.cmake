# Sanitizer and fuzzing instrumentation for every target of the build (the core, the
# plugins, the utilities and the tests), set by two cache variables:
#
#   SCREE_SANITIZE  a list of sanitizers, e.g. "address;undefined" (-fsanitize=address,undefined)
#   SCREE_FUZZ      ON: also instrument for libFuzzer (clang only: -fsanitize=fuzzer-no-link
#                   everywhere, -fsanitize=fuzzer on the fuzz targets of tests/fuzz)
#
# The flags go on every target through add_compile_options/add_link_options, so the
# plugins (MODULE libraries loaded with Boost.DLL) are instrumented too. The sanitizer
# runtime is linked into the executables (clang: statically, with its symbols exported
# to the libraries loaded later; gcc: libasan.so first in the link), so a plugin that is
# dlopen'ed after start finds it: no LD_PRELOAD is needed. UBSan's checks stay
# recoverable so that its suppressions work (they do not for -fno-sanitize-recover):
# UBSAN_OPTIONS=halt_on_error=1 makes every report that is not suppressed fatal, as
# scripts/sanitize.sh, which builds and runs the tests this way, sets it.
set(SCREE_SANITIZE "" CACHE STRING "Sanitizers for every target, e.g. address;undefined (empty: none)")
option(SCREE_FUZZ "Instrument for libFuzzer and build the fuzz targets as libFuzzer binaries (clang only)" OFF)

if(SCREE_SANITIZE)
  list(JOIN SCREE_SANITIZE "," _scree_san)
  message(STATUS "Scree: sanitizers ${_scree_san} on every target")
  add_compile_options($<$<COMPILE_LANGUAGE:CXX>:-fsanitize=${_scree_san}>
                      $<$<COMPILE_LANGUAGE:CXX>:-fno-omit-frame-pointer>)
  add_link_options(-fsanitize=${_scree_san})
endif()

if(SCREE_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "SCREE_FUZZ needs clang (libFuzzer); with gcc the fuzz targets are built with their "
                        "standalone driver anyway (tests/fuzz/README.md)")
  endif()
  message(STATUS "Scree: libFuzzer instrumentation (fuzzer-no-link) on every target")
  add_compile_options($<$<COMPILE_LANGUAGE:CXX>:-fsanitize=fuzzer-no-link>)
endif()
