# The slambooster Debian package (architecture.md D9): install rules for what the package ships besides the
# targets that install themselves, and the CPack DEB configuration. Included at the end of the top-level
# CMakeLists.txt, so every target exists by then. Every part listed below is built and shipped; a missing
# file fails the install step, naming it.
#
#   cross-toolchain/build_deb.sh        # cross-build for armhf and write slambooster_<version>_armhf.deb
#   cpack -G DEB --config <build>/CPackConfig.cmake   # the same for any configured build (its architecture)
#
# Layout of the package:
#   /usr/bin/slambooster, /usr/bin/slamboosterctl   the offline tool and the socket client
#   /usr/sbin/slamboosterd                          the daemon (daemon/CMakeLists.txt installs it)
#   /etc/slambooster/*.json                         default configuration, conffiles (upgrades keep edits)
#   /lib/systemd/system/slambooster.{service,socket} the unit (systemd/), neither enabled nor started
#   /lib/udev/rules.d/60-slambooster.rules          meters and depth cameras for the service's groups
#   /usr/share/doc/slambooster/{copyright,changelog.gz}, /usr/share/lintian/overrides/slambooster
# The maintainer scripts (cross-toolchain/debian/) create the system user `slambooster` (groups dialout,
# plugdev, video) and enable nothing.

set(SB_PKG_DIR ${CMAKE_CURRENT_LIST_DIR})
set(SB_DEB_MAINTAINER "SLAMBooster maintainers <slambooster@example.org>" CACHE STRING
  "Maintainer field of the .deb (name <email>)")

# Executables that do not install themselves (slamboosterd does: daemon/CMakeLists.txt).
install(TARGETS slambooster slamboosterctl RUNTIME DESTINATION bin)

# Default configuration: conffiles, so dpkg keeps a user-edited copy on upgrade (and asks when both changed).
# config/controller.json is not shipped: the daemon's controllers run on their built-in defaults unless
# slam.controller_config names a file.
set(SB_CONFFILES "")
foreach(cfg slamboosterd.json power.json pipeline.json)
  install(FILES ${PROJECT_SOURCE_DIR}/config/${cfg} DESTINATION /etc/slambooster)
  string(APPEND SB_CONFFILES "/etc/slambooster/${cfg}\n")
endforeach()
file(WRITE ${CMAKE_BINARY_DIR}/deb/conffiles "${SB_CONFFILES}")

# systemd units (systemd/): the daemon's service and its socket.
install(FILES ${PROJECT_SOURCE_DIR}/systemd/slambooster.service
  ${PROJECT_SOURCE_DIR}/systemd/slambooster.socket DESTINATION /lib/systemd/system)

install(FILES ${SB_PKG_DIR}/udev/60-slambooster.rules DESTINATION /lib/udev/rules.d)

# Debian documentation files: copyright, a changelog (native package: changelog.gz, compressed with -n for
# reproducible bytes), lintian overrides (each with its reason).
string(TIMESTAMP SB_DEB_DATE "%a, %d %b %Y %H:%M:%S +0000" UTC)
configure_file(${SB_PKG_DIR}/debian/changelog.in ${CMAKE_BINARY_DIR}/deb/changelog @ONLY)
function(sb_gzip_for_deb input output)
  execute_process(COMMAND gzip -9nc ${input} OUTPUT_FILE ${output} RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "gzip of ${input} into ${output} failed (${result})")
  endif()
endfunction()
sb_gzip_for_deb(${CMAKE_BINARY_DIR}/deb/changelog ${CMAKE_BINARY_DIR}/deb/changelog.gz)
install(FILES ${SB_PKG_DIR}/debian/copyright ${CMAKE_BINARY_DIR}/deb/changelog.gz
  DESTINATION share/doc/slambooster)
install(FILES ${SB_PKG_DIR}/debian/lintian-overrides DESTINATION share/lintian/overrides
  RENAME slambooster)

# Manual pages of the three executables.
foreach(page slambooster.1 slamboosterctl.1 slamboosterd.8)
  string(REGEX REPLACE "^.*\\." "" section ${page})
  sb_gzip_for_deb(${SB_PKG_DIR}/man/${page} ${CMAKE_BINARY_DIR}/deb/${page}.gz)
  install(FILES ${CMAKE_BINARY_DIR}/deb/${page}.gz DESTINATION share/man/man${section})
endforeach()

# The package's architecture is the target's: armhf for the cross build, the host's otherwise.
set(SB_DEB_ARCH "")
find_program(SB_DPKG_ARCHITECTURE dpkg-architecture)
if(CMAKE_LIBRARY_ARCHITECTURE AND SB_DPKG_ARCHITECTURE)
  execute_process(COMMAND ${SB_DPKG_ARCHITECTURE} -t ${CMAKE_LIBRARY_ARCHITECTURE} -qDEB_HOST_ARCH
    OUTPUT_VARIABLE SB_DEB_ARCH OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
endif()
if(NOT SB_DEB_ARCH)
  execute_process(COMMAND dpkg --print-architecture OUTPUT_VARIABLE SB_DEB_ARCH
    OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
endif()

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME slambooster)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT "${SB_DEB_MAINTAINER}")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "dense SLAM with an online approximation controller")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE ${SB_DEB_ARCH})
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
# CPack writes CPACK_PACKAGE_DESCRIPTION_SUMMARY as the synopsis and this text, indented, as the extended
# description (an empty line becomes " .").
set(CPACK_DEBIAN_PACKAGE_DESCRIPTION "SLAMBooster runs KinectFusion dense SLAM (depth frames in, camera pose and a
3D map out) with a controller that turns approximation knobs frame by frame,
so that a small board such as the ODROID XU4 spends as little time and
energy per frame as it can while the trajectory stays accurate.

This package ships the slamboosterd daemon (systemd service, Unix-socket
pose/knob/energy stream), the slambooster offline tool, the slamboosterctl
client, the default configuration in /etc/slambooster and udev rules for
the ODROID SmartPower meters and OpenNI2 depth cameras. Installing it
enables and starts nothing: run 'systemctl enable --now slambooster'.")
# Library dependencies from the binaries (dpkg-shlibdeps, run for the package's architecture), plus what the
# maintainer scripts use.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "adduser, init-system-helpers (>= 1.52)")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA
  ${SB_PKG_DIR}/debian/postinst ${SB_PKG_DIR}/debian/prerm ${SB_PKG_DIR}/debian/postrm
  ${CMAKE_BINARY_DIR}/deb/conffiles)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_OUTPUT_FILE_PREFIX ${CMAKE_BINARY_DIR}/deb)
# Only the main package's files: the optional ROS component (ros/, install COMPONENT ros) links ROS and is not
# part of it, so that the daemon's package never depends on ROS.
set(CPACK_COMPONENTS_ALL Unspecified)
include(CPack)
