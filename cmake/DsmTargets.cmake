# Helpers that give every project target the same flags, and every test the same main.

set(DSM_WARNINGS -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wno-psabi)

function(dsm_target_flags target)
  # -fopenmp-simd: `#pragma omp simd` marks loops (reductions) to vectorise; no OpenMP runtime.
  # -fno-math-errno: sqrt and the like need not set errno, so they vectorise (same values).
  target_compile_options(${target} PRIVATE ${DSM_WARNINGS} -fopenmp-simd -fno-math-errno)
  if(DSM_MARCH_NATIVE)
    target_compile_options(${target} PRIVATE -march=native)
  endif()
endfunction()

# dsm_library(NAME <name> SOURCES <files...> DEPS <targets...>)
# Creates dsm_<name>; headers are included as "dsm/<name>/file.h".
function(dsm_library)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;DEPS" ${ARGN})
  set(target dsm_${ARG_NAME})
  if(ARG_SOURCES)
    add_library(${target} STATIC ${ARG_SOURCES})
    target_include_directories(${target} PUBLIC ${PROJECT_SOURCE_DIR}/src)
    target_link_libraries(${target} PUBLIC ${ARG_DEPS})
    dsm_target_flags(${target})
  else()
    add_library(${target} INTERFACE)
    target_include_directories(${target} INTERFACE ${PROJECT_SOURCE_DIR}/src)
    target_link_libraries(${target} INTERFACE ${ARG_DEPS})
  endif()
endfunction()

# dsm_test(<folder>/<name> SOURCES <files...> DEPS <targets...> [LABELS <labels...>] [SPLIT <suite>]
#          [TIMEOUT <seconds>])
# The ctest name is <folder>/<name>; every test links the shared seeded test main. With SPLIT, each
# TEST(<suite>, <Case>) of the first source is a ctest of its own, <folder>/<name>/<Case>, so that
# long end-to-end cases spread over the cores (read from the source, which then is a configure
# dependency, so that no new case is left out).
function(dsm_test name)
  if(NOT DSM_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "SPLIT;TIMEOUT" "SOURCES;DEPS;LABELS" ${ARGN})
  string(REPLACE "/" "_" target ${name})
  add_executable(${target} ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE ${ARG_DEPS} dsm_test_main)
  dsm_target_flags(${target})
  set(tests ${name})
  if(ARG_SPLIT)
    list(GET ARG_SOURCES 0 source)
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${source})
    file(STRINGS ${source} cases REGEX "^TEST\\(${ARG_SPLIT}, [A-Za-z0-9_]+\\)")
    list(TRANSFORM cases REPLACE "^TEST\\(${ARG_SPLIT}, ([A-Za-z0-9_]+)\\).*" "\\1")
    set(tests "")
    foreach(case IN LISTS cases)
      add_test(NAME ${name}/${case} COMMAND ${target} --gtest_filter=${ARG_SPLIT}.${case})
      list(APPEND tests ${name}/${case})
    endforeach()
  else()
    add_test(NAME ${name} COMMAND ${target})
  endif()
  set(labels unit)
  if(ARG_LABELS)
    set(labels ${ARG_LABELS})
  endif()
  set_tests_properties(${tests} PROPERTIES LABELS "${labels}"
    ENVIRONMENT "DSM_SHARED_DATA=${DSM_SHARED_DATA_DIR};DSM_BINARY_DIR=${PROJECT_BINARY_DIR}")
  if(ARG_TIMEOUT)
    set_tests_properties(${tests} PROPERTIES TIMEOUT ${ARG_TIMEOUT})
  endif()
endfunction()

# dsm_benchmark(<folder>/<name> SOURCES <files...> DEPS <targets...>)
# A Google Benchmark program <folder>_<name> (not a test: speed is measured, never asserted).
function(dsm_benchmark name)
  if(NOT DSM_BUILD_BENCHMARKS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  find_package(benchmark REQUIRED)
  string(REPLACE "/" "_" target ${name})
  add_executable(${target} ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE ${ARG_DEPS} benchmark::benchmark)
  dsm_target_flags(${target})
endfunction()

# dsm_test_costs(<test> <seconds> [<test> <seconds>...])
# What a test takes, measured once (Release, one core): a parallel ctest starts the costly tests
# first, so that no long test runs alone at the end. A clean clone has no timing history to go by.
function(dsm_test_costs)
  while(ARGN)
    list(POP_FRONT ARGN test cost)
    if(TEST ${test})
      set_tests_properties(${test} PROPERTIES COST ${cost})
    endif()
  endwhile()
endfunction()
