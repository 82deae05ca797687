#pragma once
// Why an OpenNI2 camera could not be opened, in words a user can act on (no OpenNI2 types: the driver's
// extended error text and the device URI are all it needs).

#include <optional>
#include <string>

namespace sb {

enum class OpenFailure { permission, busy, other };

// How to give this user access to a camera: the project's udev rule and the group `video`.
std::string cameraAccessHint();

// The USB device node (/dev/bus/usb/BBB/DDD) of a libusb-style URI "vvvv/pppp@bus/address" (PrimeSense, Kinect,
// Orbbec), if the URI is one.
std::optional<std::string> usbNode(const std::string& uri);

// Permission denied (the node is not read/writable, or the driver says so: libusb's LIBUSB_ERROR_ACCESS, the
// PrimeSense driver's "Failed to open the USB device!"), busy (LIBUSB_ERROR_BUSY, "Failed to set USB
// interface!", "Device is already open."), or other.
OpenFailure classifyOpenFailure(const std::string& uri, const std::string& details);

// The whole message: what failed, the driver's words, and what to do.
std::string describeOpenFailure(const std::string& uri, const std::string& details);

}  // namespace sb
