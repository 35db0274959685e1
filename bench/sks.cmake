# SKS detector benchmark: time per 640 x 480 frame with 5 target models, whole
# frame and windowed (issue 11 item 3). OpenCV only for cv::setNumThreads(1).
if(TARGET hcpf::vision)
  hcpf_add_bench(sks_bench SOURCES ${CMAKE_CURRENT_LIST_DIR}/sks_bench.cc
                 DEPS hcpf::vision opencv_core)
endif()
