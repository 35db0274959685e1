#!/usr/bin/env bash
# Command (1) of the README: install what is missing, build the release
# binary, run the main job on the default scenario, print where its outputs are.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake --preset release > /dev/null
cmake --build --preset release -j "$(nproc)"
# The main job: the default sweep (crossing with a dominant target, particles x
# {systematic, charged} x 20 seeds) and its report. Re-running reuses finished runs;
# after an update whose runs have other keys, the old folder is renamed
# out/default.before-<time> and its runs still valid are copied (--move-aside,
# docs/sweeps.md).
out="out/default"
./build/release/cli/hcpf sweep scenarios/sweeps/default.yaml --out "$out" --move-aside
./build/release/cli/hcpf report "$out"
echo "report: $(pwd)/$out/report.html (results: $out/results.sqlite, $out/summary.csv)"
