#!/usr/bin/env bash
# Installs the Debian 12 packages SLAMBooster needs to build and test, when they are missing.
# Works as root (CI, containers) or through sudo. Says what it does; does nothing when all are present.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config   # toolchain
  libeigen3-dev libpng-dev nlohmann-json3-dev    # math, depth PNGs, JSON
  libspdlog-dev libfmt-dev libcli11-dev          # logging, formatting, command-line parsing
  catch2                                         # unit tests (v2)
  ocl-icd-opencl-dev opencl-headers pocl-opencl-icd  # OpenCL: ICD loader, headers, PoCL CPU device for tests
  clang                                          # OpenCL C syntax check of kernels/, fuzz targets
  libsystemd-dev systemd                         # daemon: sd_notify, socket activation; systemd-analyze verify
  libusb-1.0-0-dev                               # SmartPower (v1) HID meter
  libopenni2-dev                                 # live depth cameras
  liboctomap-dev                                 # navmap/: map.bt (optional: without it no map.bt)
  chromium                                       # report tests: render the HTML run report headless
  munge slurmctld slurmd slurm-client            # tests/tools/test_cluster.sh: the matrix as a Slurm array job
  parallel                                       # the matrix on GNU parallel (scripts/parallel_matrix.sh, its test)
  # ROS 1 (Debian 12 main), only for the optional ros/ component (slambooster_ros, the bag plugin) and its
  # tests against a real master; the daemon and the tool build without them. The ROS 2 headers that
  # rosbag/bag.h includes (pluginlib, class_loader, ...) come as dependencies of librosbag-dev.
  libroscpp-dev libtf2-ros-dev librosbag-dev     # roscpp, TF broadcaster/listener, the rosbag C++ API
  libnav-msgs-dev libsensor-msgs-dev libdiagnostic-msgs-dev libstd-msgs-dev  # the message types
  python3-rosmaster                              # the ROS master (rosmaster --core) the tests start
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#packages[@]} build/test packages are installed"
  exit 0
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then
    sudo_cmd=(sudo)
  else
    echo "install_deps: missing packages: ${missing[*]}" >&2
    echo "install_deps: run as root: apt-get update && apt-get install -y ${missing[*]}" >&2
    exit 1
  fi
fi

echo "install_deps: installing missing packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install_deps: done"
