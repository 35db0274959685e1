#!/usr/bin/env bash
# Installs every Debian 12 package HCPF Bench needs, if any is missing.
# Idempotent: when everything is present it only runs one dpkg query (well
# under a second). Must run as root (or with sudo available) on Debian 12.
set -euo pipefail

PACKAGES=(
  # toolchain
  g++ cmake ninja-build pkg-config git ca-certificates
  # core, scenarios, cli
  libeigen3-dev libfmt-dev libspdlog-dev libyaml-cpp-dev libcli11-dev nlohmann-json3-dev
  libsqlite3-dev libxxhash-dev
  # tracker / renderer / videos
  libopencv-dev
  # overlay videos: H.264 through FFmpeg (libavcodec59 brings libx264)
  libavcodec-dev libavformat-dev libavutil-dev libswscale-dev
  libosmesa6-dev libegl-dev libgl-dev libegl-mesa0 libgles-dev mesa-common-dev
  libassimp-dev libtinygltf-dev libstb-dev libpng-dev libjpeg-dev libzstd-dev
  # tests and benchmarks; clang-format checks the formatting in CI
  googletest libgtest-dev libgmock-dev libbenchmark-dev clang-format
  # fuzzing: clang with libFuzzer and the sanitizer runtimes (scripts/fuzz.sh)
  clang libclang-rt-14-dev
  # reports: plots; headless Chromium checks the HTML report in the tests
  gnuplot-nox chromium
  # the MPI sweep executor (mpirun -n R hcpf sweep; docs/sweeps.md)
  openmpi-bin libopenmpi-dev
  # external trackers: the SORT example (examples/trackers/, /usr/bin/python3)
  python3 python3-numpy
)

missing=()
while IFS= read -r line; do
  missing+=("$line")
done < <(dpkg-query -W -f='${Package} ${Status}\n' "${PACKAGES[@]}" 2>&1 |
           awk '/no packages found matching/ {print $NF; next} $NF != "installed" {print $1}')

if [ "${#missing[@]}" -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} Debian packages present"
  exit 0
fi

echo "setup: installing ${#missing[@]} missing package(s): ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
# Refresh the package lists only when they are absent or an install fails.
if ! compgen -G "/var/lib/apt/lists/*_Packages" > /dev/null; then
  $SUDO apt-get update -qq
fi
if ! $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"; then
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
echo "setup: done"
