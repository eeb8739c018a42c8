# Target helpers in the spirit of absl_cc_library / mujoco_test.

function(haptex_set_warnings target)
  target_compile_options(${target} PRIVATE ${HAPTEX_WARNING_FLAGS})
endfunction()

# haptex_cc_library(NAME name SRCS ... DEPS ... [PUBLIC_DEPS ...])
# Creates target haptex_<name> with alias haptex::<name>; headers are included as "libs/<dir>/x.h".
function(haptex_cc_library)
  cmake_parse_arguments(ARG "" "NAME" "SRCS;DEPS;PUBLIC_DEPS" ${ARGN})
  set(target haptex_${ARG_NAME})
  if(ARG_SRCS)
    add_library(${target} STATIC ${ARG_SRCS})
    target_include_directories(${target} PUBLIC ${PROJECT_SOURCE_DIR})
    target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_DEPS})
    haptex_set_warnings(${target})
  else()
    add_library(${target} INTERFACE)
    target_include_directories(${target} INTERFACE ${PROJECT_SOURCE_DIR})
    target_link_libraries(${target} INTERFACE ${ARG_PUBLIC_DEPS} ${ARG_DEPS})
  endif()
  add_library(haptex::${ARG_NAME} ALIAS ${target})
endfunction()

# haptex_cc_test(NAME name SRCS ... DEPS ... [LABELS ...] [TIMEOUT s])
# One GoogleTest executable per unit, registered with ctest (tests discovered at run time).
function(haptex_cc_test)
  cmake_parse_arguments(ARG "" "NAME;TIMEOUT" "SRCS;DEPS;LABELS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SRCS})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main GTest::gmock)
  target_include_directories(${ARG_NAME} PRIVATE ${PROJECT_SOURCE_DIR})
  # where tests find test data and built executables (tests/support/test_paths.h)
  target_compile_definitions(${ARG_NAME} PRIVATE
    HAPTEX_TEST_SOURCE_DIR="${PROJECT_SOURCE_DIR}" HAPTEX_TEST_BUILD_DIR="${PROJECT_BINARY_DIR}")
  haptex_set_warnings(${ARG_NAME})
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 300)
  endif()
  if(NOT ARG_LABELS)
    set(ARG_LABELS unit)
  endif()
  # System tests start real-time services (2-6 processes each) and assert their timing: one at a
  # time, beside the unit tests. Two at once on a 2-core host stalled loops past their watchdogs.
  set(lock "")
  if("system" IN_LIST ARG_LABELS)
    set(lock RESOURCE_LOCK haptex_realtime_processes)
  endif()
  gtest_discover_tests(${ARG_NAME}
    DISCOVERY_TIMEOUT 60
    PROPERTIES TIMEOUT ${ARG_TIMEOUT} LABELS "${ARG_LABELS}" ${lock})
endfunction()

# haptex_benchmark(NAME name SRCS ... DEPS ...): a Google Benchmark executable (not a test).
function(haptex_benchmark)
  cmake_parse_arguments(ARG "" "NAME" "SRCS;DEPS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SRCS})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_DEPS} benchmark::benchmark)
  target_include_directories(${ARG_NAME} PRIVATE ${PROJECT_SOURCE_DIR})
  haptex_set_warnings(${ARG_NAME})
endfunction()
