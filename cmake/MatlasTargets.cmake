# Common compile settings for every matlas target.
add_library(matlas_options INTERFACE)
target_compile_options(matlas_options INTERFACE -Wall -Wextra -Wpedantic -Wshadow
                       -Wnon-virtual-dtor -Wcast-align)
target_compile_definitions(matlas_options INTERFACE MATLAS_VERSION="${PROJECT_VERSION}"
                           $<$<CONFIG:Debug>:MATLAS_DCHECKS>)
if(MATLAS_NATIVE)
  target_compile_options(matlas_options INTERFACE -march=native)
endif()
if(MATLAS_FUZZ)
  # Every library instrumented for libFuzzer's coverage and checked by ASan/UBSan; the fuzz
  # targets link the fuzzer's main (fuzz/CMakeLists.txt).
  target_compile_options(matlas_options INTERFACE -fsanitize=fuzzer-no-link,address,undefined
                         -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  target_link_options(matlas_options INTERFACE -fsanitize=address,undefined)
endif()
if(MATLAS_SANITIZE OR MATLAS_FUZZ)
  # The full invariant checks (core/check.h) where the sanitizers run.
  target_compile_definitions(matlas_options INTERFACE MATLAS_DCHECKS)
endif()
if(MATLAS_SANITIZE)
  target_compile_options(matlas_options INTERFACE -fsanitize=address,undefined
                         -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  target_link_options(matlas_options INTERFACE -fsanitize=address,undefined)
endif()

# matlas_module(NAME DEPS...): one static library per concern folder (src/NAME), built from every
# .cpp file there. Its headers are included as "NAME/file.h" from src/.
function(matlas_module name)
  cmake_parse_arguments(ARG "" "" "DEPS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  if(sources)
    add_library(matlas_${name} STATIC ${sources})
    target_include_directories(matlas_${name} PUBLIC ${PROJECT_SOURCE_DIR}/src)
    target_link_libraries(matlas_${name} PUBLIC ${ARG_DEPS} PRIVATE matlas_options)
    add_library(matlas::${name} ALIAS matlas_${name})
  else()  # header-only (or not yet written) concern
    add_library(matlas_${name} INTERFACE)
    target_include_directories(matlas_${name} INTERFACE ${PROJECT_SOURCE_DIR}/src)
    target_link_libraries(matlas_${name} INTERFACE ${ARG_DEPS})
  endif()
endfunction()

# matlas_test_suite(NAME DEPS... [SHARED_FIXTURES SUITE...]): one GoogleTest executable per folder
# tests/NAME; every test is one ctest test, except the GoogleTest suites named in SHARED_FIXTURES,
# which run as one ctest test each (named after the suite) so that what their fixture loads once
# (real data files) is shared by all their tests instead of being loaded again per process.
function(matlas_test_suite name)
  cmake_parse_arguments(ARG "" "" "DEPS;SHARED_FIXTURES" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  add_executable(matlas_${name}_tests ${sources})
  target_include_directories(matlas_${name}_tests PRIVATE ${PROJECT_SOURCE_DIR}/tests)
  target_link_libraries(matlas_${name}_tests PRIVATE ${ARG_DEPS} matlas_test_support
                        GTest::gtest_main matlas_options)
  set(shared "")
  foreach(suite ${ARG_SHARED_FIXTURES})
    list(APPEND shared "${suite}.*")
    add_test(NAME ${suite} COMMAND matlas_${name}_tests --gtest_filter=${suite}.*)
    set_tests_properties(${suite} PROPERTIES LABELS ${name})
  endforeach()
  set(separate "*")
  if(shared)
    list(JOIN shared ":" shared)
    set(separate "-${shared}")
  endif()
  gtest_discover_tests(matlas_${name}_tests DISCOVERY_TIMEOUT 60 TEST_FILTER "${separate}"
                       PROPERTIES LABELS ${name})
endfunction()
