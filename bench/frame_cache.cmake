# Frame cache: encoding and decoding one rendered frame in the cache's format
# against PNG (issue 13 item 2), on a frame rendered by the renderer; and the
# per-frame digest of the manifests' frame_digests.
if(TARGET hcpf::renderer AND TARGET hcpf::scenarios)
  hcpf_add_bench(frame_cache_bench
    SOURCES ${CMAKE_CURRENT_LIST_DIR}/frame_cache_bench.cc
    DEPS hcpf::renderer hcpf::scenarios)
  target_compile_definitions(frame_cache_bench PRIVATE HCPF_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  # BM_ProgramDigest reads the detection cache's private header.
  target_include_directories(frame_cache_bench PRIVATE ${PROJECT_SOURCE_DIR}/scenarios/src)
endif()
