#pragma once
// Where the pipeline keeps stage results under their keys (pipeline/fe_model.hpp FeStageKeys), so
// that a stage whose inputs did not change is read instead of recomputed: in memory
// (MemoryStageStore: a fit, a Python session), on disk (io::StageCache: `jointhb run`, shared
// between runs), or nowhere (a null store: the pipeline still keeps its current stages).
//
// Contract of every store: load_* return std::nullopt on a miss and never throw; store_* never
// throw (a failure is a warning of the store); what was stored under a key is what is loaded
// (bit-identical). The pipeline checks that a loaded result fits the model (sizes) and recomputes
// otherwise.

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "jointhb/contact/contact_point.hpp"
#include "jointhb/hb/interface_model.hpp"
#include "jointhb/modal/modes.hpp"
#include "jointhb/preload/preload_solver.hpp"
#include "jointhb/reduction/field_recovery.hpp"

namespace jointhb::pipeline {

class StageStore {
 public:
  virtual ~StageStore() = default;

  [[nodiscard]] virtual std::optional<preload::PreloadResult> load_preload(const std::string& key) = 0;
  virtual void store_preload(const std::string& key, const preload::PreloadResult& result) = 0;

  [[nodiscard]] virtual std::optional<modal::ModalResult> load_modes(const std::string& key) = 0;
  virtual void store_modes(const std::string& key, const modal::ModalResult& result) = 0;

  /// The condensed model (before the merge of coincident points). The contact laws are not
  /// plain data: the caller passes them, one per group in group order (the laws the model was
  /// built with, which the key covers); a count that differs from the stored groups is a miss.
  [[nodiscard]] virtual std::optional<hb::InterfaceModel> load_interface_model(
      const std::string& key, const std::vector<contact::ContactPoint>& laws) = 0;
  virtual void store_interface_model(const std::string& key, const hb::InterfaceModel& model) = 0;

  /// The full-field recovery of a condensation, keyed as its interface model.
  [[nodiscard]] virtual std::optional<reduction::FieldRecovery> load_field_recovery(const std::string& key) = 0;
  virtual void store_field_recovery(const std::string& key, const reduction::FieldRecovery& recovery) = 0;

  /// Where `stage` under `key` is kept, for messages ("memory", a file name).
  [[nodiscard]] virtual std::string location(std::string_view stage, std::string_view key) const = 0;
};

/// Keeps every stored result in memory (a copy each: the condensed model of a large interface
/// takes GBs, so prefer a disk store or none for those).
class MemoryStageStore final : public StageStore {
 public:
  std::optional<preload::PreloadResult> load_preload(const std::string& key) override;
  void store_preload(const std::string& key, const preload::PreloadResult& result) override;
  std::optional<modal::ModalResult> load_modes(const std::string& key) override;
  void store_modes(const std::string& key, const modal::ModalResult& result) override;
  std::optional<hb::InterfaceModel> load_interface_model(const std::string& key,
                                                         const std::vector<contact::ContactPoint>& laws) override;
  void store_interface_model(const std::string& key, const hb::InterfaceModel& model) override;
  std::optional<reduction::FieldRecovery> load_field_recovery(const std::string& key) override;
  void store_field_recovery(const std::string& key, const reduction::FieldRecovery& recovery) override;
  std::string location(std::string_view, std::string_view) const override { return "memory"; }

 private:
  std::map<std::string, preload::PreloadResult> preload_;
  std::map<std::string, modal::ModalResult> modes_;
  std::map<std::string, hb::InterfaceModel> interface_;
  std::map<std::string, reduction::FieldRecovery> recovery_;
};

/// Keeps nothing: every load misses.
class NullStageStore final : public StageStore {
 public:
  std::optional<preload::PreloadResult> load_preload(const std::string&) override { return std::nullopt; }
  void store_preload(const std::string&, const preload::PreloadResult&) override {}
  std::optional<modal::ModalResult> load_modes(const std::string&) override { return std::nullopt; }
  void store_modes(const std::string&, const modal::ModalResult&) override {}
  std::optional<hb::InterfaceModel> load_interface_model(const std::string&,
                                                         const std::vector<contact::ContactPoint>&) override {
    return std::nullopt;
  }
  void store_interface_model(const std::string&, const hb::InterfaceModel&) override {}
  std::optional<reduction::FieldRecovery> load_field_recovery(const std::string&) override { return std::nullopt; }
  void store_field_recovery(const std::string&, const reduction::FieldRecovery&) override {}
  std::string location(std::string_view, std::string_view) const override { return "nowhere"; }
};

}  // namespace jointhb::pipeline
