# Detector benchmarks: NCC, colour and differencing per 640x480 frame (whole
# frame and windows, 5 target models) and SKS + PRCA fused. OpenCV only for
# cv::setNumThreads(1).
if(TARGET hcpf::vision)
  hcpf_add_bench(detectors_bench SOURCES ${CMAKE_CURRENT_LIST_DIR}/detectors_bench.cc
                 DEPS hcpf::vision opencv_core)
endif()

# The Detector contract's cost clause: every detector on frames of 1, 4 and 9
# times 640x480 pixels, with a linear fit (time per pixel and its RMS).
# OpenCV only for cv::setNumThreads(1).
if(TARGET hcpf::vision)
  hcpf_add_bench(detector_cost_bench SOURCES ${CMAKE_CURRENT_LIST_DIR}/detector_cost_bench.cc
                 DEPS hcpf::vision opencv_core)
endif()
