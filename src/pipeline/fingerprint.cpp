// 128-bit FNV-1a over typed values (pipeline/fingerprint.hpp).
#include "jointhb/pipeline/fingerprint.hpp"

#include <fmt/format.h>

#include <array>
#include <bit>
#include <fstream>
#include <optional>
#include <stdexcept>

#include "../support/file_bytes.hpp"

namespace jointhb::pipeline {
namespace {

__extension__ typedef unsigned __int128 u128;

constexpr u128 fnv128_prime = (static_cast<u128>(1) << 88) + 0x13b;
constexpr u128 fnv128_offset =
    (static_cast<u128>(0x6c62272e07bb0142ULL) << 64) | static_cast<u128>(0x62b821756295c58dULL);

/// v as 8 little-endian bytes (the hash does not depend on the platform's byte order).
std::array<unsigned char, 8> le64(std::uint64_t v) {
  std::array<unsigned char, 8> b{};
  for (int k = 0; k < 8; ++k) b[static_cast<std::size_t>(k)] = static_cast<unsigned char>((v >> (8 * k)) & 0xffU);
  return b;
}

using support::file_bytes;

}  // namespace

Fingerprint::Fingerprint()
    : high_(static_cast<std::uint64_t>(fnv128_offset >> 64)), low_(static_cast<std::uint64_t>(fnv128_offset)) {}

Fingerprint Fingerprint::chain(std::string_view parent_hex) {
  Fingerprint f;
  f.tag('P');
  f.add(parent_hex);
  return f;
}

void Fingerprint::mix(const void* data, std::size_t size) {
  u128 h = (static_cast<u128>(high_) << 64) | low_;
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    h ^= p[i];
    h *= fnv128_prime;
  }
  high_ = static_cast<std::uint64_t>(h >> 64);
  low_ = static_cast<std::uint64_t>(h);
}

void Fingerprint::mix_u64(std::uint64_t value) {
  const auto b = le64(value);
  mix(b.data(), b.size());
}

Fingerprint& Fingerprint::add_bytes(const void* data, std::size_t size) {
  mix_u64(size);
  mix(data, size);
  return *this;
}

Fingerprint& Fingerprint::add(std::string_view text) {
  tag('s');
  return add_bytes(text.data(), text.size());
}

Fingerprint& Fingerprint::add(std::uint64_t value) {
  tag('u');
  mix_u64(value);
  return *this;
}

Fingerprint& Fingerprint::add(std::int64_t value) {
  tag('i');
  mix_u64(static_cast<std::uint64_t>(value));
  return *this;
}

Fingerprint& Fingerprint::add(int value) { return add(static_cast<std::int64_t>(value)); }

Fingerprint& Fingerprint::add(bool value) {
  tag('b');
  const unsigned char b = value ? 1 : 0;
  mix(&b, 1);
  return *this;
}

Fingerprint& Fingerprint::add(double value) {
  tag('d');
  mix_u64(std::bit_cast<std::uint64_t>(value));
  return *this;
}

Fingerprint& Fingerprint::add(const Eigen::VectorXd& values) {
  tag('v');
  mix_u64(static_cast<std::uint64_t>(values.size()));
  for (const double v : values) mix_u64(std::bit_cast<std::uint64_t>(v));
  return *this;
}

Fingerprint& Fingerprint::add_file(const std::filesystem::path& file) {
  const std::optional<std::string> bytes = file_bytes(file);
  if (!bytes) throw std::runtime_error(file.string() + ": cannot read the file for its fingerprint");
  tag('f');
  return add_bytes(bytes->data(), bytes->size());
}

std::string Fingerprint::hex() const { return fmt::format("{:016x}{:016x}", high_, low_); }

}  // namespace jointhb::pipeline
