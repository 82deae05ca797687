#!/usr/bin/env bash
# Cross-builds SLAMBooster for the ODROID XU4 (armhf) and writes slambooster_<version>_armhf.deb.
#
#   cross-toolchain/build_deb.sh [BUILD_DIR]     # default: build-armhf in the checkout
#
# Steps: prepares the host when something is missing (cross-toolchain/prepare_host.sh: root or sudo), configures
# BUILD_DIR with the armhf toolchain file (Release; the toolchain adds the CPU and hardening flags), builds
# what the package ships, and runs CPack's DEB generator. Prints the path of the .deb on the last line.
# Re-running rebuilds only what changed (ccache is used when installed).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-"$root/build-armhf"}
say() { echo "build_deb: $*"; }

"$root/cross-toolchain/prepare_host.sh"

launcher=()
if command -v ccache >/dev/null 2>&1; then
  launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
say "configuring $build (armhf, Release)"
cmake -S "$root" -B "$build" -G Ninja \
  -DCMAKE_TOOLCHAIN_FILE="$root/cross-toolchain/toolchain-armhf.cmake" \
  -DCMAKE_BUILD_TYPE=Release \
  "${launcher[@]}" >/dev/null

# The executables the package ships (cross-toolchain/packaging.cmake installs them and the rest).
targets=(slambooster slamboosterd slamboosterctl)
say "building ${targets[*]}"
cmake --build "$build" -j "$(nproc)" --target "${targets[@]}"

say "packaging (CPack DEB)"
rm -f "$build"/deb/slambooster_*.deb
# dpkg-shlibdeps computes Depends: for the target architecture's libraries (multiarch armhf).
arch=$(sed -n 's/^set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE "\(.*\)")$/\1/p' "$build/CPackConfig.cmake")
(cd "$build" && DEB_HOST_ARCH="$arch" cpack -G DEB --config CPackConfig.cmake >cpack.log 2>&1) || {
  cat "$build/cpack.log" >&2
  say "cpack failed (log above, also in $build/cpack.log)" >&2
  exit 1
}
deb=$(ls "$build"/deb/slambooster_*_"$arch".deb)
say "package: $(dpkg-deb -f "$deb" Package) $(dpkg-deb -f "$deb" Version) $(dpkg-deb -f "$deb" Architecture)"
echo "$deb"
