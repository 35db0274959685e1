# PRCA detector benchmarks: time per 640x480 frame with 1 and 5 target models,
# whole-frame and windowed, and the scene clustering alone.
if(TARGET hcpf::vision)
  hcpf_add_bench(prca_bench SOURCES ${CMAKE_CURRENT_LIST_DIR}/prca_bench.cc DEPS hcpf::vision)
endif()
