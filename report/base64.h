#pragma once
// Base64 (RFC 4648, with padding, no line breaks) for data: URIs.

#include <cstdint>
#include <string>
#include <vector>

namespace sb::report {

std::string base64Encode(const std::vector<uint8_t>& bytes);

// Decodes strict base64 (the alphabet above, '=' padding only at the end, length a multiple of 4).
// Returns false on anything else.
bool base64Decode(const std::string& text, std::vector<uint8_t>& bytes);

}  // namespace sb::report
