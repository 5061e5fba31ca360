#include "jointhb/io/fe_case.hpp"

#include "fit_keys.hpp"
#include "study_keys.hpp"
#include "jointhb/pipeline/fe_pipeline.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <set>

#include "jointhb/contact/harmonic_loop.hpp"
#include "jointhb/fe/assembly.hpp"
#include "jointhb/fe/box_mesh.hpp"
#include "jointhb/fe/gmsh_reader.hpp"
#include "jointhb/fe/inp_reader.hpp"
#include "jointhb/fe/mesh_checks.hpp"
#include "jointhb/fe/mesh_file_error.hpp"
#include "jointhb/fe/tie.hpp"
#include "jointhb/io/input_error.hpp"
#include "jointhb/io/value_checks.hpp"
#include "../support/physical_memory.hpp"
#include "fe_dynamics_keys.hpp"
#include "yaml_support.hpp"

namespace jointhb::io {
namespace {

using yaml::Fields;
using yaml::item_path;

#ifndef JOINTHB_VERSION
#define JOINTHB_VERSION "unknown"
#endif

const std::set<std::string> kAnalysisKeys = {"preload",    "modes",   "damping",         "reduction",
                                             "excitation", "outputs", "nonlinear_modes", "frf"};

// What a fit section of an FE case may name: the parameters of pipeline/fe_pipeline.hpp, modal
// targets of the elastic modes the modes stage computes at most, backbone targets of the followed
// modes, FRF targets of analysis.frf (level = index into its force list).
FitContext fit_context(const FeCase& c) {
  FitContext x;
  x.names = pipeline::fe_parameter_names(c, c);
  x.modes = c.modes ? c.modes->count : modal::ModalOptions{}.count;
  if (c.dynamics && c.dynamics->nonlinear_modes) {
    const FeNonlinearModesSpec& nm = *c.dynamics->nonlinear_modes;
    x.backbone = std::pair(nm.log10_amplitude_start, nm.log10_amplitude_end);
    x.backbone_modes = nm.modes;
    x.modes = std::max(x.modes, *std::max_element(nm.modes.begin(), nm.modes.end()));
  }
  if (c.dynamics && c.dynamics->frf) {
    const FeFrfSpec& f = *c.dynamics->frf;
    x.frf = std::pair(f.omega_start / (2.0 * std::numbers::pi), f.omega_end / (2.0 * std::numbers::pi));
    x.levels = static_cast<int>(f.forces.size());
  }
  x.finite_element = true;
  return x;
}

class FeCaseReader {
 public:
  FeCaseReader(std::string file_name, std::filesystem::path directory)
      : reader_(std::move(file_name)), directory_(std::move(directory)) {}

  FeCase read(const YAML::Node& root) {
    FeCase c;
    c.source = reader_.file();
    const Fields top = reader_.fields(root, "", {"model", "analysis", "fit", "study"});
    const auto* model = top.find("model");
    if (!model) reader_.fail(root, "model", "required");
    read_model(model->value, c);
    if (const auto* analysis = top.find("analysis")) {
      read_analysis(analysis->value, c);
      const Fields f = reader_.fields(analysis->value, "analysis", kAnalysisKeys);
      for (const char* key : {"damping", "reduction", "excitation", "outputs", "nonlinear_modes", "frf"})
        if (f.has(key)) {
          c.dynamics = read_fe_dynamics(reader_, f, c.mesh);
          check_modes_can_exist(f, c);
          break;
        }
    }
    // fit: last, since its parameter names and targets depend on the model and the analyses.
    if (const auto* section = top.find("fit")) c.fit = read_fit_section(reader_, section->value, "fit", fit_context(c), directory_);
    if (const auto* section = top.find("study")) c.study = read_study_section(reader_, section->value, "study", fit_context(c));
    return c;
  }

 private:
  yaml::Reader reader_;
  std::filesystem::path directory_;
  std::map<std::string, fe::Material> materials_;
  // A deck's *TIE, built once every part has its material (the penalty reads them).
  struct DeckTie {
    fe::InpTie tie;  // node indices of the combined mesh
    std::string file, key;
  };
  std::vector<DeckTie> deck_ties_;

  // A positive physical number (moduli, densities, stiffnesses, pressures, lengths): > 0 and of a
  // magnitude doubles can multiply (check_magnitude: [1e-100, 1e100], as for discrete models;
  // issue 20, item 3).
  double positive(const Fields& f, const char* name) const {
    const YAML::Node v = f.find(name)->value;
    const double x = reader_.number(v, f.path_of(name));
    reader_.check(v, f.path_of(name), check_positive(x));
    reader_.check(v, f.path_of(name), check_magnitude(x));
    return x;
  }
  double positive_or(const Fields& f, const char* name, double fallback) const {
    return f.has(name) ? positive(f, name) : fallback;
  }
  void require(const YAML::Node& node, const Fields& f, std::initializer_list<const char*> names) const {
    for (const char* name : names)
      if (!f.has(name)) reader_.fail(node, f.path_of(name), "required");
  }
  Eigen::Vector3d vector3(const YAML::Node& node, const std::string& path) const {
    if (!node.IsSequence() || node.size() != 3)
      reader_.fail(node, path, "must be a list of 3 numbers, got " + yaml::Reader::describe(node));
    Eigen::Vector3d v;
    for (std::size_t k = 0; k < 3; ++k) v[static_cast<Eigen::Index>(k)] = reader_.finite_number(node[k], item_path(path, k));
    return v;
  }
  std::string text(const Fields& f, const char* name) const {
    return reader_.text(f.find(name)->value, f.path_of(name));
  }

  // ---- model ---------------------------------------------------------------------------------

  void read_model(const YAML::Node& node, FeCase& c) {
    const Fields f = reader_.fields(node, "model",
                                    {"type", "materials", "parts", "interfaces", "bolts", "constraints", "loads", "ties"});
    require(node, f, {"type", "parts"});
    const std::string type = text(f, "type");
    if (type != "fe") reader_.fail(f.find("type")->value, "model.type", "must be fe here, got '" + type + "'");
    if (const auto* materials = f.find("materials")) read_materials(materials->value);
    read_parts(f.find("parts")->value, c);
    check_mesh(f.find("parts")->value, c);
    build_deck_ties(c);
    if (const auto* interfaces = f.find("interfaces")) read_interfaces(interfaces->value, c);
    if (const auto* ties = f.find("ties")) read_ties(ties->value, c);
    if (const auto* bolts = f.find("bolts")) read_bolts(bolts->value, c);
    if (const auto* constraints = f.find("constraints")) read_constraints(constraints->value, c);
    if (const auto* loads = f.find("loads")) read_loads(loads->value, c);
    if (f.has("loads")) check_free_loads(f.find("loads")->value, "model.loads", c);
    else check_free_loads(f.find("parts")->value, "model.parts", c);  // loads of the decks
    try {
      preload::check_connectivity(c.mesh, c.interfaces, c.bolts, c.constraints, c.ties);
    } catch (const std::invalid_argument& error) {
      reader_.fail(f.find("parts")->value, "model.parts", error.what());
    }
  }

  void read_materials(const YAML::Node& node) {
    if (!node.IsMap() || node.size() == 0)
      reader_.fail(node, "model.materials", "must be a non-empty mapping name → {youngs_modulus, poissons_ratio, density}");
    for (auto it = node.begin(); it != node.end(); ++it) {
      const std::string name = it->first.as<std::string>();
      const std::string path = "model.materials." + name;
      const Fields f = reader_.fields(it->second, path, {"youngs_modulus", "poissons_ratio", "density"});
      require(it->second, f, {"youngs_modulus", "poissons_ratio", "density"});
      fe::Material m;
      m.name = name;
      m.youngs_modulus = positive(f, "youngs_modulus");
      m.density = positive(f, "density");
      const YAML::Node nu = f.find("poissons_ratio")->value;
      m.poissons_ratio = reader_.finite_number(nu, f.path_of("poissons_ratio"));
      if (!(m.poissons_ratio > -1.0 && m.poissons_ratio < 0.5))
        reader_.fail(nu, f.path_of("poissons_ratio"), fmt::format("must be in (-1, 0.5), got {}", m.poissons_ratio));
      materials_[name] = m;
    }
  }

  const fe::Material& material(const YAML::Node& node, const std::string& path) const {
    const std::string name = reader_.text(node, path);
    const auto it = materials_.find(name);
    if (it == materials_.end()) {
      std::set<std::string> known;
      for (const auto& [k, v] : materials_) known.insert(k);
      reader_.fail(node, path, "unknown material '" + name + "'; defined: " + yaml::Reader::list(known));
    }
    return it->second;
  }

  // A box mesh's memory, estimated before it is built: its DOFs (3 per node of the linear mesh, a
  // lower bound for quadratic elements) at the ~12 KB per DOF that the sparse Cholesky factor of
  // a box took at 3e5 DOFs (3.5 GB, docs/performance.md); refused when that exceeds the machine.
  void check_box_memory(const YAML::Node& at, const std::string& key, const std::array<int, 3>& n) const {
    const double dofs = 3.0 * (n[0] + 1.0) * (n[1] + 1.0) * (n[2] + 1.0);
    const double bytes = 12.0e3 * dofs;
    const double available = static_cast<double>(support::physical_memory_bytes());
    if (available > 0.0 && bytes > available) {
      reader_.fail(at, key,
                   fmt::format("{} x {} x {} elements give {:.3g} DOFs, which need about {:.3g} GB "
                               "(12 KB per DOF for the factorisation), more than this machine's "
                               "{:.3g} GB: use fewer divisions",
                               n[0], n[1], n[2], dofs, bytes / 1e9, available / 1e9));
    }
  }

  void read_parts(const YAML::Node& node, FeCase& c) {
    if (!node.IsSequence() || node.size() == 0)
      reader_.fail(node, "model.parts", "must be a non-empty list of parts, got " + yaml::Reader::describe(node));
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string path = item_path("model.parts", i);
      const Fields f = reader_.fields(node[i], path, {"name", "material", "element", "box", "mesh", "materials", "ignore_cards"});
      fe::Mesh part_mesh;
      std::vector<fe::Material> part_materials;
      if (f.has("box") == f.has("mesh"))
        reader_.fail(node[i], path, "needs exactly one of box (a generated block) or mesh (a .inp or .msh file)");
      fe::ElementType type = fe::ElementType::hex8_incompatible;
      if (const auto* e = f.find("element")) {
        const std::string name = reader_.text(e->value, f.path_of("element"));
        const auto t = fe::element_type_of_abaqus_name(name);
        if (!t) reader_.fail(e->value, f.path_of("element"), "must be one of C3D8, C3D8I, C3D20, C3D20R, C3D4, C3D10, C3D6, C3D15, got '" + name + "'");
        type = *t;
      }
      if (const auto* box = f.find("box")) {
        require(node[i], f, {"name", "material"});
        const Fields b = reader_.fields(box->value, f.path_of("box"), {"origin", "size", "divisions"});
        require(box->value, b, {"size", "divisions"});
        fe::BoxOptions o;
        o.part = text(f, "name");
        o.type = type;
        if (b.has("origin")) o.origin = vector3(b.find("origin")->value, b.path_of("origin"));
        o.size = vector3(b.find("size")->value, b.path_of("size"));
        for (int k = 0; k < 3; ++k)
          if (!(o.size[k] > 0.0)) reader_.fail(b.find("size")->value[static_cast<std::size_t>(k)], item_path(b.path_of("size"), static_cast<std::size_t>(k)), fmt::format("must be > 0, got {}", o.size[k]));
        const YAML::Node d = b.find("divisions")->value;
        if (!d.IsSequence() || d.size() != 3) reader_.fail(d, b.path_of("divisions"), "must be a list of 3 integers");
        for (std::size_t k = 0; k < 3; ++k) {
          const long long v = reader_.integer(d[k], item_path(b.path_of("divisions"), k));
          reader_.check(d[k], item_path(b.path_of("divisions"), k), check_in_range(v, 1, 100000));
          o.divisions[k] = static_cast<int>(v);
        }
        check_box_memory(d, b.path_of("divisions"), o.divisions);
        part_mesh = fe::box_mesh(o);
        part_materials.push_back(material(f.find("material")->value, f.path_of("material")));
      } else {
        const auto* m = f.find("mesh");
        const std::filesystem::path file = directory_ / reader_.text(m->value, f.path_of("mesh"));
        DeckPhysics deck;
        try {
          const std::string ext = file.extension().string();
          if (ext == ".inp") {
            deck = read_deck(file, f, c);
            part_mesh = std::move(deck.inp.mesh);
          } else if (ext == ".msh") {
            if (const auto* ig = f.find("ignore_cards"))
              reader_.fail(ig->value, f.path_of("ignore_cards"), "applies to .inp decks only");
            // `element` chooses the formulation of Gmsh's hexahedra only: tetrahedra and prisms
            // are read as C3D4, C3D10, C3D6 or C3D15 whatever it says (a tet never becomes a hex).
            fe::GmshOptions g;
            if (const auto* e = f.find("element"); e && fe::family(type) != fe::ElementFamily::hexahedron)
              reader_.fail(e->value, f.path_of("element"), fmt::format("for a .msh mesh must be a hexahedron type (C3D8, C3D8I, C3D20, C3D20R): it selects the formulation of the file's hexahedra; its tetrahedra and prisms are read as C3D4/C3D10/C3D6/C3D15, got '{}'", fe::abaqus_name(type)));
            if (node_count(type) == 8) g.hex8_type = type; else g.hex20_type = type;
            part_mesh = fe::read_gmsh(file, g);
          } else {
            reader_.fail(m->value, f.path_of("mesh"), "must be a .inp (Abaqus/CalculiX) or .msh (Gmsh 4.1) file, got '" + file.string() + "'");
          }
        } catch (const fe::MeshFileError& error) {
          throw InputError(error.file(), error.line(), 0, f.path_of("mesh"), error.problem());
        }
        part_materials = file_part_materials(part_mesh, deck.inp.part_materials, f, file);
        add_deck_physics(deck.inp, c.mesh.num_nodes(), c.mesh.num_elements(), c);
        for (fe::InpTie tie : deck.inp.ties) {
          for (int& n : tie.tied_nodes) n += c.mesh.num_nodes();
          deck_ties_.push_back({std::move(tie), file.string(), f.path_of("mesh")});
        }
      }
      try {
        fe::append(c.mesh, part_mesh);
      } catch (const std::invalid_argument& error) {
        reader_.fail(node[i], path, error.what());
      }
      c.material_per_part.insert(c.material_per_part.end(), part_materials.begin(), part_materials.end());
    }
  }

  struct DeckPhysics {
    fe::InpResult inp;
  };

  // An .inp deck with its physics cards; its ignored cards become one warning, the cards skipped
  // on request one warning each.
  DeckPhysics read_deck(const std::filesystem::path& file, const Fields& f, FeCase& c) const {
    fe::InpOptions options;
    if (const auto* ig = f.find("ignore_cards")) {
      if (!ig->value.IsSequence() || ig->value.size() == 0)
        reader_.fail(ig->value, f.path_of("ignore_cards"), "must be a non-empty list of card names such as \"*TIE\"");
      for (std::size_t k = 0; k < ig->value.size(); ++k)
        options.ignore_cards.push_back(reader_.text(ig->value[k], item_path(f.path_of("ignore_cards"), k)));
    }
    DeckPhysics deck{fe::read_inp(file, options)};
    if (!deck.inp.ignored_cards.empty()) {
      std::string list;
      for (const auto& card : deck.inp.ignored_cards)
        list += fmt::format("{}{} ({})", list.empty() ? "" : ", ", card.keyword, card.line);
      c.warnings.push_back(fmt::format("{}: cards without effect on the results skipped (the analysis comes from the case): {}", file.string(), list));
    }
    for (const auto& card : deck.inp.skipped_cards)
      c.warnings.push_back(fmt::format("{}:{}: {} skipped as the case asks (ignore_cards): its effect is not in the results", file.string(), card.line, card.keyword));
    return deck;
  }

  // One material per part of an imported mesh: the case's (`materials` by part, then `material`
  // for all) overrides the deck's *SOLID SECTION material.
  std::vector<fe::Material> file_part_materials(const fe::Mesh& part_mesh,
                                                const std::vector<std::optional<fe::Material>>& from_deck,
                                                const Fields& f, const std::filesystem::path& file) const {
    std::map<std::string, const fe::Material*> by_part;
    if (const auto* ms = f.find("materials")) {
      if (!ms->value.IsMap()) reader_.fail(ms->value, f.path_of("materials"), "must be a mapping part → material");
      for (auto it = ms->value.begin(); it != ms->value.end(); ++it) {
        const std::string part = it->first.as<std::string>();
        if (std::find(part_mesh.parts.begin(), part_mesh.parts.end(), part) == part_mesh.parts.end())
          reader_.fail(it->first, f.path_of("materials") + "." + part, fmt::format("{} has no part '{}'; its parts: {}", file.string(), part, fmt::join(part_mesh.parts, ", ")));
        by_part[part] = &material(it->second, f.path_of("materials") + "." + part);
      }
    }
    std::vector<fe::Material> materials;
    for (std::size_t p = 0; p < part_mesh.parts.size(); ++p) {
      const std::string& name = part_mesh.parts[p];
      if (by_part.count(name)) materials.push_back(*by_part[name]);
      else if (f.has("material")) materials.push_back(material(f.find("material")->value, f.path_of("material")));
      else if (p < from_deck.size() && from_deck[p]) materials.push_back(*from_deck[p]);
      else reader_.fail(f.find("mesh")->value, f.path_of("materials"), fmt::format("no material for part '{}' of {} ({}; give material: or materials: {{{}: ...}})", name, file.string(), file.extension() == ".inp" ? "the deck has no *SOLID SECTION for it" : "a .msh file carries no materials", name));
    }
    return materials;
  }

  // The deck's *BOUNDARY constraints and loads, with node and element indices shifted to the
  // combined mesh (fe::append puts the deck's nodes after `node_offset` existing ones).
  static void add_deck_physics(const fe::InpResult& inp, int node_offset, int element_offset, FeCase& c) {
    for (std::size_t k = 0; k < inp.constraints.size(); ++k) {
      fe::FixedNodes fixed = inp.constraints[k];
      for (int& n : fixed.nodes) n += node_offset;
      c.constraints.push_back(std::move(fixed));
      c.constraint_sets.push_back(inp.constraint_labels[k]);
    }
    for (fe::NodalForces load : inp.loads.forces) {
      for (int& n : load.nodes) n += node_offset;
      c.loads.forces.push_back(std::move(load));
    }
    for (fe::SurfacePressure load : inp.loads.pressures) {
      for (fe::Face& face : load.faces) face.element += element_offset;
      c.loads.pressures.push_back(std::move(load));
    }
  }

  void check_mesh(const YAML::Node& at, const FeCase& c) const {
    const auto problems = fe::check_mesh(c.mesh);
    if (!problems.empty()) {
      reader_.fail(at, "model.parts", problems.front().message +
                                          (problems.size() > 1 ? fmt::format(" (and {} more problems)", problems.size() - 1) : ""));
    }
  }

  std::string surface_name(const YAML::Node& node, const std::string& path, const FeCase& c) const {
    const std::string name = reader_.text(node, path);
    if (!c.mesh.surfaces.count(name)) {
      std::set<std::string> known;
      for (const auto& [k, v] : c.mesh.surfaces) known.insert(k);
      reader_.fail(node, path, "unknown surface '" + name + "'; defined: " + yaml::Reader::list(known));
    }
    return name;
  }

  void read_interfaces(const YAML::Node& node, FeCase& c) {
    if (!node.IsSequence()) reader_.fail(node, "model.interfaces", "must be a list, got " + yaml::Reader::describe(node));
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string path = item_path("model.interfaces", i);
      const Fields f = reader_.fields(node[i], path, {"name", "bottom", "top", "region", "integration", "meshes", "contact"});
      require(node[i], f, {"bottom", "top", "contact"});
      FeInterfaceSpec spec;
      spec.name = f.has("name") ? text(f, "name") : fmt::format("interface{}", i + 1);
      // Names address parameters (interfaces.<name>.mu) and outputs: they must be unique.
      for (const FeInterfaceSpec& other : c.interface_specs)
        if (other.name == spec.name)
          reader_.fail(f.has("name") ? f.find("name")->value : node[i], f.path_of("name"),
                       fmt::format("'{}' is used twice (interface names must be unique)", spec.name));
      spec.bottom = surface_name(f.find("bottom")->value, f.path_of("bottom"), c);
      spec.top = surface_name(f.find("top")->value, f.path_of("top"), c);
      fe::InterfaceOptions o;
      o.name = spec.name;
      o.bottom_surface = spec.bottom;
      o.top_surface = spec.top;
      spec.integration = "nodal";
      if (const auto* in = f.find("integration")) {
        spec.integration = reader_.text(in->value, f.path_of("integration"));
        reader_.check(in->value, f.path_of("integration"), check_one_of(spec.integration, {"nodal", "gauss"}));
        o.integration = spec.integration == "gauss" ? fe::InterfaceIntegration::gauss : fe::InterfaceIntegration::nodal;
      }
      spec.meshes = "matching";
      if (const auto* in = f.find("meshes")) {
        spec.meshes = reader_.text(in->value, f.path_of("meshes"));
        reader_.check(in->value, f.path_of("meshes"), check_one_of(spec.meshes, {"matching", "non-matching", "automatic"}));
        o.meshes = spec.meshes == "non-matching" ? fe::InterfaceMeshes::non_matching
                   : spec.meshes == "automatic"  ? fe::InterfaceMeshes::automatic
                                                 : fe::InterfaceMeshes::matching;
      }
      if (const auto* region = f.find("region")) {
        // Only the faces whose centres lie in the box [min, max] take part (e.g. the overlap of
        // a lap joint): restricted copies of both surfaces.
        const Fields r = reader_.fields(region->value, f.path_of("region"), {"min", "max"});
        require(region->value, r, {"min", "max"});
        const Eigen::Vector3d lo = vector3(r.find("min")->value, r.path_of("min"));
        const Eigen::Vector3d hi = vector3(r.find("max")->value, r.path_of("max"));
        for (std::string* surface : {&o.bottom_surface, &o.top_surface}) {
          std::vector<fe::Face> kept;
          for (const fe::Face& face : c.mesh.surfaces.at(*surface)) {
            const Eigen::Vector3d centre = fe::face_centre(c.mesh, face);
            if ((centre.array() >= lo.array()).all() && (centre.array() <= hi.array()).all()) kept.push_back(face);
          }
          if (kept.empty()) reader_.fail(region->value, f.path_of("region"), "no face of surface '" + *surface + "' has its centre inside the region");
          const std::string restricted = fmt::format("{}@{}", *surface, spec.name);
          c.mesh.surfaces[restricted] = std::move(kept);
          *surface = restricted;
        }
      }
      // contact law
      const std::string cpath = f.path_of("contact");
      const YAML::Node cn = f.find("contact")->value;
      const contact::ContactPointOptions cp = read_contact_law(cn, cpath, spec);
      try {
        preload::ContactInterface ci{fe::build_interface(c.mesh, o),
                                     contact::ContactPoint(cp, contact::make_tangential_law(spec.law, spec.exponent))};
        spec.faces = static_cast<int>(ci.geometry.elements.size());
        c.interfaces.push_back(std::move(ci));
      } catch (const std::invalid_argument& error) {
        reader_.fail(node[i], path, error.what());
      }
      c.interface_specs.push_back(spec);
    }
  }

  // ---- ties (fe/tie.hpp, docs/ties.md) --------------------------------------------------------

  // The name of a new tie, unique among the case's ties (the summary and messages name them);
  // empty when it is unique, else the problem.
  static std::string tie_name_problem(const std::string& name, const FeCase& c) {
    for (std::size_t k = 0; k < c.ties.size(); ++k)
      if (c.ties[k].name == name)
        return fmt::format("tie '{}' is defined twice (also at {}): tie names must be unique", name, c.tie_sources[k]);
    return {};
  }

  void build_deck_ties(FeCase& c) {
    for (const DeckTie& d : deck_ties_) {
      const auto fail = [&](const std::string& problem) { throw InputError(d.file, d.tie.line, 0, d.key, problem); };
      if (const std::string problem = tie_name_problem(d.tie.name, c); !problem.empty()) fail(problem);
      fe::TieOptions o;
      o.name = d.tie.name;
      o.slave_surface = d.tie.slave_surface;
      o.master_surface = d.tie.master_surface;
      o.tied_nodes = d.tie.tied_nodes;
      try {
        c.ties.push_back(fe::build_tie(c.mesh, c.material_per_part, o));
      } catch (const std::invalid_argument& error) {
        fail(error.what());
      }
      c.tie_sources.push_back(fmt::format("{}:{}", d.file, d.tie.line));
    }
  }

  // model.ties: [{name, slave, master, penalty_factor}] (docs/case-files.md §"Ties").
  void read_ties(const YAML::Node& node, FeCase& c) {
    if (!node.IsSequence()) reader_.fail(node, "model.ties", "must be a list, got " + yaml::Reader::describe(node));
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string path = item_path("model.ties", i);
      const Fields f = reader_.fields(node[i], path, {"name", "slave", "master", "penalty_factor"});
      require(node[i], f, {"slave", "master"});
      fe::TieOptions o;
      o.name = f.has("name") ? text(f, "name") : fmt::format("tie{}", c.ties.size() + 1);
      if (const std::string problem = tie_name_problem(o.name, c); !problem.empty())
        reader_.fail(f.has("name") ? f.find("name")->value : node[i], f.path_of("name"), problem);
      o.slave_surface = surface_name(f.find("slave")->value, f.path_of("slave"), c);
      o.master_surface = surface_name(f.find("master")->value, f.path_of("master"), c);
      if (o.slave_surface == o.master_surface)
        reader_.fail(f.find("master")->value, f.path_of("master"), "must differ from slave, got '" + o.master_surface + "' for both");
      if (const auto* a = f.find("penalty_factor")) {
        o.penalty_factor = reader_.number(a->value, f.path_of("penalty_factor"));
        if (!(o.penalty_factor >= 1.0 && o.penalty_factor <= 1e6))
          reader_.fail(a->value, f.path_of("penalty_factor"), fmt::format("must be in [1, 1e6], got {}", o.penalty_factor));
      }
      try {
        c.ties.push_back(fe::build_tie(c.mesh, c.material_per_part, o));
      } catch (const std::invalid_argument& error) {
        reader_.fail(node[i], path, error.what());
      }
      c.tie_sources.push_back(path);
    }
  }

  void read_bolts(const YAML::Node& node, FeCase& c) {
    if (!node.IsSequence()) reader_.fail(node, "model.bolts", "must be a list, got " + yaml::Reader::describe(node));
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string path = item_path("model.bolts", i);
      const Fields f = reader_.fields(node[i], path, {"name", "point", "direction", "head", "nut", "stiffness", "preload"});
      require(node[i], f, {"point", "head", "nut", "stiffness", "preload"});
      preload::BoltOptions o;
      o.name = f.has("name") ? text(f, "name") : fmt::format("bolt{}", i + 1);
      // Names address parameters (bolts.<name>.preload): they must be unique.
      for (const preload::Bolt& other : c.bolts)
        if (other.name == o.name)
          reader_.fail(f.has("name") ? f.find("name")->value : node[i], f.path_of("name"),
                       fmt::format("'{}' is used twice (bolt names must be unique)", o.name));
      o.axis_point = vector3(f.find("point")->value, f.path_of("point"));
      if (f.has("direction")) {
        o.axis_direction = vector3(f.find("direction")->value, f.path_of("direction"));
        if (!(o.axis_direction.norm() > 0.0)) reader_.fail(f.find("direction")->value, f.path_of("direction"), "must not be zero");
      }
      for (const char* role : {"head", "nut"}) {
        const YAML::Node side = f.find(role)->value;
        const Fields s = reader_.fields(side, f.path_of(role), {"surface", "radius", "inner_radius"});
        require(side, s, {"surface", "radius"});
        const std::string surface = surface_name(s.find("surface")->value, s.path_of("surface"), c);
        const double radius = positive(s, "radius");
        double inner_radius = 0.0;  // a washer's annulus around a hole (eq. B-4 of preload/bolt.hpp)
        if (const auto* in = s.find("inner_radius")) {
          inner_radius = reader_.number(in->value, s.path_of("inner_radius"));
          reader_.check(in->value, s.path_of("inner_radius"), check_non_negative(inner_radius));
          if (!(inner_radius < radius))
            reader_.fail(in->value, s.path_of("inner_radius"),
                         fmt::format("must be < radius = {}, got {}", format_number(radius), format_number(inner_radius)));
        }
        if (std::string(role) == "head") o.head_surface = surface, o.head_radius = radius, o.head_inner_radius = inner_radius;
        else o.nut_surface = surface, o.nut_radius = radius, o.nut_inner_radius = inner_radius;
      }
      o.axial_stiffness = positive(f, "stiffness");
      const YAML::Node p = f.find("preload")->value;
      o.preload = reader_.number(p, f.path_of("preload"));
      reader_.check(p, f.path_of("preload"), check_magnitude(o.preload));
      reader_.check(p, f.path_of("preload"), check_non_negative(o.preload));
      try {
        c.bolts.push_back(preload::build_bolt(c.mesh, o));
      } catch (const std::invalid_argument& error) {
        reader_.fail(node[i], path, error.what());
      }
    }
  }

  // An interface's contact law (docs/case-files.md §"Interfaces"): the normal law — exponential
  // (pressure, decay [, cutoff_gap]) or linear (normal_stiffness) — and the tangential law
  // (gaul-mayer or jenkins with mu, or frictionless) with kt or stiffness_ratio.
  contact::ContactPointOptions read_contact_law(const YAML::Node& cn, const std::string& cpath, FeInterfaceSpec& spec) const {
    const Fields cf = reader_.fields(cn, cpath, {"pressure", "decay", "cutoff_gap", "normal_stiffness", "mu", "law", "n", "stiffness_ratio", "kt"});
    require(cn, cf, {"law"});
    contact::ContactPointOptions cp;
    const bool linear = cf.has("normal_stiffness");
    if (linear) {
      for (const char* key : {"pressure", "decay", "cutoff_gap"})
        if (cf.has(key)) reader_.fail(cf.find(key)->value, cf.path_of(key), "belongs to the exponential normal law; this contact has the linear one (normal_stiffness)");
      cp.normal.kind = contact::NormalLawKind::linear;
      spec.normal_stiffness = cp.normal.penalty_stiffness = positive(cf, "normal_stiffness");
    } else {
      if (!cf.has("pressure") || !cf.has("decay"))
        reader_.fail(cn, cpath, "needs the normal law: pressure and decay (exponential, eq. 6) or normal_stiffness (linear penalty)");
      spec.pressure = cp.normal.reference_pressure = positive(cf, "pressure");
      spec.decay = cp.normal.decay = positive(cf, "decay");
      if (cf.has("cutoff_gap")) spec.cutoff_gap = cp.normal.cutoff_gap = positive(cf, "cutoff_gap");
    }
    spec.law = text(cf, "law");
    reader_.check(cf.find("law")->value, cf.path_of("law"), check_one_of(spec.law, {"gaul-mayer", "jenkins", "frictionless"}));
    if (spec.law == "frictionless") {
      for (const char* key : {"mu", "n", "kt", "stiffness_ratio"})
        if (cf.has(key)) reader_.fail(cf.find(key)->value, cf.path_of(key), "a frictionless contact has no tangential law (no friction, no tangential stiffness)");
      cp.friction_coefficient = 0.0;
      spec.law = "jenkins";  // with μ = 0: t_T = 0, k_T = 0 (contact_point.hpp)
      spec.frictionless = true;
      return cp;
    }
    require(cn, cf, {"mu"});
    spec.mu = cp.friction_coefficient = positive(cf, "mu");
    spec.exponent = 1.0 / 3.0;
    if (const auto* n = cf.find("n")) {
      spec.exponent = reader_.number(n->value, cf.path_of("n"));
      reader_.check(n->value, cf.path_of("n"), check_open_unit(spec.exponent));
    }
    if (cf.has("kt") && cf.has("stiffness_ratio"))
      reader_.fail(cn, cpath, "give either kt (constant tangential stiffness [Pa/m]) or stiffness_ratio (k_T = χ k_N), not both");
    if (cf.has("kt")) {
      cp.stiffness_model = contact::TangentialStiffnessModel::constant;
      spec.tangential_stiffness = cp.tangential_stiffness = positive(cf, "kt");
    } else {
      spec.stiffness_ratio = cp.stiffness_ratio = positive_or(cf, "stiffness_ratio", cp.stiffness_ratio);
    }
    return cp;
  }

  void read_constraints(const YAML::Node& node, FeCase& c) {
    if (!node.IsSequence()) reader_.fail(node, "model.constraints", "must be a list, got " + yaml::Reader::describe(node));
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string path = item_path("model.constraints", i);
      const Fields f = reader_.fields(node[i], path, {"node_set", "fix"});
      require(node[i], f, {"node_set"});
      const std::string set = text(f, "node_set");
      const auto it = c.mesh.node_sets.find(set);
      if (it == c.mesh.node_sets.end()) reader_.fail(f.find("node_set")->value, f.path_of("node_set"), "unknown node set '" + set + "'");
      fe::FixedNodes fixed;
      fixed.nodes = it->second;
      if (const auto* fix = f.find("fix")) {
        fixed.directions = {false, false, false};
        if (!fix->value.IsSequence() || fix->value.size() == 0) reader_.fail(fix->value, f.path_of("fix"), "must be a list of x, y, z");
        for (std::size_t k = 0; k < fix->value.size(); ++k) {
          const std::string axis = reader_.text(fix->value[k], item_path(f.path_of("fix"), k));
          reader_.check(fix->value[k], item_path(f.path_of("fix"), k), check_one_of(axis, {"x", "y", "z"}));
          fixed.directions[static_cast<std::size_t>(axis[0] - 'x')] = true;
        }
      }
      c.constraints.push_back(fixed);
      c.constraint_sets.push_back(set);
    }
  }

  // model.loads: static loads of the preload besides the bolts (fe/static_load.hpp).
  void read_loads(const YAML::Node& node, FeCase& c) {
    if (!node.IsSequence()) reader_.fail(node, "model.loads", "must be a list, got " + yaml::Reader::describe(node));
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string path = item_path("model.loads", i);
      const Fields f = reader_.fields(node[i], path, {"node_set", "force", "surface", "pressure"});
      const bool nodal = f.has("node_set") || f.has("force");
      if (nodal == (f.has("surface") || f.has("pressure")))
        reader_.fail(node[i], path, "needs either node_set and force (a force on each node [N]) or surface and pressure [Pa]");
      if (nodal) {
        require(node[i], f, {"node_set", "force"});
        const std::string set = text(f, "node_set");
        const auto it = c.mesh.node_sets.find(set);
        if (it == c.mesh.node_sets.end()) reader_.fail(f.find("node_set")->value, f.path_of("node_set"), "unknown node set '" + set + "'");
        c.loads.forces.push_back({path, it->second, vector3(f.find("force")->value, f.path_of("force"))});
      } else {
        require(node[i], f, {"surface", "pressure"});
        const std::string surface = surface_name(f.find("surface")->value, f.path_of("surface"), c);
        const double p = reader_.finite_number(f.find("pressure")->value, f.path_of("pressure"));
        c.loads.pressures.push_back({path, c.mesh.surfaces.at(surface), p});
      }
    }
  }

  // Loads (the case's and the decks') on a model without constraints must be self-equilibrated:
  // the preload's 3-2-1 support would otherwise carry their resultant (preload_solver.hpp).
  void check_free_loads(const YAML::Node& at, const std::string& path, const FeCase& c) const {
    if (c.loads.empty() || !c.constraints.empty()) return;
    std::string problem;
    try {
      problem = fe::equilibrium_problem(c.mesh, fe::static_load_vector(c.mesh, c.loads));
    } catch (const std::invalid_argument& error) {
      reader_.fail(at, path, error.what());
    }
    if (!problem.empty())
      reader_.fail(at, path, "the loads have " + problem + ", and the model has no constraints (a free-free body carries only self-equilibrated loads): add model.constraints");
  }


  // ---- analysis ------------------------------------------------------------------------------

  // The modes stage computes analysis.modes.count modes; of a model without constraints (free-free,
  // held by a 3-2-1 support in the preload only) six are rigid-body modes. A damping curve of an
  // elastic mode beyond what remains cannot exist: refused here rather than after the preload
  // (pipeline/interface_settings.cpp finds it only then).
  void check_modes_can_exist(const Fields& analysis, const FeCase& c) const {
    const int count = c.modes ? c.modes->count : modal::ModalOptions{}.count;
    const int rigid = c.constraints.empty() ? 6 : 0;
    const int elastic = count - rigid;
    const std::string source = c.modes ? fmt::format("analysis.modes.count = {}", count)
                                       : fmt::format("the default analysis.modes.count = {}", count);
    const std::string why = rigid > 0 ? fmt::format("{} modes, {} of them rigid-body modes (the model has no "
                                                    "constraints)", source, rigid)
                                      : source + " modes";
    if (elastic < 1) {
      const auto* at = analysis.find("modes");
      reader_.fail(at ? at->value : analysis.find(c.dynamics->nonlinear_modes ? "nonlinear_modes" : "frf")->key,
                   "analysis.modes.count",
                   fmt::format("must leave at least one elastic mode for analysis.nonlinear_modes / frf: {}; "
                               "raise it to at least {}", why, rigid + 1));
    }
    if (!c.dynamics->nonlinear_modes) return;
    const Fields::Entry* nm = analysis.find("nonlinear_modes");
    const std::vector<int>& modes = c.dynamics->nonlinear_modes->modes;
    for (std::size_t i = 0; i < modes.size(); ++i) {
      if (modes[i] <= elastic) continue;
      // The position of the offending number: mode: k, or item i of mode: [..].
      const YAML::Node mode = nm->value.IsMap() ? nm->value["mode"] : YAML::Node();
      const bool listed = mode && mode.IsSequence();
      reader_.fail(listed ? mode[i] : (mode ? mode : nm->key),
                   listed ? item_path(analysis.path_of("nonlinear_modes") + ".mode", i)
                          : analysis.path_of("nonlinear_modes") + ".mode",
                   fmt::format("elastic mode {} cannot exist: {} leave at most {} elastic modes; raise "
                               "analysis.modes.count to at least {}",
                               modes[i], why, std::max(elastic, 0), modes[i] + rigid));
    }
  }

  void read_analysis(const YAML::Node& node, FeCase& c) {
    const Fields f = reader_.fields(node, "analysis", kAnalysisKeys);
    if (const auto* p = f.find("preload")) {
      c.preload_requested = true;
      const Fields pf = reader_.fields(p->value, f.path_of("preload"), {"load_steps", "tolerance", "max_iterations", "closed_pressure_fraction"});
      if (const auto* s = pf.find("load_steps")) {
        const long long v = reader_.integer(s->value, pf.path_of("load_steps"));
        reader_.check(s->value, pf.path_of("load_steps"), check_in_range(v, 1, 1000));
        c.preload.load_steps = static_cast<int>(v);
      }
      if (const auto* s = pf.find("max_iterations")) {
        const long long v = reader_.integer(s->value, pf.path_of("max_iterations"));
        reader_.check(s->value, pf.path_of("max_iterations"), check_in_range(v, 1, 1000));
        c.preload.max_iterations = static_cast<int>(v);
      }
      if (const auto* s = pf.find("tolerance")) {
        const double v = reader_.number(s->value, pf.path_of("tolerance"));
        if (!(v > 0.0 && v < 1.0)) reader_.fail(s->value, pf.path_of("tolerance"), fmt::format("must be in (0, 1), got {}", format_number(v)));
        c.preload.residual_tolerance = v;
      }
      if (const auto* s = pf.find("closed_pressure_fraction")) {
        const double v = reader_.number(s->value, pf.path_of("closed_pressure_fraction"));
        if (!(v >= 0.0 && v < 1.0)) reader_.fail(s->value, pf.path_of("closed_pressure_fraction"), fmt::format("must be in [0, 1), got {}", v));
        c.preload.closed_pressure_fraction = v;
      }
    }
    if (const auto* m = f.find("modes")) {
      const Fields mf = reader_.fields(m->value, f.path_of("modes"), {"count", "shift_hz", "tolerance"});
      modal::ModalOptions o;
      if (const auto* s = mf.find("count")) {
        const long long v = reader_.integer(s->value, mf.path_of("count"));
        reader_.check(s->value, mf.path_of("count"), check_in_range(v, 1, std::max(1, c.mesh.num_dofs() - 1)));
        o.count = static_cast<int>(v);
      }
      if (const auto* s = mf.find("shift_hz")) {
        const double hz = reader_.finite_number(s->value, mf.path_of("shift_hz"));
        if (!(hz < 0.0)) reader_.fail(s->value, mf.path_of("shift_hz"), fmt::format("must be < 0 (σ = −(2π·|shift_hz|)², below every eigenvalue), got {}", hz));
        o.shift = -std::pow(2.0 * std::numbers::pi * hz, 2);
      }
      if (const auto* s = mf.find("tolerance")) {
        const double v = reader_.number(s->value, mf.path_of("tolerance"));
        if (!(v > 0.0 && v <= 1e-3)) reader_.fail(s->value, mf.path_of("tolerance"), fmt::format("must be in (0, 1e-3], got {}", v));
        o.tolerance = v;
      }
      c.modes = o;
    }
  }
};

}  // namespace

FeCase parse_fe_case(const std::string& text, const std::string& file_name) {
  const std::filesystem::path dir = std::filesystem::path(file_name).parent_path();
  return FeCaseReader(file_name, dir).read(yaml::load(text, file_name));
}

FeCase read_fe_case(const std::filesystem::path& file) {
  return parse_fe_case(yaml::read_text_file(file), file.string());
}

}  // namespace jointhb::io
