// A 64-bit FNV-1a digest of a sequence of strings (settings, file contents): what keys a sweep's rows.
#pragma once
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace semlb {

// FNV-1a 64 (Fowler-Noll-Vo, offset basis 14695981039346656037, prime 1099511628211). Each add() hashes the
// part's length before its bytes, so ("ab", "c") and ("a", "bc") differ. Not cryptographic: it tells settings
// apart, it does not resist forgery.
class Digest {
 public:
  // Adds one part (a setting, a file's contents).
  Digest& add(std::string_view part) {
    const uint64_t n = part.size();
    for (int i = 0; i < 8; ++i) byte(static_cast<unsigned char>(n >> (8 * i)));
    for (unsigned char c : part) byte(c);
    return *this;
  }
  // The digest as 16 lowercase hex digits.
  std::string hex() const {
    char s[17];
    std::snprintf(s, sizeof s, "%016llx", static_cast<unsigned long long>(h_));
    return s;
  }

 private:
  void byte(unsigned char c) { h_ = (h_ ^ c) * 1099511628211ULL; }
  uint64_t h_ = 14695981039346656037ULL;
};

}  // namespace semlb
