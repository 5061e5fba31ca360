// Parameter checks shared by the mesh and physics readers of an .inp deck (inp_card.hpp).
#include "inp_card.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "jointhb/fe/mesh_file_error.hpp"

namespace jointhb::fe::detail {

void check_card_parameters(const Card& card, std::initializer_list<const char*> allowed,
                           const std::string& file) {
  for (const auto& parameter : card.parameters) {
    const auto& key = parameter.first;  // not a structured binding: Clang < 16 cannot capture one
    if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; })) {
      std::string list;
      for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
      throw MeshFileError(file, card.line,
                          fmt::format("parameter {} of *{} is not supported (supported: {})", key,
                                      card.keyword, list.empty() ? "none" : list));
    }
  }
}

std::string required_parameter(const Card& card, const char* key, const std::string& file) {
  const std::string* value = card.find(key);
  if (!value || value->empty())
    throw MeshFileError(file, card.line, fmt::format("*{} needs the parameter {}=", card.keyword, key));
  return *value;
}

}  // namespace jointhb::fe::detail
