// Materials, sections, boundary conditions and loads of an Abaqus/CalculiX deck (inp_physics.hpp;
// the card formats follow the Abaqus Keywords Reference and CalculiX's ccx manual, §7).
#include "inp_physics.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <set>
#include <unordered_map>

#include "jointhb/fe/mesh_file_error.hpp"

namespace jointhb::fe::detail {

namespace {

// clang-format off
const std::set<std::string> kMeshCards = {
    "NODE", "ELEMENT", "NSET", "ELSET", "SURFACE", "PART", "END PART", "ASSEMBLY", "END ASSEMBLY",
    "INSTANCE", "END INSTANCE"};
const std::set<std::string> kPhysicsCards = {
    "MATERIAL", "ELASTIC", "DENSITY", "SOLID SECTION", "BOUNDARY", "CLOAD", "DLOAD", "DSLOAD",
    "TIE"};
// Output, print, heading and procedure cards, and thermal data without a temperature field (a
// *TEMPERATURE or *INITIAL CONDITIONS card, which would use it, is unsupported).
const std::set<std::string> kNoEffectCards = {
    "HEADING", "PREPRINT", "PHYSICAL CONSTANTS", "RESTART", "FILE FORMAT", "MONITOR",
    "OUTPUT", "NODE OUTPUT", "ELEMENT OUTPUT", "CONTACT OUTPUT", "ENERGY OUTPUT",
    "NODE PRINT", "EL PRINT", "CONTACT PRINT", "ENERGY PRINT", "NODE FILE", "EL FILE",
    "CONTACT FILE", "SECTION PRINT",
    "STEP", "END STEP", "STATIC", "FREQUENCY", "DYNAMIC", "MODAL DYNAMIC",
    "STEADY STATE DYNAMICS", "BUCKLE", "AMPLITUDE",
    "EXPANSION", "CONDUCTIVITY", "SPECIFIC HEAT"};
const std::set<std::string> kUnsupportedCards = {
    "PLASTIC", "DAMPING", "MODAL DAMPING", "HYPERELASTIC", "VISCOELASTIC", "ORIENTATION",
    "TRANSFORM", "DISTRIBUTION", "SHELL SECTION", "BEAM SECTION", "MEMBRANE SECTION",
    "COHESIVE SECTION", "GAP", "SPRING", "DASHPOT", "MASS", "ROTARY INERTIA",
    "TEMPERATURE", "INITIAL CONDITIONS", "DFLUX", "CFLUX", "FILM", "RADIATE",
    "SURFACE INTERACTION", "SURFACE BEHAVIOR", "FRICTION", "CONTACT PAIR", "CONTACT",
    "CLEARANCE", "EQUATION", "MPC", "COUPLING", "KINEMATIC", "DISTRIBUTING", "RIGID BODY",
    "PRE-TENSION SECTION", "NODAL THICKNESS"};
// clang-format on

using detail::to_integer;
using detail::to_number;
using detail::upper;

struct DeckMaterial {
  Material material;
  int line = 0;
  bool elastic = false, density = false;
};

class PhysicsReader {
 public:
  PhysicsReader(const std::string& file, const DeckIndex& index, InpResult& result)
      : file_(file), index_(index), result_(result), mesh_(result.mesh) {
    for (const auto& [name, members] : mesh_.node_sets) node_sets_[upper(name)] = &members;
    for (const auto& [name, members] : mesh_.element_sets) element_sets_[upper(name)] = &members;
    for (const auto& [name, faces] : mesh_.surfaces) {
      surfaces_[upper(name)] = &faces;
      surface_names_[upper(name)] = &name;
    }
  }

  void read(const std::vector<Card>& cards) {
    for (const Card& card : cards) {
      scope_ = card.scope;
      const std::string& k = card.keyword;
      if (k != "ELASTIC" && k != "DENSITY") material_.clear();
      if (k == "MATERIAL") begin_material(card);
      else if (k == "ELASTIC") read_elastic(card);
      else if (k == "DENSITY") read_density(card);
      else if (k == "SOLID SECTION") read_section(card);
      else if (k == "BOUNDARY") read_boundary(card);
      else if (k == "CLOAD") read_cload(card);
      else if (k == "DSLOAD") read_dsload(card);
      else if (k == "DLOAD") read_dload(card);
      else if (k == "TIE") read_tie(card);
    }
    assign_part_materials();
  }

 private:
  [[noreturn]] void fail(int line, const std::string& problem) const {
    throw MeshFileError(file_, line, problem);
  }
  std::string label(int line) const { return fmt::format("{}:{}", file_, line); }

  void check_parameters(const Card& card, std::initializer_list<const char*> allowed) const {
    for (const auto& [key, value] : card.parameters) {
      if (key == "AMPLITUDE")
        fail(card.line, fmt::format("*{}, AMPLITUDE={}: loads and boundary conditions that vary in "
                                    "time are not supported (the deck's loads are static loads of "
                                    "the preload)",
                                    card.keyword, value));
    }
    check_card_parameters(card, allowed, file_);
    if (const std::string* op = card.find("OP"); op && upper(*op) != "MOD" && upper(*op) != "NEW")
      fail(card.line, fmt::format("*{}, OP={}: must be MOD or NEW", card.keyword, *op));
  }

  std::string required(const Card& card, const char* key) const {
    return required_parameter(card, key, file_);
  }

  double number(int line, std::string_view text, const std::string& what) const {
    const auto value = to_number(text);
    if (!value) fail(line, fmt::format("{}: '{}' is not a finite number", what, text));
    return *value;
  }

  // The entry of `named` (upper-case keys) that a name in a data line means: in the card's scope
  // ("instance.name"), then as written; with a single instance, "instance.name" is "name".
  template <typename T>
  const T* lookup(const std::map<std::string, const T*>& named, std::string_view name) const {
    const std::string key = upper(name);
    if (!scope_.empty() && scope_ != index_.single_instance)
      if (const auto it = named.find(scope_ + "." + key); it != named.end()) return it->second;
    if (const auto it = named.find(key); it != named.end()) return it->second;
    const std::string& single = index_.single_instance;
    if (!single.empty() && key.starts_with(single + "."))
      if (const auto it = named.find(key.substr(single.size() + 1)); it != named.end()) return it->second;
    return nullptr;
  }

  // The index of node or element `text` (an id, or "instance.id"), or -1 when it is no id.
  int id_index(int line, std::string_view text, bool node, const std::string& what) const {
    std::string scope = scope_;
    std::string_view id_text = text;
    if (const std::size_t dot = text.rfind('.'); dot != std::string_view::npos && to_integer(text.substr(dot + 1))) {
      scope = upper(text.substr(0, dot));
      id_text = text.substr(dot + 1);
    }
    const auto id = to_integer(id_text);
    if (!id) return -1;
    const auto& ids = node ? index_.nodes : index_.elements;
    const auto scope_it = ids.find(scope);
    if (scope_it == ids.end()) fail(line, fmt::format("{}: '{}' names instance '{}', which is not defined", what, text, scope));
    const auto it = scope_it->second->find(*id);
    if (it == scope_it->second->end()) fail(line, fmt::format("{}: unknown {} {}", what, node ? "node" : "element", text));
    return it->second;
  }

  // A node number or node set name of a data line.
  std::vector<int> nodes(int line, std::string_view text, const std::string& what) const {
    if (const int index = id_index(line, text, true, what); index >= 0) return {index};
    const std::vector<int>* set = lookup(node_sets_, text);
    if (set == nullptr) fail(line, fmt::format("{}: unknown node set '{}'", what, text));
    return *set;
  }

  // An element number or element set name of a data line.
  std::vector<int> elements(int line, std::string_view text, const std::string& what) const {
    if (const int index = id_index(line, text, false, what); index >= 0) return {index};
    const std::vector<int>* set = lookup(element_sets_, text);
    if (set == nullptr) fail(line, fmt::format("{}: unknown element set '{}'", what, text));
    return *set;
  }

  // ---- materials and sections --------------------------------------------------------------

  void begin_material(const Card& card) {
    check_parameters(card, {"NAME"});
    const std::string name = required(card, "NAME");
    const std::string key = upper(name);
    if (const auto it = materials_.find(key); it != materials_.end())
      fail(card.line, fmt::format("*MATERIAL '{}' defined twice (first at line {})", name, it->second.line));
    DeckMaterial& m = materials_[key];
    m.material.name = name;
    m.line = card.line;
    material_ = key;
  }

  DeckMaterial& open_material(const Card& card) {
    if (material_.empty()) fail(card.line, fmt::format("*{} outside a *MATERIAL definition", card.keyword));
    return materials_.at(material_);
  }

  // The single data line of *ELASTIC or *DENSITY: `count` numbers (a further entry would be a
  // temperature: temperature-dependent data are not supported).
  std::vector<double> single_line(const Card& card, std::size_t count, const std::string& what) const {
    if (card.data.size() != 1)
      fail(card.data.empty() ? card.line : card.data[1].line,
           fmt::format("{}: one data line expected, got {} (temperature-dependent data are not "
                       "supported)", what, card.data.size()));
    const std::vector<std::string_view> e = card_entries(card.data[0].text);
    if (e.size() < count || (e.size() > count && !(e.size() == count + 1 && e[count].empty())))
      fail(card.data[0].line, fmt::format("{}: data must be {} number(s), got '{}'", what, count, card.data[0].text));
    std::vector<double> values;
    for (std::size_t i = 0; i < count; ++i) values.push_back(number(card.data[0].line, e[i], what));
    return values;
  }

  void read_elastic(const Card& card) {
    check_parameters(card, {"TYPE"});
    if (const std::string* type = card.find("TYPE"); type && upper(*type) != "ISO" && upper(*type) != "ISOTROPIC")
      fail(card.line, fmt::format("*ELASTIC, TYPE={} is not supported (only isotropic materials)", *type));
    DeckMaterial& m = open_material(card);
    const std::string what = fmt::format("*ELASTIC of material '{}'", m.material.name);
    const std::vector<double> v = single_line(card, 2, what);
    m.material.youngs_modulus = v[0];
    m.material.poissons_ratio = v[1];
    m.elastic = true;
  }

  void read_density(const Card& card) {
    check_parameters(card, {});
    DeckMaterial& m = open_material(card);
    m.material.density = single_line(card, 1, fmt::format("*DENSITY of material '{}'", m.material.name))[0];
    m.density = true;
  }

  void read_section(const Card& card) {
    check_parameters(card, {"ELSET", "MATERIAL", "CONTROLS"});
    const std::string elset = required(card, "ELSET");
    const std::string material = required(card, "MATERIAL");
    sections_.push_back({card.line, elements(card.line, elset, "*SOLID SECTION"), upper(material), material});
  }

  // Every element gets the material of its section; a part whose elements all share one material
  // takes it (jointhb has one material per part).
  void assign_part_materials() {
    std::vector<int> section_of(static_cast<std::size_t>(mesh_.num_elements()), -1);
    for (std::size_t s = 0; s < sections_.size(); ++s) {
      const Section& section = sections_[s];
      const auto it = materials_.find(section.material_key);
      if (it == materials_.end())
        fail(section.line, fmt::format("*SOLID SECTION: unknown material '{}'", section.material));
      const DeckMaterial& m = it->second;
      if (!m.elastic) fail(m.line, fmt::format("material '{}' has no *ELASTIC data", m.material.name));
      if (!m.density) fail(m.line, fmt::format("material '{}' has no *DENSITY (the mass needs it)", m.material.name));
      if (const std::string problem = m.material.validate(); !problem.empty())
        fail(m.line, problem);
      for (int e : section.elements) {
        int& owner = section_of[static_cast<std::size_t>(e)];
        if (owner >= 0)
          fail(section.line, fmt::format("*SOLID SECTION: element {} already has a section (line {})",
                                         mesh_.element_ids[static_cast<std::size_t>(e)], sections_[static_cast<std::size_t>(owner)].line));
        owner = static_cast<int>(s);
      }
    }
    result_.part_materials.assign(mesh_.parts.size(), std::nullopt);
    std::vector<int> part_section(mesh_.parts.size(), -2);  // -2: no element seen yet
    for (int e = 0; e < mesh_.num_elements(); ++e) {
      const int s = section_of[static_cast<std::size_t>(e)];
      const auto p = static_cast<std::size_t>(mesh_.elements[static_cast<std::size_t>(e)].part);
      int& first = part_section[p];
      if (first == -2) first = s;
      const auto key = [&](int k) { return k < 0 ? std::string() : sections_[static_cast<std::size_t>(k)].material_key; };
      if (key(first) != key(s)) {
        const int line = sections_[static_cast<std::size_t>(std::max(first, s))].line;
        fail(line, fmt::format("part '{}' has elements {} (jointhb has one material per part: give "
                               "the elements of each material their own ELSET on *ELEMENT)",
                               mesh_.parts[p], first < 0 || s < 0 ? "with and without a *SOLID SECTION"
                                                                  : "of materials '" + sections_[static_cast<std::size_t>(first)].material + "' and '" + sections_[static_cast<std::size_t>(s)].material + "'"));
      }
    }
    for (std::size_t p = 0; p < mesh_.parts.size(); ++p)
      if (part_section[p] >= 0)
        result_.part_materials[p] = materials_.at(sections_[static_cast<std::size_t>(part_section[p])].material_key).material;
  }

  // ---- boundary conditions -----------------------------------------------------------------

  // The fixed translations of a *BOUNDARY type name, or none for a name that is not one. For
  // solid elements only the translations exist; the rotations of XSYMM etc. have no DOF to fix.
  static std::optional<std::array<bool, 3>> boundary_type(const std::string& name) {
    if (name == "ENCASTRE" || name == "PINNED") return std::array<bool, 3>{true, true, true};
    if (name == "XSYMM") return std::array<bool, 3>{true, false, false};
    if (name == "YSYMM") return std::array<bool, 3>{false, true, false};
    if (name == "ZSYMM") return std::array<bool, 3>{false, false, true};
    if (name == "XASYMM") return std::array<bool, 3>{false, true, true};
    if (name == "YASYMM") return std::array<bool, 3>{true, false, true};
    if (name == "ZASYMM") return std::array<bool, 3>{true, true, false};
    return std::nullopt;
  }

  int dof(int line, std::string_view text, const std::string& what) const {
    const auto d = to_integer(text);
    if (!d || *d < 1 || *d > 6) fail(line, fmt::format("{}: DOF '{}' must be an integer 1..6", what, text));
    return static_cast<int>(*d);
  }

  void read_boundary(const Card& card) {
    check_parameters(card, {"OP", "TYPE"});
    if (const std::string* type = card.find("TYPE"); type && upper(*type) != "DISPLACEMENT")
      fail(card.line, fmt::format("*BOUNDARY, TYPE={} is not supported (only zero displacements)", *type));
    for (const DataLine& data : card.data) {
      const std::vector<std::string_view> e = card_entries(data.text);
      const std::string what = fmt::format("*BOUNDARY '{}'", data.text);
      if (e.size() < 2 || e.size() > 4)
        fail(data.line, fmt::format("*BOUNDARY data must be 'node or node set, first DOF [, last DOF [, value]]' or 'node or node set, ENCASTRE|PINNED|XSYMM|...', got '{}'", data.text));
      FixedNodes fixed;
      fixed.nodes = nodes(data.line, e[0], "*BOUNDARY");
      if (const auto type = boundary_type(upper(e[1])); type && e.size() == 2) {
        fixed.directions = *type;
      } else {
        const int first = dof(data.line, e[1], what);
        const int last = e.size() >= 3 && !e[2].empty() ? dof(data.line, e[2], what) : first;
        if (last < first) fail(data.line, fmt::format("{}: last DOF {} < first DOF {}", what, last, first));
        if (e.size() == 4 && !e[3].empty() && number(data.line, e[3], what) != 0.0)
          fail(data.line, fmt::format("{}: a prescribed displacement of {} is not supported (only fixed DOFs, value 0)", what, e[3]));
        fixed.directions = {false, false, false};
        for (int d = first; d <= std::min(last, 3); ++d) fixed.directions[static_cast<std::size_t>(d - 1)] = true;
        if (first > 3) continue;  // rotations only: solid elements have none
      }
      result_.constraints.push_back(std::move(fixed));
      result_.constraint_labels.push_back(label(data.line));
    }
  }

  // ---- loads -------------------------------------------------------------------------------

  void read_cload(const Card& card) {
    check_parameters(card, {"OP"});
    for (const DataLine& data : card.data) {
      const std::vector<std::string_view> e = card_entries(data.text);
      if (e.size() != 3) fail(data.line, fmt::format("*CLOAD data must be 'node or node set, DOF, magnitude', got '{}'", data.text));
      const std::string what = fmt::format("*CLOAD '{}'", data.text);
      const int d = dof(data.line, e[1], what);
      if (d > 3) fail(data.line, fmt::format("{}: a moment (DOF {}) on solid elements is not supported (they have no rotations)", what, d));
      NodalForces load;
      load.label = label(data.line);
      load.nodes = nodes(data.line, e[0], "*CLOAD");
      load.force[d - 1] = number(data.line, e[2], what);
      for (int n : load.nodes) {
        const auto [it, fresh] = loaded_dofs_.emplace(3 * n + d - 1, data.line);
        if (!fresh)
          fail(data.line, fmt::format("{}: node {} DOF {} already loaded at line {} (combine the loads into one)",
                                      what, mesh_.node_ids[static_cast<std::size_t>(n)], d, it->second));
      }
      result_.loads.forces.push_back(std::move(load));
    }
  }

  void read_dsload(const Card& card) {
    check_parameters(card, {"OP"});
    for (const DataLine& data : card.data) {
      const std::vector<std::string_view> e = card_entries(data.text);
      if (e.size() != 3) fail(data.line, fmt::format("*DSLOAD data must be 'surface, P, magnitude', got '{}'", data.text));
      const std::string what = fmt::format("*DSLOAD '{}'", data.text);
      if (upper(e[1]) != "P") fail(data.line, fmt::format("{}: load type '{}' is not supported (only P, a pressure)", what, e[1]));
      const std::vector<Face>* faces = lookup(surfaces_, e[0]);
      if (faces == nullptr) fail(data.line, fmt::format("{}: unknown surface '{}'", what, e[0]));
      result_.loads.pressures.push_back({label(data.line), *faces, number(data.line, e[2], what)});
    }
  }

  void read_dload(const Card& card) {
    check_parameters(card, {"OP"});
    for (const DataLine& data : card.data) {
      const std::vector<std::string_view> e = card_entries(data.text);
      if (e.size() != 3) fail(data.line, fmt::format("*DLOAD data must be 'element or element set, Pn, magnitude', got '{}'", data.text));
      const std::string what = fmt::format("*DLOAD '{}'", data.text);
      const std::string type = upper(e[1]);
      if (type.size() != 2 || type[0] != 'P' || type[1] < '1' || type[1] > '6')
        fail(data.line, fmt::format("{}: load type '{}' is not supported (only P1..P6, a pressure on a face)", what, e[1]));
      SurfacePressure load;
      load.label = label(data.line);
      load.pressure = number(data.line, e[2], what);
      for (int element : elements(data.line, e[0], "*DLOAD")) load.faces.push_back({element, type[1] - '1'});
      result_.loads.pressures.push_back(std::move(load));
    }
  }

  // ---- ties --------------------------------------------------------------------------------

  // *TIE (Abaqus Keywords Reference; CalculiX §7): one data line "slave, master". The tie is
  // linear and small-displacement (fe/tie.hpp), so ADJUST (moving slave nodes onto the master)
  // and POSITION TOLERANCE (which slave nodes to tie) change nothing jointhb computes: they are
  // checked and accepted (docs/ties.md §"Decks" says why).
  void read_tie(const Card& card) {
    check_parameters(card, {"NAME", "POSITION TOLERANCE", "ADJUST", "TIED NSET", "TYPE"});
    InpTie tie;
    tie.name = required(card, "NAME");
    tie.line = card.line;
    for (const InpTie& other : result_.ties)
      if (upper(other.name) == upper(tie.name))
        fail(card.line, fmt::format("*TIE '{}' defined twice (first at line {})", tie.name, other.line));
    if (const std::string* adjust = card.find("ADJUST"); adjust && upper(*adjust) != "YES" && upper(*adjust) != "NO")
      fail(card.line, fmt::format("*TIE, ADJUST={}: must be YES or NO", *adjust));
    if (const std::string* tolerance = card.find("POSITION TOLERANCE")) {
      const auto value = to_number(*tolerance);
      if (!value || *value < 0.0)
        fail(card.line, fmt::format("*TIE, POSITION TOLERANCE={}: must be a number >= 0", *tolerance));
    }
    if (const std::string* type = card.find("TYPE"); type && upper(*type) != "SURFACE TO SURFACE" && upper(*type) != "NODE TO SURFACE")
      fail(card.line, fmt::format("*TIE, TYPE={}: must be SURFACE TO SURFACE or NODE TO SURFACE", *type));
    if (const std::string* nset = card.find("TIED NSET")) {
      if (nset->empty()) fail(card.line, "*TIE, TIED NSET=: needs a node set name");
      tie.tied_nodes = nodes(card.line, *nset, "*TIE, TIED NSET");
    }
    if (card.data.size() != 1)
      fail(card.data.empty() ? card.line : card.data[1].line,
           fmt::format("*TIE '{}': one data line 'slave surface, master surface' expected, got {}", tie.name, card.data.size()));
    const DataLine& data = card.data[0];
    const std::vector<std::string_view> e = card_entries(data.text);
    if (e.size() != 2 || e[0].empty() || e[1].empty())
      fail(data.line, fmt::format("*TIE '{}' data must be 'slave surface, master surface', got '{}'", tie.name, data.text));
    const auto surface = [&](std::string_view name, const char* role) {
      const std::string* found = lookup(surface_names_, name);
      if (found == nullptr) fail(data.line, fmt::format("*TIE '{}': unknown {} surface '{}'", tie.name, role, name));
      return *found;
    };
    tie.slave_surface = surface(e[0], "slave");
    tie.master_surface = surface(e[1], "master");
    if (tie.slave_surface == tie.master_surface)
      fail(data.line, fmt::format("*TIE '{}': the slave and master surfaces are the same ('{}')", tie.name, tie.slave_surface));
    result_.ties.push_back(std::move(tie));
  }

  struct Section {
    int line = 0;
    std::vector<int> elements;
    std::string material_key, material;
  };

  const std::string& file_;
  const DeckIndex& index_;
  std::string scope_;  // Card::scope of the card being read
  InpResult& result_;
  const Mesh& mesh_;
  std::map<std::string, const std::vector<int>*> node_sets_, element_sets_;  // upper-case keys
  std::map<std::string, const std::vector<Face>*> surfaces_;
  std::map<std::string, const std::string*> surface_names_;  // upper case → Mesh::surfaces key
  std::map<std::string, DeckMaterial> materials_;  // upper-case name
  std::string material_;  // the open *MATERIAL (upper case), or empty
  std::vector<Section> sections_;
  std::map<int, int> loaded_dofs_;  // full DOF → line of its *CLOAD
};

}  // namespace

CardClass classify_card(const std::string& keyword) {
  if (kMeshCards.count(keyword)) return CardClass::mesh;
  if (kPhysicsCards.count(keyword)) return CardClass::physics;
  if (kNoEffectCards.count(keyword)) return CardClass::no_effect;
  if (kUnsupportedCards.count(keyword)) return CardClass::unsupported;
  return CardClass::unknown;
}

void read_physics_cards(const std::vector<Card>& cards, const std::string& file,
                        const DeckIndex& index, InpResult& result) {
  PhysicsReader(file, index, result).read(cards);
}

}  // namespace jointhb::fe::detail
