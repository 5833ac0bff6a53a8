# What every test program is compiled and linked with. The precompiled header is only valid for a
# program compiled exactly like the target that made it, so both get their settings here.
function(meter_test_program_settings target)
  # The test drivers themselves at -O1 in optimised builds (a third less compile time than -O3);
  # the libraries they test keep the build's own flags.
  # In the sanitizer build at -O0 and without libFuzzer's coverage counters (no fuzzer runs a test
  # driver): a test source under clang with ASan+UBSan compiled in 9.0 s instead of 27.8 s
  # (protocol's first test batch, 2026-12-06), and the test programs were 45 % of that build's
  # compile time. The sanitizers still check every line the tests run; the libraries under test keep
  # -O2 and their coverage counters.
  if(METER_SANITIZE)
    target_compile_options(${target} PRIVATE $<$<CONFIG:Release,RelWithDebInfo>:-O0>)
  else()
    target_compile_options(${target} PRIVATE $<$<CONFIG:Release,RelWithDebInfo>:-O1>)
  endif()
  if(METER_FUZZ)
    target_compile_options(${target} PRIVATE -fno-sanitize=fuzzer-no-link)
  endif()
  # A test file's fixtures live in an anonymous namespace and TEST_F derives from them; a unity batch
  # includes the file, and GCC then takes it for a header and warns of the derived class's linkage.
  # The idiom is right in a test file; the product keeps the warning (it caught a file-local type
  # shadowing a library's type in a batch).
  if(METER_UNITY AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${target} PRIVATE -Wno-subobject-linkage)
  endif()
  target_link_libraries(${target} PRIVATE GTest::gtest GTest::gtest_main GTest::gmock
                        meter_build_flags Threads::Threads)
  target_compile_definitions(${target} PRIVATE
      METER_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
      METER_BINARY_DIR="${PROJECT_BINARY_DIR}"
      METER_SHARED_DIR="${METER_SHARED_DIR}")
endfunction()

# GoogleTest and GoogleMock, precompiled once for all test programs (REUSE_FROM): parsing them took
# about 2.5 s of each test source's compile (one TEST at -O1: 3.3 s, 2026-12-05), and there are 130
# test sources in the two builds scripts/test makes.
function(meter_add_test_pch)
  set(anchor "${PROJECT_BINARY_DIR}/meter_test_pch.cpp")
  if(NOT EXISTS "${anchor}")
    file(WRITE "${anchor}" "// The precompiled GoogleTest headers' own translation unit (cmake/MeterTesting.cmake).\n")
  endif()
  add_library(meter_test_pch STATIC "${anchor}")
  meter_test_program_settings(meter_test_pch)
  target_precompile_headers(meter_test_pch PRIVATE <gtest/gtest.h> <gmock/gmock.h>)
endfunction()

# The offline side's libraries (the converter and what it links): a test program linking one is not
# built by a target build.
set(METER_OFFLINE_LIBRARIES meter::convert meter_engine_test_scenes TinyGLTF::TinyGLTF meshoptimizer::meshoptimizer)

# meter_add_gtest(<target> LABELS <labels...> SOURCES <files...> LIBS <libs...> [TIMEOUT s]
#                 [RESOURCE_LOCK name] [COST n])
# Builds a GoogleTest executable and registers each test case with CTest under the given labels
# (unit, integration, vcan, slow) so `ctest -L unit` runs a subset. COST starts a long program's
# tests early under ctest -j in a fresh tree, before ctest has measured any time (it orders by the
# times it measured once it has them).
function(meter_add_gtest target)
  cmake_parse_arguments(T "" "TIMEOUT;RESOURCE_LOCK;COST" "LABELS;SOURCES;LIBS" ${ARGN})
  if(NOT METER_BUILD_TESTS)
    return()
  endif()
  # A target build (METER_RUNTIME_ONLY) has no converter: the test programs that convert scenes
  # in-process are left out there (they run in the host's builds).
  if(METER_RUNTIME_ONLY)
    foreach(lib IN LISTS T_LIBS)
      if(lib IN_LIST METER_OFFLINE_LIBRARIES)
        return()
      endif()
    endforeach()
  endif()
  if(NOT TARGET meter_test_pch)
    meter_add_test_pch()
  endif()
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 120)
  endif()
  set(_props LABELS "${T_LABELS}")
  if(METER_SANITIZE)
    # ASan+UBSan (and the fuzz build's coverage counters) run our code 2-5x slower; the timeouts
    # are hang guards, not speed goals.
    math(EXPR T_TIMEOUT "${T_TIMEOUT} * 4")
    list(APPEND _props ENVIRONMENT
         "LSAN_OPTIONS=suppressions=${PROJECT_SOURCE_DIR}/cmake/sanitizers/lsan.supp:print_suppressions=0")
  endif()
  list(APPEND _props TIMEOUT ${T_TIMEOUT})
  if(T_RESOURCE_LOCK)
    list(APPEND _props RESOURCE_LOCK ${T_RESOURCE_LOCK})
  endif()
  if(T_COST)
    list(APPEND _props COST ${T_COST})
  endif()
  add_executable(${target} ${T_SOURCES})
  if("unit" IN_LIST T_LABELS)
    set_property(GLOBAL APPEND PROPERTY METER_UNIT_TEST_PROGRAMS ${target})
  endif()
  meter_test_program_settings(${target})
  target_link_libraries(${target} PRIVATE ${T_LIBS})
  target_precompile_headers(${target} REUSE_FROM meter_test_pch)
  gtest_discover_tests(${target}
      DISCOVERY_TIMEOUT 60
      PROPERTIES ${_props}
      WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
endfunction()

# meter_hold_vcan(<tests...>)
# The tests boot the qemu VM or use vcan0: one at a time (RESOURCE_LOCK meter_vcan), since two TCG
# guests on the CI machine's two cores would each get half the time they were measured with, and on
# a CAN kernel no two tests may share vcan0. Other tests may run beside them (no RUN_SERIAL): the
# label passes with a CPU-bound process taking one of the two cores (docs/vcan.md, "Wall time and
# load"); the replay's timing is measured on the guest's instruction-counted clock, where host
# load does not show. COST starts them first, before ctest has measured times, so the long VM
# tests do not end a parallel run alone.
function(meter_hold_vcan)
  set_tests_properties(${ARGN} PROPERTIES RESOURCE_LOCK meter_vcan COST 1000)
endfunction()
