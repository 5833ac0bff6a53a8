# meter_add_gtest(<target> LABELS <labels...> SOURCES <files...> LIBS <libs...> [TIMEOUT s]
#                 [RESOURCE_LOCK name])
# Builds a GoogleTest executable and registers each test case with CTest under the given labels
# (unit, integration, vcan, slow) so `ctest -L unit` runs a subset.
function(meter_add_gtest target)
  cmake_parse_arguments(T "" "TIMEOUT;RESOURCE_LOCK" "LABELS;SOURCES;LIBS" ${ARGN})
  if(NOT METER_BUILD_TESTS)
    return()
  endif()
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 120)
  endif()
  set(_props LABELS "${T_LABELS}")
  if(METER_SANITIZE)
    # ASan+UBSan at -O0 runs our code 3-10x slower; the timeouts are hang guards, not speed goals.
    math(EXPR T_TIMEOUT "${T_TIMEOUT} * 4")
    list(APPEND _props ENVIRONMENT
         "LSAN_OPTIONS=suppressions=${PROJECT_SOURCE_DIR}/cmake/sanitizers/lsan.supp:print_suppressions=0")
  endif()
  list(APPEND _props TIMEOUT ${T_TIMEOUT})
  if(T_RESOURCE_LOCK)
    list(APPEND _props RESOURCE_LOCK ${T_RESOURCE_LOCK})
  endif()
  add_executable(${target} ${T_SOURCES})
  # The test drivers themselves at -O1 in release builds (a third less compile time than -O3);
  # the libraries they test keep the build's own flags.
  target_compile_options(${target} PRIVATE $<$<CONFIG:Release>:-O1>)
  if("unit" IN_LIST T_LABELS)
    set_property(GLOBAL APPEND PROPERTY METER_UNIT_TEST_PROGRAMS ${target})
  endif()
  target_link_libraries(${target} PRIVATE ${T_LIBS} GTest::gtest GTest::gtest_main GTest::gmock
                        meter_build_flags Threads::Threads)
  target_compile_definitions(${target} PRIVATE
      METER_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
      METER_BINARY_DIR="${PROJECT_BINARY_DIR}"
      METER_SHARED_DIR="${METER_SHARED_DIR}")
  gtest_discover_tests(${target}
      DISCOVERY_TIMEOUT 60
      PROPERTIES ${_props}
      WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
endfunction()
