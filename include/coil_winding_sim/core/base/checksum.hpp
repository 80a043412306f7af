// FNV-1a (64 bit): a checksum of files the project writes and reads back
// (snapshots, study checkpoints), to refuse a changed byte. Not for security.
#pragma once

#include <cstddef>
#include <cstdint>

namespace cws {

constexpr uint64_t kFnv1aBasis = 0xcbf29ce484222325ull;

// The hash of `size` bytes at `data`, continued from `h`.
inline uint64_t fnv1a(const void* data, std::size_t size, uint64_t h = kFnv1aBasis) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) h = (h ^ bytes[i]) * 0x100000001b3ull;
  return h;
}

}  // namespace cws
