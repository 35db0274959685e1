# hcpf_add_library(<module> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Creates target hcpf_<module> with alias hcpf::<module>; public headers live in
# <module>/include/hcpf/<module>/, sources and private headers in <module>/src/.
function(hcpf_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wno-missing-field-initializers)
  if(HCPF_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

function(hcpf_add_library module)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(hcpf_${module} STATIC ${ARG_SOURCES})
  add_library(hcpf::${module} ALIAS hcpf_${module})
  target_include_directories(hcpf_${module}
    PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include
    PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
  target_link_libraries(hcpf_${module} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  target_compile_features(hcpf_${module} PUBLIC cxx_std_20)
  hcpf_set_warnings(hcpf_${module})
endfunction()

# hcpf_add_test(<name> SOURCES ... [DEPS ...] [LABELS unit|gl|e2e|slow ...] [TIMEOUT s])
# One GoogleTest executable, every TEST registered with CTest under the labels.
function(hcpf_add_test name)
  if(NOT HCPF_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "TIMEOUT" "SOURCES;DEPS;LABELS" ${ARGN})
  if(NOT ARG_LABELS)
    set(ARG_LABELS unit)
  endif()
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 600)
  endif()
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gmock GTest::gtest_main)
  # Shared test helpers: #include "support/..." (tests/support/).
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/tests)
  target_compile_definitions(${name} PRIVATE
    HCPF_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    HCPF_BINARY_DIR="${PROJECT_BINARY_DIR}"
    HCPF_CONFORMANCE_DEFAULT_DIR="${PROJECT_SOURCE_DIR}/../shared/conformance/mot")
  hcpf_set_warnings(${name})
  gtest_discover_tests(${name}
    PROPERTIES LABELS "${ARG_LABELS}" TIMEOUT ${ARG_TIMEOUT}
    DISCOVERY_TIMEOUT 60)
endfunction()

# hcpf_add_bench(<name> SOURCES ... [DEPS ...]): a Google Benchmark program in bench/.
function(hcpf_add_bench name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} benchmark::benchmark benchmark::benchmark_main)
  hcpf_set_warnings(${name})
endfunction()

if(HCPF_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()
