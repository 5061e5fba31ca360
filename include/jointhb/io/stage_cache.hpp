#pragma once
// The disk store of the finite-element pipeline's stages (pipeline/stage_store.hpp): preload,
// modes, the interface model of the dynamic stage, kept under their keys, so that a run whose stage
// inputs are unchanged (e.g. only the dynamic settings were edited) reads the stage instead of
// recomputing it.
//
// Keys (pipeline/fe_model.hpp, fe_stage_keys): a Fingerprint of the typed values a stage reads —
// the model (mesh, materials, interfaces with their laws, bolts, constraints), the stage's own
// settings and, by Fingerprint::chain, the key of the stage it builds on (modes ← preload ←
// model). What is not in a key must not change the stage's result; what is in it may change it.
// The solver code is not hashed: a change of what a stage computes for the same input must bump
// pipeline::fe_stage_version — or run with --no-cache.
//
// Files. DIR/<stage>-<key>.bin, little-endian:
//   "JHBC"  u32 format version (stage_cache_format)  str stage  str key
//   u64 payload length   payload   u64 FNV-1a-64 checksum of the payload
// (str = u64 length + bytes). The payload is one record, self-describing so that a file written by
// a build whose cached types differ is told apart by name, not misread by position:
//   record = str type name (the C++ struct, e.g. "PreloadResult")  u32 field count
//            field × count, each: str field name (the C++ member)  u8 type code  u64 length  bytes
// Type codes and their bytes (n = the count that the length implies; doubles as their IEEE bit
// patterns, so a round trip is bit-identical; i32 arrays and f64 arrays are bulk copies):
//    1 boolean (1 byte, 0 or 1)   2 i32   3 i64   4 f64   5 string (the bytes)
//    6 enumeration (1 byte: the enumerator's value)
//    7 f64 array (Eigen::VectorXd, std::vector<double>)
//    8 f64 matrix: u64 rows, u64 cols, rows × cols f64 column-major (Eigen::MatrixXd)
//    9 i32 array   10 boolean array (a byte each)   11 3×3 matrix array (9 f64 each, column-major)
//   12 3-vector array (3 f64 each)
//   13 sparse matrix: u64 rows, cols, nnz; (cols + 1) i32 column starts, nnz i32 row indices,
//      nnz f64 values (compressed column storage)
//   14 record (a nested struct)   15 record list: u64 n, n records (std::vector of a struct)
//   16 record columns: u64 n, one record whose fields hold the n items' values of that member one
//      after another (std::vector of a small struct with many items: no per-item names)
// Decoding reads each field by name; a missing field, an unknown extra field, another type code
// or length, or another record type name makes decode_* throw std::runtime_error naming the record
// type and the field. stage_cache.cpp checks at compile time that each cached struct still has the
// members it serialises (aggregate_field_count.hpp); stage_cache_format is bumped with the layout.
// Written to a temporary file in DIR and renamed, so a reader never sees a partial file. A
// missing file is a silent miss; a truncated or corrupted file (bad magic, length, checksum,
// stage or key, or a payload that does not parse or whose fields differ from this build's) and a
// file of another format version are a miss with a one-line warning on stderr (naming the file
// and, for a payload, the record and field). Failing to create DIR or to write a file (disk full,
// no permission) is a warning; the run goes on without the cache. Never a crash, never a wrong result
// (short of a 128-bit hash collision or a stale pipeline::fe_stage_version).

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "jointhb/contact/contact_point.hpp"
#include "jointhb/hb/interface_model.hpp"
#include "jointhb/modal/modes.hpp"
#include "jointhb/pipeline/fingerprint.hpp"
#include "jointhb/pipeline/stage_store.hpp"
#include "jointhb/preload/preload_solver.hpp"
#include "jointhb/reduction/field_recovery.hpp"


namespace jointhb::io {

using pipeline::Fingerprint;  // the stage keys (pipeline/fingerprint.hpp)

/// Layout version of the cache files; bump when a serialised type gains, loses or changes a field
/// (the field names would tell the difference anyway; the version says it in the warning first).
/// 1: positional values; 2: self-describing records (above); 3: the preload's and the modes'
/// status as a Termination ("termination"; were "converged" flags and a ModalStatus "status");
/// 4: the solver statistics' Krylov counts ("iterations", "solved_columns": the cg backend).
inline constexpr std::uint32_t stage_cache_format = 4;

/// The on-disk cache of stage results. All load_* return std::nullopt on a miss; store_* never
/// throw (a failure is a warning). With enabled = false every load misses and store does nothing.
class StageCache final : public pipeline::StageStore {
 public:
  StageCache(std::filesystem::path dir, bool enabled);

  [[nodiscard]] bool enabled() const { return enabled_; }
  [[nodiscard]] const std::filesystem::path& directory() const { return dir_; }
  /// DIR/<stage>-<key>.bin
  [[nodiscard]] std::filesystem::path file(std::string_view stage, std::string_view key) const;
  [[nodiscard]] std::string location(std::string_view stage, std::string_view key) const override {
    return file(stage, key).string();
  }

  [[nodiscard]] std::optional<preload::PreloadResult> load_preload(const std::string& key) override;
  void store_preload(const std::string& key, const preload::PreloadResult& result) override;

  [[nodiscard]] std::optional<modal::ModalResult> load_modes(const std::string& key) override;
  void store_modes(const std::string& key, const modal::ModalResult& result) override;

  /// The condensation stage (reduction::build_modal_interface) should key it as
  /// Fingerprint::chain(fingerprints.preload) + its ModalInterfaceOptions (every field, the
  /// modal options too) + the load and output names and vectors (add(VectorXd)).
  /// The contact laws (contact::ContactPoint: a law object, not plain data) are not stored: the
  /// file keeps each group's name, first point and count, and the caller passes the laws, one
  /// per group in group order — the laws the model was built with, which the key already covers
  /// (they come from the case's model node). A count that differs from the stored groups is a miss
  /// with a warning.
  [[nodiscard]] std::optional<hb::InterfaceModel> load_interface_model(
      const std::string& key, const std::vector<contact::ContactPoint>& laws) override;
  void store_interface_model(const std::string& key, const hb::InterfaceModel& model) override;

  /// The full-field recovery of the condensation (reduction/field_recovery.hpp), keyed as the
  /// interface model it belongs to; stored only when a case asks for full fields.
  [[nodiscard]] std::optional<reduction::FieldRecovery> load_field_recovery(const std::string& key) override;
  void store_field_recovery(const std::string& key, const reduction::FieldRecovery& recovery) override;

  /// The warnings printed so far (each also went to stderr as one line "warning: ...").
  [[nodiscard]] const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  /// The payload of DIR/<stage>-<key>.bin when the file exists and its header, length and
  /// checksum are right; otherwise nullopt (with a warning unless the file is missing).
  std::optional<std::string> read_payload(std::string_view stage, const std::string& key);
  void write_payload(std::string_view stage, const std::string& key, const std::string& payload);
  void warn(const std::string& message);

  std::filesystem::path dir_;
  bool enabled_;
  std::vector<std::string> warnings_;
};

/// The payload encoding on its own (no header), for tests and for other containers. decode_*
/// throw std::runtime_error when the bytes do not parse (truncated, inconsistent sizes, trailing
/// bytes) or a record's fields differ from this build's (the message names record and field).
std::string encode_preload(const preload::PreloadResult& result);
preload::PreloadResult decode_preload(std::string_view payload);
std::string encode_modes(const modal::ModalResult& result);
modal::ModalResult decode_modes(std::string_view payload);
std::string encode_interface_model(const hb::InterfaceModel& model);
hb::InterfaceModel decode_interface_model(std::string_view payload,
                                          const std::vector<contact::ContactPoint>& laws);
std::string encode_field_recovery(const reduction::FieldRecovery& recovery);
reduction::FieldRecovery decode_field_recovery(std::string_view payload);

}  // namespace jointhb::io
