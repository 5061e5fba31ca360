#pragma once
// One keyword card of an Abaqus/CalculiX input file with its data lines (private to the fe layer;
// shared by the mesh reader, inp_reader.cpp, and the reader of the deck's physics cards,
// inp_physics.cpp).

#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "text_fields.hpp"

namespace jointhb::fe::detail {

struct DataLine {
  int line = 0;
  std::string_view text;  ///< trimmed; views into the file's text
};

struct Card {
  std::string keyword;  ///< upper case, single spaces, without the star
  int line = 0;
  std::vector<std::pair<std::string, std::string>> parameters;  ///< KEY (upper case), value
  std::vector<DataLine> data;
  std::string scope;  ///< upper-case instance whose part holds the card; empty: global

  [[nodiscard]] const std::string* find(const std::string& key) const {
    for (const auto& [k, v] : parameters)
      if (k == key) return &v;
    return nullptr;
  }
};

/// The comma-separated entries of a data line, trimmed; a trailing comma (continuation) adds no
/// entry.
inline std::vector<std::string_view> card_entries(std::string_view text) {
  std::vector<std::string_view> pieces = split(text, ',');
  while (!pieces.empty() && pieces.back().empty()) pieces.pop_back();
  return pieces;
}

/// Throws MeshFileError "FILE:LINE: parameter K of *CARD is not supported (supported: ...)" for
/// the first parameter of `card` not in `allowed`.
void check_card_parameters(const Card& card, std::initializer_list<const char*> allowed,
                           const std::string& file);

/// The value of parameter `key`; throws MeshFileError "FILE:LINE: *CARD needs the parameter K="
/// when it is missing or empty.
[[nodiscard]] std::string required_parameter(const Card& card, const char* key, const std::string& file);

}  // namespace jointhb::fe::detail
