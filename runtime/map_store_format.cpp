#include "runtime/map_store_format.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <iterator>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/input_file.h"
#include "runtime/map_store_bytes.h"

namespace sb::mapstore {

namespace {

constexpr char kSlabMagic[8] = {'S', 'B', 'T', 'S', 'D', 'F', '\n', '\0'};
constexpr char kKeyframeMagic[8] = {'S', 'B', 'K', 'E', 'Y', 'F', '\n', '\0'};
constexpr size_t kSlabHeaderBytes = 8 + 4 + 12 + 12 + 8 + 8;
constexpr size_t kKeyframeHeaderBytes = 8 + 4 + 4 + 4 + 8 + 8;
constexpr int kMaxExtent = 1 << 14;         // voxels per axis of one slab: far beyond any volume

using Writer = ByteWriter;
using Reader = ByteReader;

std::vector<uint8_t> readAll(const std::string& path, const std::string& what) { return readFileBytes(path, what); }

// Checks the magic and the version (from kFormatVersion to `newest`: a state file's payload may have grown) and
// returns the version; once the header is read, checkPayload checks the payload's size and checksum.
uint32_t checkMagic(Reader& r, const char (&magic)[8], const char* what, uint32_t newest = kFormatVersion) {
  r.need(8);
  if (std::memcmp(r.bytes.data(), magic, 8) != 0)
    throw Error("map store: '" + r.path + "' is not a " + what + " (its first bytes differ): a foreign file in the "
                "store, or a corrupt one; move it away");
  r.at = 8;
  const uint32_t version = r.u32();
  if (version < kFormatVersion || version > newest)
    throw Error("map store: '" + r.path + "' is format version " + std::to_string(version) + ", this build reads " +
                (newest == kFormatVersion ? std::to_string(kFormatVersion)
                                          : std::to_string(kFormatVersion) + " to " + std::to_string(newest)) +
                ": use the slambooster that wrote it, or another --map-store");
  return version;
}

void checkPayload(const Reader& r, uint64_t payloadBytes, uint64_t checksum) {
  if (r.bytes.size() - r.at != payloadBytes)
    throw Error("map store: '" + r.path + "' is truncated or has bytes appended (payload " +
                std::to_string(r.bytes.size() - r.at) + " bytes, header says " + std::to_string(payloadBytes) +
                "): move it away");
  if (fnv1a64(r.bytes.data() + r.at, payloadBytes) != checksum)
    throw Error("map store: '" + r.path + "' is corrupt (its checksum does not match): move it away");
}

struct SlabHeader {
  SlabBox box;
  size_t payloadAt = 0;
};

// `bytes`: the slab file's (read from `path`, or kept in memory under that name).
SlabHeader parseSlab(const std::string& path, const std::vector<uint8_t>& bytes) {
  SlabHeader h;
  Reader r{path, bytes};
  checkMagic(r, kSlabMagic, "map store slab");
  for (int& v : h.box.first) v = static_cast<int32_t>(r.u32());
  for (int& v : h.box.extent) {
    v = static_cast<int32_t>(r.u32());
    if (v < 1 || v > kMaxExtent)
      throw Error("map store: '" + path + "' has a box extent of " + std::to_string(v) + " voxels: corrupt");
  }
  const uint64_t payload = r.u64(), checksum = r.u64();
  checkPayload(r, payload, checksum);
  h.payloadAt = r.at;
  return h;
}

}  // namespace

uint64_t fnv1a64(const uint8_t* data, size_t bytes) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (size_t i = 0; i < bytes; ++i) h = (h ^ data[i]) * 0x100000001b3ull;
  return h;
}

void ByteReader::need(size_t n) const {
  if (bytes.size() - at < n)
    throw Error("map store: '" + path + "' is truncated (" + std::to_string(bytes.size()) +
                " bytes); it is not a complete store file: move it away or give another --map-store");
}

std::vector<uint8_t> readFileBytes(const std::string& path, const std::string& what) {
  InputFile in(path, what);
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw Error("map store: cannot read '" + path + "'");
  return bytes;
}

void writeFileBytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  writeFileAtomically(path, [&](std::FILE* f, const std::string& temporary) {
    if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size())
      throw Error("map store: cannot write '" + temporary + "'");
  });
}

std::vector<uint8_t> encodeStateFile(const char (&magic)[8], uint32_t version, const std::vector<uint8_t>& payload) {
  Writer out;
  out.raw(magic, 8);
  out.u32(version);
  out.u64(payload.size());
  out.u64(fnv1a64(payload.data(), payload.size()));
  out.raw(payload.data(), payload.size());
  return std::move(out.bytes);
}

StatePayload stateFilePayload(const std::string& path, const std::vector<uint8_t>& bytes, const char (&magic)[8],
                              const char* what, uint32_t newest) {
  Reader r{path, bytes};
  StatePayload out;
  out.version = checkMagic(r, magic, what, newest);
  const uint64_t payload = r.u64(), checksum = r.u64();
  checkPayload(r, payload, checksum);
  out.bytes.assign(bytes.begin() + std::ptrdiff_t(r.at), bytes.end());
  return out;
}

bool SlabBox::intersects(const SlabBox& o) const {
  for (int a = 0; a < 3; ++a)
    if (first[a] >= o.first[a] + o.extent[a] || o.first[a] >= first[a] + extent[a]) return false;
  return true;
}

SlabBox SlabBox::intersection(const SlabBox& o) const {
  SlabBox out;
  for (int a = 0; a < 3; ++a) {
    out.first[a] = std::max(first[a], o.first[a]);
    out.extent[a] = std::max(0, std::min(first[a] + extent[a], o.first[a] + o.extent[a]) - out.first[a]);
  }
  return out;
}

std::vector<uint8_t> encodeSlab(const SlabBox& box, const int16_t* voxels) {
  Writer payload;
  const uint64_t n = box.voxels();
  bool any = false;
  for (uint64_t i = 0; i < n;) {
    uint64_t skip = 0;
    while (i < n && voxels[2 * i + 1] == 0 && skip < UINT32_MAX) ++skip, ++i;
    uint64_t count = 0;
    while (i + count < n && voxels[2 * (i + count) + 1] != 0 && count < UINT32_MAX) ++count;
    payload.u32(uint32_t(skip));
    payload.u32(uint32_t(count));
    // The run's voxels as Writer::i16 writes them (little-endian), a run at a time: byte by byte through
    // push_back this was most of the store's worker's time.
    const size_t at = payload.bytes.size();
    payload.bytes.resize(at + 4 * size_t(count));
    uint8_t* p = payload.bytes.data() + at;
    for (uint64_t j = 0; j < count; ++j, p += 4) {
      const auto tsdf = uint16_t(voxels[2 * (i + j)]), weight = uint16_t(voxels[2 * (i + j) + 1]);
      p[0] = uint8_t(tsdf), p[1] = uint8_t(tsdf >> 8), p[2] = uint8_t(weight), p[3] = uint8_t(weight >> 8);
    }
    any = any || count > 0;
    i += count;
  }
  if (!any) return {};
  Writer out;
  out.raw(kSlabMagic, 8);
  out.u32(kFormatVersion);
  for (int v : box.first) out.u32(static_cast<uint32_t>(v));
  for (int v : box.extent) out.u32(static_cast<uint32_t>(v));
  out.u64(payload.bytes.size());
  out.u64(fnv1a64(payload.bytes.data(), payload.bytes.size()));
  out.raw(payload.bytes.data(), payload.bytes.size());
  static_assert(kSlabHeaderBytes == 52, "the slab header's size");
  return std::move(out.bytes);
}

SlabBox readSlabHeader(const std::string& path) { return parseSlab(path, readAll(path, "map store slab")).box; }

void mergeSlab(const std::string& path, const SlabBox& target, int16_t* out) {
  mergeSlab(readAll(path, "map store slab"), path, target, out);
}

void mergeSlab(const std::vector<uint8_t>& bytes, const std::string& name, const SlabBox& target, int16_t* out) {
  const std::string& path = name;
  const SlabHeader h = parseSlab(path, bytes);
  Reader r{path, bytes, h.payloadAt};
  const SlabBox& box = h.box;
  const uint64_t n = box.voxels();
  const auto malformed = [&] {
    return Error("map store: '" + path + "' holds runs that do not cover its box: corrupt; move it away");
  };
  const uint64_t ex = uint64_t(box.extent[0]), exy = ex * uint64_t(box.extent[1]);
  for (uint64_t i = 0; i < n;) {
    const uint64_t skip = r.u32(), count = r.u32();
    if (skip > n - i || count > n - i - skip) throw malformed();
    i += skip;
    r.need(4 * size_t(count));
    const uint8_t* p = bytes.data() + r.at;
    r.at += 4 * size_t(count);
    // The run's first voxel in the target's coordinates, then stepped along x, y, z (no division a voxel).
    int tx = box.first[0] + int(i % ex) - target.first[0];
    int ty = box.first[1] + int((i / ex) % uint64_t(box.extent[1])) - target.first[1];
    int tz = box.first[2] + int(i / exy) - target.first[2];
    const int txEnd = box.first[0] + box.extent[0] - target.first[0];
    const int tyEnd = box.first[1] + box.extent[1] - target.first[1];
    for (uint64_t j = 0; j < count; ++j, p += 4) {
      if (tx >= 0 && ty >= 0 && tz >= 0 && tx < target.extent[0] && ty < target.extent[1] && tz < target.extent[2]) {
        const size_t at = size_t(tx) + size_t(target.extent[0]) * (size_t(ty) + size_t(target.extent[1]) * size_t(tz));
        out[2 * at] = int16_t(uint16_t(p[0] | (p[1] << 8)));
        out[2 * at + 1] = int16_t(uint16_t(p[2] | (p[3] << 8)));
      }
      if (++tx == txEnd) {
        tx = box.first[0] - target.first[0];
        if (++ty == tyEnd) ty = box.first[1] - target.first[1], ++tz;
      }
    }
    i += count;
  }
  if (r.at != bytes.size()) throw malformed();
}

std::vector<uint8_t> encodeKeyframes(const std::vector<const Keyframe*>& keyframes) {
  Writer payload;
  const uint32_t ferns = keyframes.empty() ? 0 : uint32_t(keyframes.front()->code.codes.size());
  for (const Keyframe* k : keyframes) {
    if (k->code.codes.size() != ferns) throw Error("map store: keyframes with codes of different sizes");
    payload.u64(k->frame);
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 4; ++col) payload.f64(k->T_camera_to_world.matrix()(row, col));
    payload.raw(k->code.codes.data(), ferns);
  }
  Writer out;
  out.raw(kKeyframeMagic, 8);
  out.u32(kFormatVersion);
  out.u32(uint32_t(keyframes.size()));
  out.u32(ferns);
  out.u64(payload.bytes.size());
  out.u64(fnv1a64(payload.bytes.data(), payload.bytes.size()));
  out.raw(payload.bytes.data(), payload.bytes.size());
  static_assert(kKeyframeHeaderBytes == 36, "the keyframe header's size");
  return std::move(out.bytes);
}

std::vector<Keyframe> readKeyframes(const std::string& path) {
  const std::vector<uint8_t> bytes = readAll(path, "map store keyframes");
  Reader r{path, bytes};
  checkMagic(r, kKeyframeMagic, "map store keyframe file");
  const uint32_t count = r.u32(), ferns = r.u32();
  const uint64_t payload = r.u64(), checksum = r.u64();
  checkPayload(r, payload, checksum);
  if (payload != uint64_t(count) * (8 + 96 + uint64_t(ferns)))
    throw Error("map store: '" + path + "' says " + std::to_string(count) + " keyframes of " + std::to_string(ferns) +
                " codes but holds " + std::to_string(payload) + " bytes of them: corrupt; move it away");
  std::vector<Keyframe> out(count);
  for (Keyframe& k : out) {
    k.frame = size_t(r.u64());
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 4; ++col) m(row, col) = r.f64();
    if (!m.allFinite())
      throw Error("map store: '" + path + "' holds a keyframe pose that is not finite: corrupt; move it away");
    k.T_camera_to_world.matrix() = m;
    k.code.codes.assign(bytes.begin() + std::ptrdiff_t(r.at), bytes.begin() + std::ptrdiff_t(r.at + ferns));
    r.at += ferns;
  }
  return out;
}

}  // namespace sb::mapstore
