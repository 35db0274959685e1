# Sweeps, the results store, reports, the regression gate and overlay videos
# (included from scenarios/CMakeLists.txt).
target_sources(hcpf_scenarios PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/src/sweep.cc
  ${CMAKE_CURRENT_LIST_DIR}/src/sweep_run.cc
  ${CMAKE_CURRENT_LIST_DIR}/src/results_store.cc
  ${CMAKE_CURRENT_LIST_DIR}/src/report.cc
  ${CMAKE_CURRENT_LIST_DIR}/src/regress.cc
  ${CMAKE_CURRENT_LIST_DIR}/src/overlay.cc)
target_link_libraries(hcpf_scenarios PRIVATE SQLite::SQLite3)

hcpf_add_test(scenarios_sweep_tests
  SOURCES
    ${CMAKE_CURRENT_LIST_DIR}/tests/sweep_test.cc
    ${CMAKE_CURRENT_LIST_DIR}/tests/results_store_test.cc
    ${CMAKE_CURRENT_LIST_DIR}/tests/report_test.cc
    ${CMAKE_CURRENT_LIST_DIR}/tests/regress_test.cc
    ${CMAKE_CURRENT_LIST_DIR}/tests/overlay_test.cc
  DEPS hcpf::scenarios ${OpenCV_LIBS}
  LABELS unit)
if(TARGET scenarios_sweep_tests)
  # White-box tests of private helpers (src/text.h).
  target_include_directories(scenarios_sweep_tests PRIVATE ${CMAKE_CURRENT_LIST_DIR}/src)
endif()
