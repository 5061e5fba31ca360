#include "jointhb/fe/inp_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <initializer_list>
#include <map>
#include <set>
#include <unordered_map>
#include <utility>

#include "jointhb/fe/mesh_file_error.hpp"
#include "text_fields.hpp"

namespace jointhb::fe {

namespace {

using detail::split;
using detail::to_integer;
using detail::to_number;
using detail::trim;
using detail::upper;

// Cards that carry no mesh (Abaqus Keywords Reference: materials, sections, steps, loads, output,
// contact and constraint definitions). They are skipped and reported.
// clang-format off
const std::set<std::string> kIgnoredKeywords = {
    "HEADING", "PREPRINT", "PHYSICAL CONSTANTS",
    "MATERIAL", "ELASTIC", "DENSITY", "EXPANSION", "PLASTIC", "DAMPING", "CONDUCTIVITY",
    "SPECIFIC HEAT",
    "SOLID SECTION", "ORIENTATION", "TRANSFORM", "DISTRIBUTION",
    "STEP", "END STEP", "STATIC", "FREQUENCY", "DYNAMIC", "MODAL DYNAMIC",
    "STEADY STATE DYNAMICS", "BUCKLE", "MODAL DAMPING", "RESTART",
    "BOUNDARY", "CLOAD", "DLOAD", "DSLOAD", "TEMPERATURE", "INITIAL CONDITIONS", "AMPLITUDE",
    "OUTPUT", "NODE OUTPUT", "ELEMENT OUTPUT", "CONTACT OUTPUT", "NODE PRINT", "EL PRINT",
    "CONTACT PRINT", "NODE FILE", "EL FILE", "CONTACT FILE",
    "SURFACE INTERACTION", "SURFACE BEHAVIOR", "FRICTION", "CONTACT PAIR", "CLEARANCE",
    "TIE", "EQUATION", "MPC", "COUPLING", "KINEMATIC", "DISTRIBUTING", "RIGID BODY",
    "PRE-TENSION SECTION"};
// clang-format on

constexpr const char* kSupportedCards =
    "*NODE, *ELEMENT, *NSET, *ELSET, *SURFACE, *PART, *ASSEMBLY, *INSTANCE";

struct DataLine {
  int line = 0;
  std::string_view text;
};

struct Card {
  std::string keyword;  // upper case, single spaces, without the star
  int line = 0;
  std::vector<std::pair<std::string, std::string>> parameters;  // KEY (upper case), value
  std::vector<DataLine> data;

  [[nodiscard]] const std::string* find(const std::string& key) const {
    for (const auto& [k, v] : parameters)
      if (k == key) return &v;
    return nullptr;
  }
};

struct Token {
  int line = 0;
  std::string_view text;
};

// The comma-separated entries of a data line; a trailing comma (continuation) adds no entry.
std::vector<std::string_view> entries(std::string_view text) {
  std::vector<std::string_view> pieces = split(text, ',');
  while (!pieces.empty() && pieces.back().empty()) pieces.pop_back();
  return pieces;
}

std::string canonical_keyword(std::string_view text) {
  std::string keyword;
  for (std::string_view word : detail::split_blanks(text)) {
    if (!keyword.empty()) keyword += ' ';
    keyword += upper(word);
  }
  return keyword;
}

std::string unquote(std::string_view value) {
  if (value.size() >= 2 && value.front() == '"' && value.back() == '"') {
    value = value.substr(1, value.size() - 2);
  }
  return std::string(value);
}

class InpReader {
 public:
  explicit InpReader(std::string file) : file_(std::move(file)) {}

  InpResult read(std::string_view text) {
    InpResult result;
    for (const Card& card : cards(text)) {
      const std::string& k = card.keyword;
      if (k == "NODE") {
        read_nodes(card);
      } else if (k == "ELEMENT") {
        read_elements(card);
      } else if (k == "NSET") {
        read_set(card, node_sets_, "NSET", "node");
      } else if (k == "ELSET") {
        read_set(card, element_sets_, "ELSET", "element");
      } else if (k == "SURFACE") {
        read_surface(card);
      } else if (k == "PART") {
        begin_part(card);
      } else if (k == "END PART") {
        if (current_part_.empty()) fail(card.line, "*END PART without *PART");
        current_part_.clear();
      } else if (k == "ASSEMBLY" || k == "END ASSEMBLY" || k == "END INSTANCE") {
        // Structure only: the single instance adds nothing to the flat model.
      } else if (k == "INSTANCE") {
        read_instance(card);
      } else if (kIgnoredKeywords.count(k)) {
        result.ignored_cards.push_back({"*" + k, card.line});
      } else {
        fail(card.line, fmt::format("card *{} is not supported (mesh cards: {}; material, "
                                    "section, step, load and constraint cards are ignored)",
                                    k, kSupportedCards));
      }
    }
    if (mesh_.elements.empty()) fail(0, "no elements: the file has no *ELEMENT data");
    finish();
    result.mesh = std::move(mesh_);
    return result;
  }

 private:
  // A named set as read: its spelling at the first definition and its members by index.
  struct NamedSet {
    std::string name;
    std::vector<int> members;
  };
  using SetMap = std::map<std::string, NamedSet>;  // key: upper-case name

  [[noreturn]] void fail(int line, const std::string& problem) const {
    throw MeshFileError(file_, line, problem);
  }

  std::vector<Card> cards(std::string_view text) const {
    std::vector<Card> cards;
    int line_number = 0;
    for (std::string_view raw : detail::split_lines(text)) {
      ++line_number;
      const std::string_view line = trim(raw);
      if (line.empty() || line.starts_with("**")) continue;
      if (line.front() != '*') {
        if (cards.empty()) fail(line_number, "data line before the first keyword card");
        cards.back().data.push_back({line_number, line});
        continue;
      }
      Card card;
      card.line = line_number;
      const std::vector<std::string_view> pieces = split(line.substr(1), ',');
      card.keyword = canonical_keyword(pieces.front());
      if (card.keyword.empty()) fail(line_number, "a '*' without a keyword");
      for (std::size_t i = 1; i < pieces.size(); ++i) {
        if (pieces[i].empty()) continue;
        const std::size_t equals = pieces[i].find('=');
        const std::string key = canonical_keyword(pieces[i].substr(0, equals));
        const std::string value =
            equals == std::string_view::npos ? "" : unquote(trim(pieces[i].substr(equals + 1)));
        card.parameters.emplace_back(key, value);
      }
      cards.push_back(std::move(card));
    }
    return cards;
  }

  void check_parameters(const Card& card, std::initializer_list<const char*> allowed) const {
    for (const auto& [key, value] : card.parameters) {
      if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; })) {
        std::string list;
        for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
        fail(card.line, fmt::format("parameter {} of *{} is not supported (supported: {})", key,
                                    card.keyword, list));
      }
    }
  }

  std::string required(const Card& card, const char* key) const {
    const std::string* value = card.find(key);
    if (!value || value->empty()) {
      fail(card.line, fmt::format("*{} needs the parameter {}=", card.keyword, key));
    }
    return *value;
  }

  void check_instance(const Card& card) const {
    const std::string* instance = card.find("INSTANCE");
    if (instance && upper(*instance) != upper(instance_name_)) {
      fail(card.line, fmt::format("*{} refers to instance '{}', which is not defined", card.keyword,
                                  *instance));
    }
  }

  long integer(const Token& token, const std::string& what) const {
    const auto value = to_integer(token.text);
    if (!value) fail(token.line, fmt::format("{}: '{}' is not an integer", what, token.text));
    return *value;
  }

  int node_index(const Token& token, const std::string& what) const {
    const long id = integer(token, what);
    const auto it = node_index_.find(id);
    if (it == node_index_.end()) fail(token.line, fmt::format("{}: unknown node {}", what, id));
    return it->second;
  }

  int element_index(const Token& token, const std::string& what) const {
    const long id = integer(token, what);
    const auto it = element_index_.find(id);
    if (it == element_index_.end()) {
      fail(token.line, fmt::format("{}: unknown element {}", what, id));
    }
    return it->second;
  }

  // The set `name` of `sets`, created with this spelling if new.
  static NamedSet& set_named(SetMap& sets, const std::string& name) {
    NamedSet& set = sets[upper(name)];
    if (set.name.empty()) set.name = name;
    return set;
  }

  void read_nodes(const Card& card) {
    check_parameters(card, {"NSET", "SYSTEM"});
    if (const std::string* system = card.find("SYSTEM"); system && upper(*system) != "R") {
      fail(card.line,
           fmt::format("*NODE, SYSTEM={} is not supported (only rectangular, SYSTEM=R)", *system));
    }
    NamedSet* set = card.find("NSET") ? &set_named(node_sets_, required(card, "NSET")) : nullptr;
    for (const DataLine& data : card.data) {
      const std::vector<std::string_view> e = entries(data.text);
      if (e.size() < 2 || e.size() > 7) {
        fail(data.line, fmt::format("*NODE data must be 'id, x [, y [, z]]', got '{}'", data.text));
      }
      const long id = integer({data.line, e[0]}, "*NODE");
      if (const auto it = node_line_.find(id); it != node_line_.end()) {
        fail(data.line, fmt::format("node {} defined twice (first at line {})", id, it->second));
      }
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      for (std::size_t d = 0; d < 3 && d + 1 < e.size(); ++d) {
        if (e[d + 1].empty()) continue;  // a blank coordinate is zero
        const auto value = to_number(e[d + 1]);
        if (!value) {
          fail(data.line,
               fmt::format("node {}: coordinate '{}' is not a finite number", id, e[d + 1]));
        }
        x[static_cast<Eigen::Index>(d)] = *value;
      }
      const int index = static_cast<int>(coordinates_.size());
      coordinates_.push_back(x);
      mesh_.node_ids.push_back(id);
      node_index_[id] = index;
      node_line_[id] = data.line;
      if (set) set->members.push_back(index);
    }
  }

  void read_elements(const Card& card) {
    check_parameters(card, {"TYPE", "ELSET"});
    const std::string type_name = upper(required(card, "TYPE"));
    const std::optional<ElementType> known = element_type_of_abaqus_name(type_name);
    if (!known) {
      fail(card.line, fmt::format("element type {} is not supported (supported: C3D8, C3D8I, "
                                  "C3D20, C3D20R, C3D4, C3D10, C3D6, C3D15)",
                                  type_name));
    }
    const ElementType type = *known;
    const std::string* elset = card.find("ELSET");
    const std::string part_name = elset                    ? *elset
                                  : !current_part_.empty() ? current_part_
                                                           : std::string("default");
    NamedSet& part_set = set_named(element_sets_, part_name);
    const int part = part_index(part_set.name);
    const auto needed = static_cast<std::size_t>(node_count(type)) + 1;

    std::vector<Token> pending;  // element id and node numbers, possibly over several lines
    for (const DataLine& data : card.data) {
      for (std::string_view entry : entries(data.text)) pending.push_back({data.line, entry});
      if (pending.size() > needed) {
        fail(data.line, fmt::format("element {}: more than {} node numbers for {}",
                                    pending.front().text, needed - 1, type_name));
      }
      if (pending.size() == needed) {
        add_element(pending, type, part, type_name);
        part_set.members.push_back(mesh_.num_elements() - 1);
        pending.clear();
      }
    }
    if (!pending.empty()) {
      fail(pending.back().line,
           fmt::format("element {}: {} node numbers, {} needs {}", pending.front().text,
                       pending.size() - 1, type_name, needed - 1));
    }
  }

  int part_index(const std::string& name) {
    const auto it = std::find(mesh_.parts.begin(), mesh_.parts.end(), name);
    if (it != mesh_.parts.end()) return static_cast<int>(it - mesh_.parts.begin());
    mesh_.parts.push_back(name);
    return static_cast<int>(mesh_.parts.size()) - 1;
  }

  void add_element(const std::vector<Token>& tokens, ElementType type, int part,
                   const std::string& type_name) {
    const long id = integer(tokens.front(), "*ELEMENT " + type_name);
    if (const auto it = element_line_.find(id); it != element_line_.end()) {
      fail(tokens.front().line,
           fmt::format("element {} defined twice (first at line {})", id, it->second));
    }
    Element element;
    element.type = type;
    element.part = part;
    const std::string what = fmt::format("element {}", id);
    for (std::size_t a = 1; a < tokens.size(); ++a) {
      element.nodes[a - 1] = node_index(tokens[a], what);
    }
    element_index_[id] = mesh_.num_elements();
    element_line_[id] = tokens.front().line;
    mesh_.elements.push_back(element);
    mesh_.element_ids.push_back(id);
  }

  // *NSET and *ELSET: members by id or by set name, or GENERATE ranges.
  void read_set(const Card& card, SetMap& sets, const char* name_key, const char* what) {
    check_parameters(card, {name_key, "GENERATE", "INTERNAL", "UNSORTED", "INSTANCE"});
    check_instance(card);
    const std::string name = required(card, name_key);
    const std::string context = fmt::format("*{} '{}'", card.keyword, name);
    const bool nodes = std::string(name_key) == "NSET";
    std::vector<int> members;
    const auto add_id = [&](const Token& token) {
      members.push_back(nodes ? node_index(token, context) : element_index(token, context));
    };
    for (const DataLine& data : card.data) {
      const std::vector<std::string_view> e = entries(data.text);
      if (card.find("GENERATE")) {
        if (e.size() < 2 || e.size() > 3) {
          fail(data.line, fmt::format("{}: GENERATE data must be 'first, last [, increment]', "
                                      "got '{}'",
                                      context, data.text));
        }
        const long first = integer({data.line, e[0]}, context);
        const long last = integer({data.line, e[1]}, context);
        const long step = e.size() == 3 ? integer({data.line, e[2]}, context) : 1;
        if (step < 1 || last < first) {
          fail(data.line, fmt::format("{}: GENERATE needs first <= last and increment >= 1, got "
                                      "{}, {}, {}",
                                      context, first, last, step));
        }
        for (long id = first; id <= last; id += step) {
          const std::string text = std::to_string(id);
          add_id({data.line, text});
        }
        continue;
      }
      for (std::string_view entry : e) {
        if (entry.empty()) continue;
        if (to_integer(entry)) {
          add_id({data.line, entry});
          continue;
        }
        const auto it = sets.find(upper(entry));
        if (it == sets.end()) {
          fail(data.line, fmt::format("{}: unknown {} set '{}'", context, what, entry));
        }
        members.insert(members.end(), it->second.members.begin(), it->second.members.end());
      }
    }
    NamedSet& set = set_named(sets, name);
    set.members.insert(set.members.end(), members.begin(), members.end());
  }

  void read_surface(const Card& card) {
    check_parameters(card, {"NAME", "TYPE", "INTERNAL"});
    const std::string name = required(card, "NAME");
    if (const std::string* type = card.find("TYPE"); type && upper(*type) != "ELEMENT") {
      fail(card.line, fmt::format("*SURFACE, TYPE={} is not supported (only TYPE=ELEMENT)", *type));
    }
    const std::string context = fmt::format("*SURFACE '{}'", name);
    auto& surface = surfaces_[upper(name)];
    if (surface.first.empty()) surface.first = name;
    for (const DataLine& data : card.data) {
      const std::vector<std::string_view> e = entries(data.text);
      if (e.size() != 2) {
        fail(data.line, fmt::format("{}: data must be 'element or element set, S1..S6', got '{}'",
                                    context, data.text));
      }
      const std::string label = upper(e[1]);
      if (label.size() != 2 || label[0] != 'S' || label[1] < '1' || label[1] > '6') {
        fail(data.line, fmt::format("{}: face label '{}' is not one of S1..S6", context, e[1]));
      }
      const int face = label[1] - '1';
      // S5, S6 exist on hexahedra only, S5 on wedges too (tetrahedra have S1..S4).
      const auto add_face = [&](int element) {
        const ElementType type = mesh_.elements[static_cast<std::size_t>(element)].type;
        if (face >= face_count(type)) {
          fail(data.line,
               fmt::format("{}: element {} is a {} with faces S1..S{}, not {}", context,
                           mesh_.element_ids[static_cast<std::size_t>(element)], abaqus_name(type),
                           face_count(type), label));
        }
        surface.second.push_back({element, face});
      };
      if (to_integer(e[0])) {
        add_face(element_index({data.line, e[0]}, context));
        continue;
      }
      const auto it = element_sets_.find(upper(e[0]));
      if (it == element_sets_.end()) {
        fail(data.line, fmt::format("{}: unknown element set '{}'", context, e[0]));
      }
      for (int element : it->second.members) add_face(element);
    }
  }

  void begin_part(const Card& card) {
    check_parameters(card, {"NAME"});
    const std::string name = required(card, "NAME");
    if (!current_part_.empty()) {
      fail(card.line,
           fmt::format("*PART '{}' inside *PART '{}' (missing *END PART)", name, current_part_));
    }
    if (!defined_part_.empty()) {
      fail(card.line, fmt::format("second *PART '{}' (the first, '{}', is at line {}): only a "
                                  "single part is supported; write the input file without parts "
                                  "and assemblies (a flat model)",
                                  name, defined_part_, defined_part_line_));
    }
    current_part_ = defined_part_ = name;
    defined_part_line_ = card.line;
  }

  void read_instance(const Card& card) {
    check_parameters(card, {"NAME", "PART"});
    const std::string name = required(card, "NAME");
    const std::string part = required(card, "PART");
    if (!instance_name_.empty()) {
      fail(card.line, fmt::format("second *INSTANCE '{}' (the first, '{}', is at line {}): only "
                                  "one instance of one part is supported; write the input file "
                                  "without parts and assemblies (a flat model)",
                                  name, instance_name_, instance_line_));
    }
    if (upper(part) != upper(defined_part_)) {
      fail(card.line, fmt::format("*INSTANCE '{}' of part '{}', which is not defined", name, part));
    }
    // Data: an optional translation "dx, dy, dz", then an optional rotation "a1, a2, a3, b1, b2,
    // b3, angle" (Abaqus Keywords Reference, *INSTANCE).
    if (card.data.size() > 2) fail(card.data[2].line, "*INSTANCE has at most two data lines");
    const auto is_zero = [](std::string_view t) {
      const auto value = to_number(t);
      return value && *value == 0.0;
    };
    for (std::size_t i = 0; i < card.data.size(); ++i) {
      const DataLine& data = card.data[i];
      const std::vector<std::string_view> e = entries(data.text);
      const bool moved =
          i == 0 ? !std::all_of(e.begin(), e.end(), is_zero) : (e.size() != 7 || !is_zero(e[6]));
      if (moved) {
        fail(data.line, fmt::format("*INSTANCE '{}' is {} ('{}'): instances with offsets are not "
                                    "supported; write a flat model",
                                    name, i == 0 ? "translated" : "rotated", data.text));
      }
    }
    instance_name_ = name;
    instance_line_ = card.line;
  }

  static std::vector<int> sorted_unique(std::vector<int> v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    return v;
  }

  void finish() {
    mesh_.coordinates.resize(3, static_cast<Eigen::Index>(coordinates_.size()));
    for (std::size_t n = 0; n < coordinates_.size(); ++n) {
      mesh_.coordinates.col(static_cast<Eigen::Index>(n)) = coordinates_[n];
    }
    for (auto& [key, set] : node_sets_) mesh_.node_sets[set.name] = sorted_unique(set.members);
    for (auto& [key, set] : element_sets_) {
      mesh_.element_sets[set.name] = sorted_unique(set.members);
    }
    for (auto& [key, surface] : surfaces_) {
      std::vector<Face> faces;
      for (const Face& f : surface.second)
        if (std::find(faces.begin(), faces.end(), f) == faces.end()) faces.push_back(f);
      mesh_.surfaces[surface.first] = std::move(faces);
    }
  }

  std::string file_;
  Mesh mesh_;
  std::vector<Eigen::Vector3d> coordinates_;
  std::unordered_map<long, int> node_index_;
  std::unordered_map<long, int> node_line_;
  std::unordered_map<long, int> element_index_;
  std::unordered_map<long, int> element_line_;
  SetMap node_sets_;
  SetMap element_sets_;
  std::map<std::string, std::pair<std::string, std::vector<Face>>> surfaces_;  // upper-case key
  std::string current_part_;  // the open *PART, or empty
  std::string defined_part_;  // the (single) *PART of the file, or empty
  int defined_part_line_ = 0;
  std::string instance_name_;  // the (single) *INSTANCE, or empty
  int instance_line_ = 0;
};

}  // namespace

InpResult parse_inp(std::string_view text, const std::string& file_name) {
  return InpReader(file_name).read(text);
}

InpResult read_inp(const std::filesystem::path& file) {
  const std::string text = detail::read_file(file);
  return parse_inp(text, file.string());
}

}  // namespace jointhb::fe
