# Detector benchmarks: NCC, colour and differencing per 640x480 frame (whole
# frame and windows, 5 target models) and SKS + PRCA fused.
if(TARGET hcpf::vision)
  hcpf_add_bench(detectors_bench SOURCES ${CMAKE_CURRENT_LIST_DIR}/detectors_bench.cc
                 DEPS hcpf::vision)
endif()
