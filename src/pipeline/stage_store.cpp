// The in-memory stage store (pipeline/stage_store.hpp).
#include "jointhb/pipeline/stage_store.hpp"

namespace jointhb::pipeline {
namespace {

template <class T>
std::optional<T> find(const std::map<std::string, T>& map, const std::string& key) {
  const auto it = map.find(key);
  if (it == map.end()) return std::nullopt;
  return it->second;
}

}  // namespace

std::optional<preload::PreloadResult> MemoryStageStore::load_preload(const std::string& key) { return find(preload_, key); }
void MemoryStageStore::store_preload(const std::string& key, const preload::PreloadResult& r) { preload_[key] = r; }
std::optional<modal::ModalResult> MemoryStageStore::load_modes(const std::string& key) { return find(modes_, key); }
void MemoryStageStore::store_modes(const std::string& key, const modal::ModalResult& r) { modes_[key] = r; }

std::optional<hb::InterfaceModel> MemoryStageStore::load_interface_model(const std::string& key,
                                                                         const std::vector<contact::ContactPoint>& laws) {
  std::optional<hb::InterfaceModel> m = find(interface_, key);
  if (!m || m->groups.size() != laws.size()) return std::nullopt;
  for (std::size_t g = 0; g < laws.size(); ++g) m->groups[g].law = laws[g];
  return m;
}

void MemoryStageStore::store_interface_model(const std::string& key, const hb::InterfaceModel& m) { interface_[key] = m; }

std::optional<reduction::FieldRecovery> MemoryStageStore::load_field_recovery(const std::string& key) {
  return find(recovery_, key);
}

void MemoryStageStore::store_field_recovery(const std::string& key, const reduction::FieldRecovery& r) {
  recovery_[key] = r;
}

}  // namespace jointhb::pipeline
