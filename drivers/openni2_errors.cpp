#include "drivers/openni2_errors.h"

#include <unistd.h>

#include <cstdio>

namespace sb {

namespace {

bool contains(const std::string& text, const char* needle) { return text.find(needle) != std::string::npos; }

}  // namespace

std::string cameraAccessHint() {
  return "the camera's USB device node must be readable and writable by this user: install the project's udev "
         "rule (/lib/udev/rules.d/60-slambooster.rules, shipped in the package; or copy cross-toolchain/udev/"
         "60-slambooster.rules to /etc/udev/rules.d and run `udevadm control --reload && udevadm trigger`), add "
         "the user to the group `video` (`sudo usermod -aG video $USER`, then log in again), and replug the camera";
}

// The USB device node of a libusb-style URI "vvvv/pppp@bus/address" (PrimeSense, Kinect, Orbbec), if any.
std::optional<std::string> usbNode(const std::string& uri) {
  unsigned vid = 0, pid = 0, bus = 0, address = 0;
  if (std::sscanf(uri.c_str(), "%x/%x@%u/%u", &vid, &pid, &bus, &address) != 4) return std::nullopt;
  char node[64];
  std::snprintf(node, sizeof node, "/dev/bus/usb/%03u/%03u", bus, address);
  return std::string(node);
}

OpenFailure classifyOpenFailure(const std::string& uri, const std::string& details) {
  const auto node = usbNode(uri);
  const bool nodeDenied = node && ::access(node->c_str(), F_OK) == 0 && ::access(node->c_str(), R_OK | W_OK) != 0;
  // libusb's names, and the PrimeSense driver's texts for libusb_open (EACCES) and claim_interface (EBUSY).
  if (nodeDenied || contains(details, "ACCESS") || contains(details, "ermission") ||
      contains(details, "Failed to open the USB device"))
    return OpenFailure::permission;
  if (contains(details, "BUSY") || contains(details, "busy") || contains(details, "already open") ||
      contains(details, "Failed to set USB interface"))
    return OpenFailure::busy;
  return OpenFailure::other;
}

// Why opening `uri` failed, in words a user can act on.
std::string describeOpenFailure(const std::string& uri, const std::string& details) {
  const std::string what = "cannot open the OpenNI2 camera '" + uri + "'";
  const auto node = usbNode(uri);
  switch (classifyOpenFailure(uri, details)) {
    case OpenFailure::permission:
      return what + ": permission denied" + (node ? " on " + *node : std::string()) + " (" + details + "). Fix: " +
             cameraAccessHint();
    case OpenFailure::busy:
      return what + ": the device is busy (" + details +
             "). Another program holds it: stop it (e.g. `systemctl stop slambooster`, or look with `fuser -v " +
             (node ? *node : std::string("/dev/bus/usb/*/*")) + "`) and try again";
    case OpenFailure::other:
      break;
  }
  return what + ": " + details + ". Check the cable and the camera's power, then try again";
}

}  // namespace sb
