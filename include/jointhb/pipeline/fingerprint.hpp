#pragma once
// Keys of the pipeline's stages (pipeline/stage_store.hpp): a 128-bit hash of typed values.

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace jointhb::pipeline {

/// A 128-bit FNV-1a hash (Fowler–Noll–Vo; prime 2^88 + 2^8 + 0x3b, offset basis
/// 0x6c62272e07bb014262b821756295c58d) built from typed values. Every value is preceded by a type
/// tag and strings and vectors by their length, so ("ab", "c") and ("a", "bc") differ.
class Fingerprint {
 public:
  Fingerprint();
  /// A fingerprint that starts with the key of the stage it builds on (its hex()).
  [[nodiscard]] static Fingerprint chain(std::string_view parent_hex);

  Fingerprint& add(std::string_view text);
  Fingerprint& add(const char* text) { return add(std::string_view(text)); }
  Fingerprint& add(double value);  ///< the bit pattern (0.0 and −0.0 differ)
  Fingerprint& add(int value);
  Fingerprint& add(std::int64_t value);
  Fingerprint& add(std::uint64_t value);
  Fingerprint& add(bool value);
  Fingerprint& add(const Eigen::VectorXd& values);
  /// The file's bytes (and its size). Throws std::runtime_error naming the file when unreadable.
  Fingerprint& add_file(const std::filesystem::path& file);
  /// Raw bytes with a length prefix.
  Fingerprint& add_bytes(const void* data, std::size_t size);

  /// 32 lower-case hex digits.
  [[nodiscard]] std::string hex() const;

 private:
  void mix(const void* data, std::size_t size);
  void mix_u64(std::uint64_t value);  ///< 8 little-endian bytes
  void tag(char t) { mix(&t, 1); }
  std::uint64_t high_, low_;  ///< the 128-bit state
};

}  // namespace jointhb::pipeline
