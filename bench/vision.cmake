# Vision benchmarks: the stacked integral image blur against cv::GaussianBlur
# on a 640x480 8-bit grey frame, one core.
if(TARGET hcpf::vision)
  hcpf_add_bench(vision_bench
    SOURCES ${CMAKE_CURRENT_LIST_DIR}/vision_bench.cc
    DEPS hcpf::vision opencv_core opencv_imgproc)
endif()
