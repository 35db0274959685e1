# Renderer benchmarks: frames per second of a 640x480 scene with shadows, the
# realistic issue-13 scene end to end, the sensor effects alone, and
# the cost of the ground-truth passes. It rasterises on the drawing thread, as
# hcpf does (LP_NUM_THREADS=0 unless set): the one-core figure.
if(TARGET hcpf::renderer)
  hcpf_add_bench(renderer_bench
    SOURCES ${CMAKE_CURRENT_LIST_DIR}/renderer_bench.cc
    DEPS hcpf::renderer fmt::fmt)
  target_compile_definitions(renderer_bench PRIVATE HCPF_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
endif()
