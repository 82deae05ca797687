#pragma once
// The bytes of a map store's files (runtime/map_store_format.h): little-endian fixed-size fields, written and
// read without assuming the host's byte order (the same bytes on x86-64 and armhf), and the checked frame of a
// small state file (navmap.bin, odometry.bin): a magic, the format version, the payload's size and its FNV-1a 64
// checksum. A reader names its file in every refusal.

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace sb::mapstore {

struct ByteWriter {
  std::vector<uint8_t> bytes;
  void u16(uint16_t v) {
    bytes.push_back(uint8_t(v));
    bytes.push_back(uint8_t(v >> 8));
  }
  void u32(uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes.push_back(uint8_t(v >> (8 * i)));
  }
  void u64(uint64_t v) {
    for (int i = 0; i < 8; ++i) bytes.push_back(uint8_t(v >> (8 * i)));
  }
  void i16(int16_t v) { u16(static_cast<uint16_t>(v)); }
  void i32(int32_t v) { u32(static_cast<uint32_t>(v)); }
  void f64(double v) {
    uint64_t u;
    std::memcpy(&u, &v, sizeof u);
    u64(u);
  }
  void raw(const void* data, size_t n) {
    const auto* p = static_cast<const uint8_t*>(data);
    bytes.insert(bytes.end(), p, p + n);
  }
};

// Reads `bytes` (the file `path`'s) from `at`; throws sb::Error naming `path` when fewer bytes are left than a
// field needs (a truncated file).
struct ByteReader {
  const std::string& path;
  const std::vector<uint8_t>& bytes;
  size_t at = 0;
  void need(size_t n) const;
  size_t left() const { return bytes.size() - at; }
  uint16_t u16() {
    need(2);
    const auto v = static_cast<uint16_t>(bytes[at] | (bytes[at + 1] << 8));
    at += 2;
    return v;
  }
  uint32_t u32() {
    need(4);
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= uint32_t(bytes[at + size_t(i)]) << (8 * i);
    at += 4;
    return v;
  }
  uint64_t u64() {
    need(8);
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= uint64_t(bytes[at + size_t(i)]) << (8 * i);
    at += 8;
    return v;
  }
  int16_t i16() { return static_cast<int16_t>(u16()); }
  int32_t i32() { return static_cast<int32_t>(u32()); }
  double f64() {
    const uint64_t u = u64();
    double v;
    std::memcpy(&v, &u, sizeof v);
    return v;
  }
};

// The whole file `path` (`what` names it in a message when it cannot be opened).
std::vector<uint8_t> readFileBytes(const std::string& path, const std::string& what);
// Writes `bytes` as the file `path`, aside and renamed over it (core/atomic_file.h); throws sb::Error naming the
// file when it cannot.
void writeFileBytes(const std::string& path, const std::vector<uint8_t>& bytes);

// A state file: `magic` (8 bytes), u32 version (of its payload's layout), u64 payload bytes, u64 checksum, the
// payload.
std::vector<uint8_t> encodeStateFile(const char (&magic)[8], uint32_t version, const std::vector<uint8_t>& payload);
struct StatePayload {
  uint32_t version = 0;
  std::vector<uint8_t> bytes;
};
// The payload of the state file `bytes` (read from `path`) and its version; throws sb::Error naming `path` when
// it is truncated, altered (checksum), not a `what` (magic) or of a version outside the format's first
// (kFormatVersion) to `newest`.
StatePayload stateFilePayload(const std::string& path, const std::vector<uint8_t>& bytes, const char (&magic)[8],
                              const char* what, uint32_t newest);

}  // namespace sb::mapstore
