# Warning and sanitizer flags, applied per target through barylab_set_flags(target).
add_library(barylab_flags INTERFACE)
target_compile_options(barylab_flags INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wnon-virtual-dtor>
  $<$<CXX_COMPILER_ID:GNU>:-Wshadow=local>)
if(BARYLAB_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "BARYLAB_FUZZ needs clang (libFuzzer): configure with "
      "CC=clang CXX=clang++ (tools/fuzz.sh does)")
  endif()
  # our code carries libFuzzer's coverage instrumentation; only the fuzz executables link
  # libFuzzer's main (-fsanitize=fuzzer)
  target_compile_options(barylab_flags INTERFACE -fsanitize=fuzzer-no-link)
  set(BARYLAB_SANITIZE ON)
endif()
# UndefinedBehaviorSanitizer checks a sanitizer tree leaves out (a -fno-sanitize= list). CI's
# sanitizer tree leaves out `null,alignment` (tools/bootstrap.sh): they instrument every load and
# store, which made the -O1 core files compile ~35% slower (unity batch of the BBW/LBC files:
# 52-58 s of CPU with them, 36-42 s without); a null dereference still stops the run as
# AddressSanitizer's SEGV report, and the vectorised kernels load unaligned on purpose.
set(BARYLAB_SANITIZE_UNDEFINED_SKIP "" CACHE STRING
  "UBSan checks left out of sanitizer trees (comma-separated, e.g. null,alignment)")
if(BARYLAB_SANITIZE)
  target_compile_options(barylab_flags INTERFACE
    -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  if(BARYLAB_SANITIZE_UNDEFINED_SKIP)
    target_compile_options(barylab_flags INTERFACE
      -fno-sanitize=${BARYLAB_SANITIZE_UNDEFINED_SKIP})
  endif()
  target_link_options(barylab_flags INTERFACE -fsanitize=address,undefined)
endif()

# The linker: LLVM's lld where the compiler can use it (Debian's lld, in tools/bootstrap.sh's
# packages). CI links ~160 executables and modules in two trees; GNU ld took 3.3 s for one
# sanitizer test executable, lld 1.3 s (~2 min of CI's CPU). Off, or without lld: the default
# linker.
option(BARYLAB_USE_LLD "Link with LLVM's lld when the compiler can use it" ON)
if(BARYLAB_USE_LLD AND NOT CMAKE_VERSION VERSION_LESS 3.18)
  include(CheckLinkerFlag)
  check_linker_flag(CXX "-fuse-ld=lld" BARYLAB_HAVE_LLD)
  if(BARYLAB_HAVE_LLD)
    add_link_options(-fuse-ld=lld)
  endif()
endif()

function(barylab_set_flags target)
  target_link_libraries(${target} PRIVATE $<BUILD_INTERFACE:barylab_flags>)
endfunction()

# Tests and the application shells (CLI, viewer) compile at -O1 in optimised builds: their own
# code is thin over the core and filter libraries, which keep the build type's -O3, and -O1
# compiles them 20-35% faster (the LBC test: 45 s -> 30 s), which CI's 30 minutes on 2 cores
# need. Benchmarks keep -O3.
add_library(barylab_light_optimization INTERFACE)
target_compile_options(barylab_light_optimization INTERFACE
  $<$<AND:$<CXX_COMPILER_ID:GNU,Clang>,$<CONFIG:Release>>:-O1>)

function(barylab_set_light_optimization target)
  target_link_libraries(${target} PRIVATE $<BUILD_INTERFACE:barylab_light_optimization>)
endfunction()

# barylab_set_unity_build(target [SKIP sources...]): compiles the target's sources in unity
# batches when BARYLAB_UNITY_BUILD is on. Sources listed after SKIP are compiled on their own
# (the largest files, which share little with the rest and would lengthen one batch). Every core
# file must then avoid names that clash with another file's anonymous namespace: shared helpers
# live in core/detail (timing.h, constants.h).
function(barylab_set_unity_build target)
  cmake_parse_arguments(ARG "" "" "SKIP" ${ARGN})
  if(NOT BARYLAB_UNITY_BUILD)
    return()
  endif()
  set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
  if(ARG_SKIP)
    set_source_files_properties(${ARG_SKIP} TARGET_DIRECTORY ${target}
      PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
  endif()
  # GCC warns about a class whose member's type lives in an anonymous namespace when the class is
  # defined in an included file, which every source is in a unity batch; it is not a problem in
  # a file compiled once.
  target_compile_options(${target} PRIVATE $<$<CXX_COMPILER_ID:GNU>:-Wno-subobject-linkage>)
endfunction()
