# The instruction set the project is compiled for (PARTITA_ARCH):
#   auto      x86-64-v3 (AVX2, FMA; Haswell, Zen and later) when the build machine runs it,
#             otherwise the compiler's default. For builds that run where they are built
#             (`make demo`, `make test`, `make bench`).
#   portable  the compiler's default (x86-64 baseline): binaries that run on any x86-64.
#             The Docker image is built this way.
#   <level>   any -march value, e.g. x86-64-v3 or native.
# The path tracer is about 4% faster with x86-64-v3 (docs/eval-throughput.md); results agree within
# the statistical tests either way (FMA contraction changes the last bits of some sums).
set(PARTITA_ARCH "auto" CACHE STRING "Instruction set: auto, portable or a -march value")

function(partita_resolve_arch out)
  if(PARTITA_ARCH STREQUAL "portable")
    set(${out} "" PARENT_SCOPE)
    return()
  endif()
  if(NOT PARTITA_ARCH STREQUAL "auto")
    include(CheckCXXCompilerFlag)
    # The result is cached per value, so that changing PARTITA_ARCH checks the new one.
    string(MAKE_C_IDENTIFIER "${PARTITA_ARCH}" _arch_id)
    check_cxx_compiler_flag("-march=${PARTITA_ARCH}" PARTITA_MARCH_ACCEPTED_${_arch_id})
    if(NOT PARTITA_MARCH_ACCEPTED_${_arch_id})
      message(FATAL_ERROR "PARTITA_ARCH=${PARTITA_ARCH}: the compiler does not accept "
                          "-march=${PARTITA_ARCH} (use auto, portable or a -march value)")
    endif()
    set(${out} "${PARTITA_ARCH}" PARENT_SCOPE)
    return()
  endif()
  set(${out} "" PARENT_SCOPE)
  if(NOT CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$")
    return()
  endif()
  try_run(_run_result _compile_result
          SOURCES "${CMAKE_CURRENT_SOURCE_DIR}/cmake/cpu_has_x86_64_v3.cpp")
  if(_compile_result AND _run_result EQUAL 0)
    set(${out} "x86-64-v3" PARENT_SCOPE)
  endif()
endfunction()

partita_resolve_arch(PARTITA_MARCH)
if(PARTITA_MARCH)
  add_compile_options(-march=${PARTITA_MARCH})
  message(STATUS "Partita: compiling for -march=${PARTITA_MARCH} (PARTITA_ARCH=${PARTITA_ARCH})")
else()
  message(STATUS "Partita: compiling for the compiler's default instruction set (PARTITA_ARCH=${PARTITA_ARCH})")
endif()
