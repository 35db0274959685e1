# Every dependency comes from a Debian package (scripts/setup.sh installs them);
# nothing is downloaded at configure time.
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(fmt REQUIRED)
find_package(spdlog REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(SQLite3 REQUIRED)
# Libraries link opencv_core/opencv_imgproc (vision/ also video and calib3d,
# about 25 shared libraries each, mostly shared with imgproc): imgcodecs and videoio pull
# in ~100 shared libraries (GDAL, HDF5, FFmpeg) that cost every process
# ~60 ms to load; PNG/JPEG go through libpng/libjpeg, video through a plugin.
find_package(OpenCV REQUIRED COMPONENTS core imgproc imgcodecs videoio video calib3d)
find_package(PkgConfig REQUIRED)
pkg_check_modules(PNG REQUIRED IMPORTED_TARGET libpng)
pkg_check_modules(JPEG REQUIRED IMPORTED_TARGET libjpeg)
pkg_check_modules(ZSTD REQUIRED IMPORTED_TARGET libzstd)
pkg_check_modules(XXHASH REQUIRED IMPORTED_TARGET libxxhash)
# FFmpeg, for the overlay videos (scenarios/src/video_plugin.cc).
pkg_check_modules(AVCODEC REQUIRED IMPORTED_TARGET libavcodec)
pkg_check_modules(AVFORMAT REQUIRED IMPORTED_TARGET libavformat)
pkg_check_modules(AVUTIL REQUIRED IMPORTED_TARGET libavutil)
pkg_check_modules(SWSCALE REQUIRED IMPORTED_TARGET libswscale)
find_package(Threads REQUIRED)
find_package(TinyGLTF REQUIRED)
find_package(assimp REQUIRED)
pkg_check_modules(OSMESA REQUIRED IMPORTED_TARGET osmesa)
pkg_check_modules(EGL REQUIRED IMPORTED_TARGET egl)
pkg_check_modules(GL REQUIRED IMPORTED_TARGET gl)
if(HCPF_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(HCPF_BUILD_BENCH)
  find_package(benchmark REQUIRED)
endif()
