# Camera-motion evidence benchmarks: background corners tracked between two
# 640 x 480 frames of a moving camera, and the RANSAC similarity fitted to
# them (issue 12 items 2 and 3). OpenCV for the frame warp and
# cv::setNumThreads(1).
if(TARGET hcpf::vision)
  hcpf_add_bench(camera_motion_bench SOURCES ${CMAKE_CURRENT_LIST_DIR}/camera_motion_bench.cc
                 DEPS hcpf::vision opencv_core opencv_imgproc)
endif()
