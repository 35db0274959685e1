#!/usr/bin/env bash
# Command (1) of the README: install what is missing, build the release
# binary, run the main job on the default scenario, print where its outputs are.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake --preset release > /dev/null
cmake --build --preset release -j "$(nproc)"
out="out/crossing-dominant"
./build/release/cli/hcpf run scenarios/library/crossing-dominant.yaml --out "$out"
echo "outputs: $(pwd)/$out"
