# Benchmarks of metrics/: HOTA + CLEAR + Identity on a generated 2,000-frame x 30-object sequence.
hcpf_add_bench(metrics_bench SOURCES ${CMAKE_CURRENT_LIST_DIR}/metrics_bench.cc DEPS hcpf::metrics)
