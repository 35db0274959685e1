# Benchmarks of studies/: sweep expansion (seeds reseeded from each cell's first run).
hcpf_add_bench(studies_bench SOURCES ${CMAKE_CURRENT_LIST_DIR}/studies_bench.cc DEPS hcpf::studies)
target_compile_definitions(studies_bench PRIVATE HCPF_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
