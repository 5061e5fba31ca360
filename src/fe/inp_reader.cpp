#include "jointhb/fe/inp_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <initializer_list>
#include <Eigen/Geometry>
#include <map>
#include <numbers>
#include <set>
#include <unordered_map>
#include <utility>

#include "jointhb/fe/mesh_file_error.hpp"
#include "inp_card.hpp"
#include "inp_physics.hpp"
#include "text_fields.hpp"

namespace jointhb::fe {

namespace {

using detail::split;
using detail::to_integer;
using detail::to_number;
using detail::trim;
using detail::upper;

constexpr const char* kSupportedCards =
    "*NODE, *ELEMENT, *NSET, *ELSET, *SURFACE, *PART, *ASSEMBLY, *INSTANCE, *MATERIAL, *ELASTIC, "
    "*DENSITY, *SOLID SECTION, *BOUNDARY, *CLOAD, *DSLOAD, *DLOAD, *TIE";

using detail::Card;
using detail::DataLine;

struct Token {
  int line = 0;
  std::string_view text;
};

// The comma-separated entries of a data line; a trailing comma (continuation) adds no entry.
constexpr auto entries = detail::card_entries;

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
  InpReader(std::string file, const InpOptions& options) : file_(std::move(file)) {
    for (const std::string& card : options.ignore_cards) {
      std::string_view name = trim(card);
      if (name.starts_with('*')) name.remove_prefix(1);
      ignore_.insert(canonical_keyword(name));
    }
  }

  InpResult read(std::string_view text) {
    InpResult result;
    result_ = &result;
    std::vector<Card> all = cards(text);
    const auto instances = std::count_if(all.begin(), all.end(), [](const Card& c) { return c.keyword == "INSTANCE"; });
    single_ = instances <= 1;
    for (Card& card : all) {
      if (recording_ != nullptr && card.keyword != "END PART" && card.keyword != "PART") {
        recording_->cards.push_back(std::move(card));  // read per instance of the part
        continue;
      }
      dispatch(std::move(card));
    }
    if (recording_ != nullptr) fail(recording_->line, fmt::format("*PART '{}' has no *END PART", recording_->name));
    if (instances == 0) {
      // A deck with parts but no assembly: each part once, where it is (several parts: their
      // names prefixed by the part's, as instances named like the parts).
      single_ = parts_.size() <= 1;
      for (auto& [key, part] : parts_) instantiate(part, part.name, part.line, Placement{});
    }
    if (mesh_.elements.empty()) fail(0, "no elements: the file has no *ELEMENT data");
    finish();
    result.mesh = std::move(mesh_);
    detail::read_physics_cards(physics_, file_, deck_index(), result);
    return result;
  }

 private:
  // A named set as read: its spelling at the first definition and its members by index.
  struct NamedSet {
    std::string name;
    std::vector<int> members;
  };
  using SetMap = std::map<std::string, NamedSet>;  // key: upper-case name

  struct PartDefinition {
    std::string name;
    int line = 0;
    std::vector<Card> cards;
    int instances = 0;
  };

  // Where the ids and names of the cards being read live: the flat model and the assembly
  // (global), or an instance of a part when the deck has several (its own ids; its set and
  // surface names prefixed "instance.").
  struct Scope {
    std::string name;    // the instance, as written; empty for the global scope
    std::string prefix;  // "" or "instance."
    std::unordered_map<long, int> node_index, node_line, element_index, element_line;
  };

  // How an instance's nodes are placed (read_instance) and which mesh part its elements without
  // ELSET join.
  struct Placement {
    std::string part = "default";
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Eigen::Vector3d axis_point = Eigen::Vector3d::Zero();
    [[nodiscard]] Eigen::Vector3d place(const Eigen::Vector3d& x) const {
      return rotation * (x + translation - axis_point) + axis_point;
    }
  };

  // Resolves the ids of one card in another scope (an INSTANCE= parameter) while it lives.
  class IdsScope {
   public:
    IdsScope(InpReader& reader, Scope* scope) : reader_(reader), saved_(reader.ids_) { reader.ids_ = scope; }
    ~IdsScope() { reader_.ids_ = saved_; }
    IdsScope(const IdsScope&) = delete;
    IdsScope& operator=(const IdsScope&) = delete;

   private:
    InpReader& reader_;
    Scope* saved_;
  };

  // A set named in a data line: first in the current scope ("instance.name"), then as written
  // (the assembly's, or "instance.name" spelled out).
  const NamedSet* find_set(const SetMap& sets, std::string_view name) const {
    if (!scope_->prefix.empty())
      if (const auto it = sets.find(upper(scope_->prefix + std::string(name))); it != sets.end()) return &it->second;
    const auto it = sets.find(upper(name));
    return it == sets.end() ? nullptr : &it->second;
  }

  // The ids of every scope, for the physics cards (inp_physics.hpp).
  [[nodiscard]] detail::DeckIndex deck_index() const {
    detail::DeckIndex index;
    index.single_instance = single_ ? upper(single_instance_) : std::string();
    index.nodes[""] = &global_.node_index;
    index.elements[""] = &global_.element_index;
    if (!index.single_instance.empty()) {
      index.nodes[index.single_instance] = &global_.node_index;
      index.elements[index.single_instance] = &global_.element_index;
    }
    for (const auto& [key, scope] : instances_) {
      index.nodes[key] = &scope.node_index;
      index.elements[key] = &scope.element_index;
    }
    return index;
  }

  // One card outside a *PART (or of a part, while an instance of it is read).
  void dispatch(Card card) {
    InpResult& result = *result_;
    const std::string& k = card.keyword;
    const detail::CardClass kind = detail::classify_card(k);
    if (kind == detail::CardClass::mesh) {
      read_mesh_card(card);
    } else if (kind == detail::CardClass::physics && ignore_.count(k)) {
      result.skipped_cards.push_back({"*" + k, card.line});  // read by jointhb, skipped on request
    } else if (kind == detail::CardClass::physics) {
      card.scope = scope_ == &global_ ? std::string() : upper(scope_->name);
      physics_.push_back(std::move(card));
    } else if (kind == detail::CardClass::no_effect) {
      if (k == "STEP" && first_step_ > 0)
        fail(card.line, fmt::format("a second *STEP (the first is at line {}): jointhb applies "
                                    "the boundary conditions and loads of one step, as the "
                                    "preload", first_step_));
      if (k == "STEP") first_step_ = card.line;
      result.ignored_cards.push_back({"*" + k, card.line});
    } else if (ignore_.count(k)) {
      result.skipped_cards.push_back({"*" + k, card.line});
    } else if (kind == detail::CardClass::unsupported) {
      fail(card.line, fmt::format("card *{} changes the physics and is not supported; to run "
                                  "without it, list it in the case under ignore_cards", k));
    } else {
      fail(card.line, fmt::format("card *{} is not supported (supported: {}; to run without "
                                  "it, list it in the case under ignore_cards)",
                                  k, kSupportedCards));
    }
  }

 private:
  void read_mesh_card(const Card& card) {
    const std::string& k = card.keyword;
    if (in_instance_ && k != "END INSTANCE")
      fail(card.line, fmt::format("*{} inside *INSTANCE '{}': instances that define their own mesh "
                                  "are not supported (define it in the *PART)", k, in_instance_name_));
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
      if (recording_ == nullptr) fail(card.line, "*END PART without *PART");
      recording_ = nullptr;
    } else if (k == "INSTANCE") {
      read_instance(card);
    } else if (k == "END INSTANCE") {
      if (!in_instance_) fail(card.line, "*END INSTANCE without *INSTANCE");
      in_instance_ = false;
    }
    // *ASSEMBLY, *END ASSEMBLY: structure only.
  }

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
    detail::check_card_parameters(card, allowed, file_);
  }

  std::string required(const Card& card, const char* key) const {
    return detail::required_parameter(card, key, file_);
  }

  // The scope whose ids a set or surface card's data use: the instance named by its INSTANCE=
  // parameter (an assembly-level set of an instance's nodes), else the current one.
  Scope* ids_scope(const Card& card) {
    const std::string* instance = card.find("INSTANCE");
    if (!instance) return scope_;
    if (single_) {
      if (upper(*instance) != upper(single_instance_))
        fail(card.line, fmt::format("*{} refers to instance '{}', which is not defined", card.keyword, *instance));
      return &global_;
    }
    const auto it = instances_.find(upper(*instance));
    if (it == instances_.end())
      fail(card.line, fmt::format("*{} refers to instance '{}', which is not defined", card.keyword, *instance));
    return &it->second;
  }


  long integer(const Token& token, const std::string& what) const {
    const auto value = to_integer(token.text);
    if (!value) fail(token.line, fmt::format("{}: '{}' is not an integer", what, token.text));
    return *value;
  }

  int node_index(const Token& token, const std::string& what) const {
    const long id = integer(token, what);
    const auto it = ids_->node_index.find(id);
    if (it == ids_->node_index.end()) fail(token.line, fmt::format("{}: unknown node {}", what, id));
    return it->second;
  }

  int element_index(const Token& token, const std::string& what) const {
    const long id = integer(token, what);
    const auto it = ids_->element_index.find(id);
    if (it == ids_->element_index.end()) {
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
      if (const auto it = scope_->node_line.find(id); it != scope_->node_line.end()) {
        fail(data.line, fmt::format("node {} defined twice (first at line {})", id, it->second));
      }
      Eigen::Vector3d x = Eigen::Vector3d::Zero();  // in the part's coordinates
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
      coordinates_.push_back(placement_.place(x));
      mesh_.node_ids.push_back(id);
      scope_->node_index[id] = index;
      scope_->node_line[id] = data.line;
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
    const std::string part_name = elset ? scope_->prefix + *elset : placement_.part;
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
    if (const auto it = scope_->element_line.find(id); it != scope_->element_line.end()) {
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
    scope_->element_index[id] = mesh_.num_elements();
    scope_->element_line[id] = tokens.front().line;
    mesh_.elements.push_back(element);
    mesh_.element_ids.push_back(id);
  }

  // *NSET and *ELSET: members by id or by set name, or GENERATE ranges.
  void read_set(const Card& card, SetMap& sets, const char* name_key, const char* what) {
    check_parameters(card, {name_key, "GENERATE", "INTERNAL", "UNSORTED", "INSTANCE"});
    const IdsScope ids(*this, ids_scope(card));
    const std::string name = scope_->prefix + required(card, name_key);
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
        const NamedSet* set = find_set(sets, entry);
        if (set == nullptr) fail(data.line, fmt::format("{}: unknown {} set '{}'", context, what, entry));
        members.insert(members.end(), set->members.begin(), set->members.end());
      }
    }
    NamedSet& set = set_named(sets, name);
    set.members.insert(set.members.end(), members.begin(), members.end());
  }

  void read_surface(const Card& card) {
    check_parameters(card, {"NAME", "TYPE", "INTERNAL", "INSTANCE"});
    const IdsScope ids(*this, ids_scope(card));
    const std::string name = scope_->prefix + required(card, "NAME");
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
      const NamedSet* set = find_set(element_sets_, e[0]);
      if (set == nullptr) fail(data.line, fmt::format("{}: unknown element set '{}'", context, e[0]));
      for (int element : set->members) add_face(element);
    }
  }

  void begin_part(const Card& card) {
    check_parameters(card, {"NAME"});
    const std::string name = required(card, "NAME");
    if (recording_ != nullptr) {
      fail(card.line,
           fmt::format("*PART '{}' inside *PART '{}' (missing *END PART)", name, recording_->name));
    }
    const auto [it, fresh] = parts_.try_emplace(upper(name));
    if (!fresh) fail(card.line, fmt::format("*PART '{}' defined twice (first at line {})", name, it->second.line));
    it->second.name = name;
    it->second.line = card.line;
    recording_ = &it->second;
  }

  // *INSTANCE, NAME=i, PART=p with an optional translation line "dx, dy, dz" and an optional
  // rotation line "a1, a2, a3, b1, b2, b3, angle" (Abaqus Keywords Reference, *INSTANCE: the
  // translation is applied first, then the rotation by `angle` degrees about the axis from a to
  // b, right-handed): x' = R (x + d − a) + a.
  void read_instance(const Card& card) {
    check_parameters(card, {"NAME", "PART"});
    const std::string name = required(card, "NAME");
    const std::string part = required(card, "PART");
    const auto it = parts_.find(upper(part));
    if (it == parts_.end()) fail(card.line, fmt::format("*INSTANCE '{}' of part '{}', which is not defined", name, part));
    if (card.data.size() > 2) fail(card.data[2].line, "*INSTANCE has at most two data lines");
    Placement placement;
    for (std::size_t i = 0; i < card.data.size(); ++i) {
      const DataLine& data = card.data[i];
      const std::vector<std::string_view> e = entries(data.text);
      const std::size_t expected = i == 0 ? 3 : 7;
      if (e.size() != expected)
        fail(data.line, fmt::format("*INSTANCE '{}': the {} line must have {} numbers, got '{}'", name,
                                    i == 0 ? "translation" : "rotation", expected, data.text));
      std::array<double, 7> v{};
      for (std::size_t k = 0; k < expected; ++k) {
        const auto value = to_number(e[k]);
        if (!value) fail(data.line, fmt::format("*INSTANCE '{}': '{}' is not a finite number", name, e[k]));
        v[k] = *value;
      }
      if (i == 0) {
        placement.translation = {v[0], v[1], v[2]};
      } else {
        const Eigen::Vector3d a(v[0], v[1], v[2]), b(v[3], v[4], v[5]);
        if ((b - a).norm() == 0.0) fail(data.line, fmt::format("*INSTANCE '{}': the rotation axis points a and b coincide", name));
        placement.axis_point = a;
        placement.rotation = Eigen::AngleAxisd(v[6] * std::numbers::pi / 180.0, (b - a).normalized()).toRotationMatrix();
      }
    }
    instantiate(it->second, name, card.line, placement);
    in_instance_ = true;
    in_instance_name_ = name;
  }

  // Reads the cards of `part` as instance `name`: its ids in their own scope, its set and surface
  // names prefixed "name." when the deck has several instances, its nodes placed.
  void instantiate(PartDefinition& part, const std::string& name, int line, Placement placement) {
    Scope* scope = &global_;
    if (single_) {
      if (++part.instances > 1 || !single_instance_.empty())
        fail(line, fmt::format("second instance '{}'", name));
      single_instance_ = name;
      placement.part = part.name;
    } else {
      const auto [it, fresh] = instances_.try_emplace(upper(name));
      if (!fresh) fail(line, fmt::format("*INSTANCE '{}' defined twice", name));
      scope = &it->second;
      scope->name = name;
      scope->prefix = name + ".";
      placement.part = name;
    }
    Scope* const outer_scope = scope_;
    const Placement outer_placement = placement_;
    scope_ = ids_ = scope;
    placement_ = placement;
    for (const Card& card : part.cards) dispatch(card);
    scope_ = ids_ = outer_scope;
    placement_ = outer_placement;
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
  std::set<std::string> ignore_;  // canonical keywords of InpOptions::ignore_cards
  InpResult* result_ = nullptr;
  Mesh mesh_;
  std::vector<Eigen::Vector3d> coordinates_;
  SetMap node_sets_;
  SetMap element_sets_;
  std::map<std::string, std::pair<std::string, std::vector<Face>>> surfaces_;  // upper-case key
  std::vector<Card> physics_;  // physics cards in file order (per instance for a part's)
  int first_step_ = 0;         // line of the first *STEP
  std::map<std::string, PartDefinition> parts_;  // upper-case name
  PartDefinition* recording_ = nullptr;           // the open *PART, or none
  bool single_ = true;            // at most one instance: no prefixes, one id scope
  std::string single_instance_;   // its name
  bool in_instance_ = false;      // between *INSTANCE and *END INSTANCE
  std::string in_instance_name_;
  Scope global_;
  std::map<std::string, Scope> instances_;  // upper-case name → scope (several instances)
  Scope* scope_ = &global_;  // where new ids and names go
  Scope* ids_ = &global_;    // where ids in data lines resolve (INSTANCE= of a set card)
  Placement placement_;      // of the instance being read
};

}  // namespace

InpResult parse_inp(std::string_view text, const std::string& file_name, const InpOptions& options) {
  return InpReader(file_name, options).read(text);
}

InpResult read_inp(const std::filesystem::path& file, const InpOptions& options) {
  const std::string text = detail::read_file(file);
  return parse_inp(text, file.string(), options);
}

}  // namespace jointhb::fe
