# End-to-end tests of hcpf sweep / merge / report / regress / export (included from tests/CMakeLists.txt).
hcpf_add_test(e2e_sweep_tests
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/sweep_test.cc ${CMAKE_CURRENT_LIST_DIR}/export_test.cc
  DEPS hcpf::core SQLite::SQLite3 nlohmann_json::nlohmann_json ${OpenCV_LIBS}
  LABELS e2e
  TIMEOUT 600)
target_include_directories(e2e_sweep_tests PRIVATE ${CMAKE_CURRENT_LIST_DIR}/..)
target_compile_definitions(e2e_sweep_tests PRIVATE HCPF_EXE="$<TARGET_FILE:hcpf>")
add_dependencies(e2e_sweep_tests hcpf)

if(HCPF_GL_TESTS)
  hcpf_add_test(e2e_sweep_rendered_tests
    SOURCES ${CMAKE_CURRENT_LIST_DIR}/sweep_rendered_test.cc
    DEPS hcpf::core
    LABELS e2e gl
    TIMEOUT 600)
  target_include_directories(e2e_sweep_rendered_tests PRIVATE ${CMAKE_CURRENT_LIST_DIR}/..)
  target_compile_definitions(e2e_sweep_rendered_tests PRIVATE HCPF_EXE="$<TARGET_FILE:hcpf>")
  add_dependencies(e2e_sweep_rendered_tests hcpf)
endif()

# The MPI executor under `mpirun --oversubscribe -n 3`, when MPI and mpirun
# were found (studies/CMakeLists.txt builds the executor then).
find_package(MPI COMPONENTS C QUIET)
if(HCPF_MPI AND MPI_C_FOUND AND MPIEXEC_EXECUTABLE)
  hcpf_add_test(e2e_sweep_mpi_tests
    SOURCES ${CMAKE_CURRENT_LIST_DIR}/sweep_mpi_test.cc
    DEPS hcpf::core SQLite::SQLite3
    LABELS e2e
    TIMEOUT 300)
  target_include_directories(e2e_sweep_mpi_tests PRIVATE ${CMAKE_CURRENT_LIST_DIR}/..)
  target_compile_definitions(e2e_sweep_mpi_tests PRIVATE HCPF_EXE="$<TARGET_FILE:hcpf>"
                                                         HCPF_MPIEXEC="${MPIEXEC_EXECUTABLE}")
  add_dependencies(e2e_sweep_mpi_tests hcpf)
endif()
