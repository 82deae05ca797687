# CMake toolchain file: cross-compile SLAMBooster on a Debian 12 amd64 host for the ODROID XU4 (Exynos 5422:
# 4x Cortex-A15 + 4x Cortex-A7, NEON/VFPv4, hard-float ABI), architecture.md D9.
#
#   cross-toolchain/prepare_host.sh      # once: multiarch armhf, cross g++, the :armhf -dev packages
#   cmake -S . -B build-armhf -G Ninja -DCMAKE_TOOLCHAIN_FILE=cross-toolchain/toolchain-armhf.cmake
#
# Libraries come from Debian multiarch (/usr/lib/arm-linux-gnueabihf, /usr/include/arm-linux-gnueabihf);
# header-only Architecture: all packages (Eigen, nlohmann-json, CLI11, Catch2's header) from /usr.
# Test binaries run through plain `qemu-arm` (CMAKE_CROSSCOMPILING_EMULATOR), which finds the armhf
# loader and libraries at their multiarch paths. Not `qemu-arm -L /usr/arm-linux-gnueabihf`: that mixes the
# cross toolchain's C library with the multiarch one and crashes.

set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR armv7l)
set(SB_CROSS_TRIPLET arm-linux-gnueabihf)

set(CMAKE_C_COMPILER ${SB_CROSS_TRIPLET}-gcc)
set(CMAKE_CXX_COMPILER ${SB_CROSS_TRIPLET}-g++)
set(CMAKE_LIBRARY_ARCHITECTURE ${SB_CROSS_TRIPLET})

# Exynos 5422 big.LITTLE tuning; -Wno-psabi silences GCC's notes about the ARM parameter-passing ABI change
# of GCC 7 (nothing here links against code built by older compilers).
set(SB_ARMHF_FLAGS "-mcpu=cortex-a15.cortex-a7 -mfpu=neon-vfpv4 -mfloat-abi=hard -Wno-psabi")
# The board build is the deployable one: Debian's hardening for a service too (fortified libc calls, full
# RELRO with immediate binding); neither changes the generated math.
set(CMAKE_C_FLAGS_INIT "${SB_ARMHF_FLAGS} -D_FORTIFY_SOURCE=2")
set(CMAKE_CXX_FLAGS_INIT "${SB_ARMHF_FLAGS} -D_FORTIFY_SOURCE=2")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-Wl,-z,relro,-z,now")
set(CMAKE_SHARED_LINKER_FLAGS_INIT "-Wl,-z,relro,-z,now")

# Search roots: the cross toolchain's own tree, then the host root, where find_library and find_package look
# in the multiarch directories first (lib/arm-linux-gnueabihf, lib/arm-linux-gnueabihf/cmake). Programs
# (compilers' helpers, code generators) are host programs. The few non-multiarch amd64 files in /usr/lib
# (e.g. libCatch2WithMain.a) must never be linked into armhf binaries: those directories are ignored.
set(CMAKE_FIND_ROOT_PATH /usr/${SB_CROSS_TRIPLET} /)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
set(CMAKE_IGNORE_PATH /usr/lib /lib /usr/lib/x86_64-linux-gnu /lib/x86_64-linux-gnu /usr/local/lib
  /usr/include/x86_64-linux-gnu)

# pkg-config (libsystemd, libusb, OpenNI2): the armhf .pc files, never the amd64 ones.
set(ENV{PKG_CONFIG_LIBDIR} "/usr/lib/${SB_CROSS_TRIPLET}/pkgconfig:/usr/share/pkgconfig")
set(ENV{PKG_CONFIG_PATH} "")

# ctest runs armhf test binaries under user-mode emulation.
find_program(SB_QEMU_ARM qemu-arm)
if(SB_QEMU_ARM)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${SB_QEMU_ARM})
endif()
