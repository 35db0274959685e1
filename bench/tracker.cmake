# Tracker benchmarks: resamplers, one filter step, charged vs systematic, and
# the time per frame of the whole bank over N x K.
if(TARGET hcpf::tracker)
  hcpf_add_bench(tracker_bench SOURCES tracker_bench.cc DEPS hcpf::tracker)
endif()
