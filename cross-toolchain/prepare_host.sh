#!/usr/bin/env bash
# Prepares a Debian 12 (bookworm) amd64 host to cross-build SLAMBooster for the ODROID XU4 (armhf), package
# it, and run the armhf unit tests under qemu-arm (architecture.md D9).
#
# What it does, each step only when needed (running it twice changes nothing the second time):
#   1. dpkg --add-architecture armhf
#   2. apt-get update (only when the armhf package lists are missing or a package is missing)
#   3. pins the packages that must carry the same version on amd64 and armhf (Multi-Arch: same, e.g.
#      liblzma5, libsystemd0, libudev1) to one version available for both, in
#      /etc/apt/preferences.d/slambooster-multiarch. This copes with an armhf security/updates index that is
#      out of sync with amd64 (or a host installed from another snapshot): instead of failing, apt installs
#      the version both architectures have, upgrading or downgrading the host's copy when it must.
#   4. installs the cross toolchain, qemu-user, the packaging/lint tools, and the armhf -dev libraries, then
#      removes the pin file again, so that it does not hold back later security updates of the host.
#
# Which libraries need their :armhf package: only those with compiled code or arch-specific files
# (libpng, zlib, spdlog, fmt, libsystemd, libusb, OpenNI2, the OpenCL ICD loader). Eigen, nlohmann-json,
# CLI11 and the OpenCL headers are Architecture: all; the amd64 catch2 package is Multi-Arch: foreign and
# only its header (catch.hpp) is used. No armhf OpenCL runtime (PoCL) is installed: it cannot be
# co-installed with the host one, and the armhf tests run on the CPU backend.
#
# Works as root (CI, containers) or through sudo. Exits non-zero, naming the package, on a real failure.
set -euo pipefail

say() { echo "prepare_host: $*"; }

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then
    sudo_cmd=(sudo)
  else
    say "needs root: run it as root or install sudo" >&2
    exit 1
  fi
fi
as_root() { "${sudo_cmd[@]}" "$@"; }
export DEBIAN_FRONTEND=noninteractive

host_arch=$(dpkg --print-architecture)
if [ "$host_arch" != amd64 ]; then
  say "host architecture is $host_arch; this script prepares an amd64 Debian 12 host" >&2
  exit 1
fi

# Host tools (native architecture).
host_packages=(
  crossbuild-essential-armhf   # arm-linux-gnueabihf-gcc/g++, armhf libc6-dev
  cmake ninja-build pkg-config ccache
  qemu-user                    # qemu-arm: runs the armhf test binaries (plain, without -L)
  dpkg-dev fakeroot            # dpkg-shlibdeps, dpkg-deb for CPack's DEB generator
  lintian                      # package checks (tests/packaging)
  systemd                      # systemd-analyze verify of the packaged unit
  libeigen3-dev nlohmann-json3-dev libcli11-dev catch2 opencl-headers  # Architecture: all / header-only
)
# Target libraries (armhf).
armhf_packages=(
  libpng-dev:armhf zlib1g-dev:armhf   # depth PNGs
  libspdlog-dev:armhf libfmt-dev:armhf
  libsystemd-dev:armhf                # daemon: sd_notify, socket activation
  libusb-1.0-0-dev:armhf              # SmartPower (v1) HID meter
  libopenni2-dev:armhf                # live depth cameras
  ocl-icd-opencl-dev:armhf            # OpenCL ICD loader (the board's Mali driver provides the device)
)

installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }

# 1. armhf as a foreign architecture.
if ! dpkg --print-foreign-architectures | grep -qx armhf; then
  say "adding the armhf architecture (dpkg --add-architecture armhf)"
  as_root dpkg --add-architecture armhf
  need_update=1
fi

missing=()
for p in "${host_packages[@]}" "${armhf_packages[@]}"; do
  installed "$p" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  say "all ${#host_packages[@]} host and ${#armhf_packages[@]} armhf packages are installed; nothing to do"
  exit 0
fi

# 2. Package lists (armhf ones are missing right after adding the architecture).
if [ "${need_update:-0}" = 1 ] || ! compgen -G "/var/lib/apt/lists/*_binary-armhf_Packages*" >/dev/null; then
  say "apt-get update (armhf package lists)"
else
  say "apt-get update (packages missing: ${missing[*]})"
fi
# A security/updates index for armhf that is out of sync with its Release file ("File has unexpected size
# ... Mirror sync in progress?") makes apt-get update fail although every other list is fine. Go on without
# that one list (apt keeps the rest; step 3 then picks versions both architectures still offer); fail only
# when a list of the host architecture could not be fetched.
update_log=$(mktemp)
pin_file=/etc/apt/preferences.d/slambooster-multiarch
trap 'rm -f "$update_log"; [ ! -f "$pin_file" ] || as_root rm -f "$pin_file"' EXIT
if ! as_root apt-get update -qq >"$update_log" 2>&1; then
  cat "$update_log" >&2
  failed=$(grep -E '^(E|W): Failed to fetch' "$update_log" || true)
  if [ -z "$failed" ] || grep -qv 'binary-armhf' <<<"$failed"; then
    say "apt-get update failed (see above); fix the sources or the network and re-run" >&2
    exit 1
  fi
  say "WARNING: these armhf package lists are out of sync on the mirror and were left out:"
  grep -oE 'https?://[^ ]*binary-armhf[^ ]*' <<<"$failed" | sed 's/^/prepare_host:   /'
  say "going on with the other lists; re-run later to pick up the armhf updates"
fi

# 3. Version skew. A Multi-Arch: same package must carry one version on both architectures; when the host has
# a version the armhf lists do not offer (an index out of sync, or a host installed from another snapshot),
# apt refuses ("held broken packages"). For each such package choose one version: the host's when armhf
# offers it (nothing on the host changes), else the newest version both lists offer, and pin it, together
# with the host's packages built from the same source (systemd depends on libsystemd0 of its own version).
# The packages architecture.md D9 names are pinned up front; others are found by a dry run of the install.
versions_for() { # package arch -> available versions, one per line
  apt-cache madison "$1:$2" 2>/dev/null | awk -F'|' -v p="$1" -v a="$1:$2" '{gsub(/ /,"",$1); gsub(/ /,"",$2); if ($1==p || $1==a) print $2}' | sort -u
}
declare -A pinned=()
pin_package() { # package -> adds pins for it and its same-source siblings; fails when no common version
  local lead=$1 amd arm current chosen src p
  amd=$(versions_for "$lead" amd64)
  arm=$(versions_for "$lead" armhf)
  current=$(dpkg-query -W -f='${Version}' "$lead:amd64" 2>/dev/null || true)
  if [ -n "$current" ] && grep -qxF "$current" <<<"$arm"; then
    chosen=$current
  else
    chosen=$(comm -12 <(echo "$amd") <(echo "$arm") | sort -V | tail -n1)
    if [ -z "$chosen" ]; then
      say "no version of $lead is offered for both amd64 ($(echo $amd)) and armhf ($(echo $arm))" >&2
      say "check /etc/apt/sources.list* (the armhf lists must come from the same mirror and suites)" >&2
      exit 1
    fi
    say "version skew: $lead is ${current:-not installed} on the host, armhf offers $(echo $arm); using $chosen on both"
  fi
  src=$(apt-cache show "$lead=$chosen" 2>/dev/null | awk '/^Source:/ && !s {s=$2} END {print s}')
  src=${src:-$lead}
  pinned[$lead]=$chosen
  [ "$chosen" != "$current" ] || return 0
  # The host's version changes: the host packages of the same source and version that must move with it
  # (Multi-Arch: same ones, and those depending on exactly this version, like systemd on libsystemd0).
  for p in $(dpkg-query -W -f='${db:Status-Abbrev}|${source:Package}|${Version}|${Package}|${Multi-Arch}|${Depends}, ${Pre-Depends}\n' 2>/dev/null |
             awk -F'|' -v s="$src" -v v="$current" '$1 ~ /^ii/ && $2==s && $3==v && ($5=="same" || index($6, "(= " v ")")) {print $4}'); do
    pinned[$p]=$chosen
  done
}
write_pins() {
  local body p
  body="# Written by SLAMBooster's cross-toolchain/prepare_host.sh while it installs the armhf packages (and
# removed when it exits): Multi-Arch: same packages must carry one version on amd64 and armhf.
"
  for p in $(printf '%s\n' "${!pinned[@]}" | sort); do
    body+="
Package: $p:amd64 $p:armhf
Pin: version ${pinned[$p]}
Pin-Priority: 1001
"
  done
  if [ ! -f "$pin_file" ] || [ "$(cat "$pin_file")" != "$(printf '%s' "$body")" ]; then
    say "writing $pin_file:"
    for p in $(printf '%s\n' "${!pinned[@]}" | sort); do say "  $p (amd64 and armhf) = ${pinned[$p]}"; done
    printf '%s' "$body" | as_root tee "$pin_file" >/dev/null
  fi
}
for p in liblzma5 libsystemd0 libudev1; do pin_package "$p"; done
install_args=(-y --no-install-recommends --no-remove --allow-downgrades)
for attempt in 1 2 3 4 5 6 7 8; do
  write_pins
  if dry=$(apt-get install -s "${install_args[@]}" "${missing[@]}" 2>&1); then
    break
  fi
  # "libpng-dev:armhf : Depends: libpng16-16:armhf (= 1.6.39-2+deb12u5) but it is not going to be installed"
  new=()
  for p in $(grep -oE '^ *[^ ]+:armhf : |Depends: [^ ]+:armhf' <<<"$dry" | sed -E 's/^ *(Depends: )?//; s/:armhf.*//' | sort -u); do
    if [ -z "${pinned[$p]:-}" ] && dpkg-query -W -f='${Multi-Arch}' "$p:amd64" 2>/dev/null | grep -qx same; then
      new+=("$p")
    fi
  done
  if [ ${#new[@]} -eq 0 ] || [ "$attempt" = 8 ]; then
    echo "$dry" >&2
    say "apt cannot install the packages above, and no version skew explains it; see apt's message" >&2
    exit 1
  fi
  for p in "${new[@]}"; do pin_package "$p"; done
done

# 4. Install.
say "installing: ${missing[*]}"
as_root apt-get install -qq "${install_args[@]}" "${missing[@]}"
say "done: arm-linux-gnueabihf-g++ $(arm-linux-gnueabihf-g++ -dumpversion), $(qemu-arm --version | head -n1)"
