#include "jointhb/io/fe_case.hpp"

#include "fit_keys.hpp"
#include "jointhb/pipeline/fe_pipeline.hpp"

#include <fmt/format.h>
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
#include "jointhb/io/input_error.hpp"
#include "jointhb/io/value_checks.hpp"
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
    const Fields top = reader_.fields(root, "", {"model", "analysis", "fit"});
    const auto* model = top.find("model");
    if (!model) reader_.fail(root, "model", "required");
    read_model(model->value, c);
    if (const auto* analysis = top.find("analysis")) {
      read_analysis(analysis->value, c);
      const Fields f = reader_.fields(analysis->value, "analysis", kAnalysisKeys);
      for (const char* key : {"damping", "reduction", "excitation", "outputs", "nonlinear_modes", "frf"})
        if (f.has(key)) {
          c.dynamics = read_fe_dynamics(reader_, f, c.mesh);
          break;
        }
    }
    // fit: last, since its parameter names and targets depend on the model and the analyses.
    if (const auto* section = top.find("fit")) c.fit = read_fit_section(reader_, section->value, "fit", fit_context(c), directory_);
    return c;
  }

 private:
  yaml::Reader reader_;
  std::filesystem::path directory_;
  std::map<std::string, fe::Material> materials_;

  double positive(const Fields& f, const char* name) const {
    const YAML::Node v = f.find(name)->value;
    const double x = reader_.number(v, f.path_of(name));
    reader_.check(v, f.path_of(name), check_positive(x));
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
                                    {"type", "materials", "parts", "interfaces", "bolts", "constraints"});
    require(node, f, {"type", "materials", "parts"});
    const std::string type = text(f, "type");
    if (type != "fe") reader_.fail(f.find("type")->value, "model.type", "must be fe here, got '" + type + "'");
    read_materials(f.find("materials")->value);
    read_parts(f.find("parts")->value, c);
    check_mesh(f.find("parts")->value, c);
    if (const auto* interfaces = f.find("interfaces")) read_interfaces(interfaces->value, c);
    if (const auto* bolts = f.find("bolts")) read_bolts(bolts->value, c);
    if (const auto* constraints = f.find("constraints")) read_constraints(constraints->value, c);
    try {
      preload::check_connectivity(c.mesh, c.interfaces, c.bolts, c.constraints);
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

  void read_parts(const YAML::Node& node, FeCase& c) {
    if (!node.IsSequence() || node.size() == 0)
      reader_.fail(node, "model.parts", "must be a non-empty list of parts, got " + yaml::Reader::describe(node));
    for (std::size_t i = 0; i < node.size(); ++i) {
      const std::string path = item_path("model.parts", i);
      const Fields f = reader_.fields(node[i], path, {"name", "material", "element", "box", "mesh", "materials"});
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
        part_mesh = fe::box_mesh(o);
        part_materials.push_back(material(f.find("material")->value, f.path_of("material")));
      } else {
        const auto* m = f.find("mesh");
        const std::filesystem::path file = directory_ / reader_.text(m->value, f.path_of("mesh"));
        try {
          const std::string ext = file.extension().string();
          if (ext == ".inp") {
            fe::InpResult r = fe::read_inp(file);
            part_mesh = std::move(r.mesh);
            for (const auto& card : r.ignored_cards)
              c.warnings.push_back(fmt::format("{}:{}: {} skipped (jointhb takes materials, loads and steps from the case file)", file.string(), card.line, card.keyword));
          } else if (ext == ".msh") {
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
        // Materials: one for every part of the file (`material` for all, or `materials` by name).
        std::map<std::string, const fe::Material*> by_part;
        if (const auto* ms = f.find("materials")) {
          if (!ms->value.IsMap()) reader_.fail(ms->value, f.path_of("materials"), "must be a mapping part → material");
          for (auto it = ms->value.begin(); it != ms->value.end(); ++it)
            by_part[it->first.as<std::string>()] = &material(it->second, f.path_of("materials") + "." + it->first.as<std::string>());
        }
        for (const std::string& p : part_mesh.parts) {
          if (by_part.count(p)) part_materials.push_back(*by_part[p]);
          else if (f.has("material")) part_materials.push_back(material(f.find("material")->value, f.path_of("material")));
          else reader_.fail(m->value, f.path_of("materials"), fmt::format("no material for part '{}' of {} (give material: or materials: {{{}: ...}})", p, file.string(), p));
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
      const Fields f = reader_.fields(node[i], path, {"name", "bottom", "top", "region", "integration", "contact"});
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
      const Fields cf = reader_.fields(cn, cpath, {"pressure", "decay", "mu", "law", "n", "stiffness_ratio", "kt"});
      require(cn, cf, {"pressure", "decay", "mu", "law"});
      contact::ContactPointOptions cp;
      spec.pressure = cp.normal.reference_pressure = positive(cf, "pressure");
      spec.decay = cp.normal.decay = positive(cf, "decay");
      spec.mu = cp.friction_coefficient = positive(cf, "mu");
      spec.law = text(cf, "law");
      reader_.check(cf.find("law")->value, cf.path_of("law"), check_one_of(spec.law, {"gaul-mayer", "jenkins"}));
      spec.exponent = 1.0 / 3.0;
      if (const auto* n = cf.find("n")) {
        spec.exponent = reader_.number(n->value, cf.path_of("n"));
        reader_.check(n->value, cf.path_of("n"), check_open_unit(spec.exponent));
      }
      if (cf.has("kt") && cf.has("stiffness_ratio"))
        reader_.fail(cn, cpath, "give either kt (constant tangential stiffness [Pa/m]) or stiffness_ratio (k_T = χ λ p_N), not both");
      if (cf.has("kt")) {
        cp.stiffness_model = contact::TangentialStiffnessModel::constant;
        spec.tangential_stiffness = cp.tangential_stiffness = positive(cf, "kt");
      } else {
        spec.stiffness_ratio = cp.stiffness_ratio = positive_or(cf, "stiffness_ratio", cp.stiffness_ratio);
      }
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
        const Fields s = reader_.fields(side, f.path_of(role), {"surface", "radius"});
        require(side, s, {"surface", "radius"});
        const std::string surface = surface_name(s.find("surface")->value, s.path_of("surface"), c);
        const double radius = positive(s, "radius");
        if (std::string(role) == "head") o.head_surface = surface, o.head_radius = radius;
        else o.nut_surface = surface, o.nut_radius = radius;
      }
      o.axial_stiffness = positive(f, "stiffness");
      const YAML::Node p = f.find("preload")->value;
      o.preload = reader_.number(p, f.path_of("preload"));
      reader_.check(p, f.path_of("preload"), check_non_negative(o.preload));
      try {
        c.bolts.push_back(preload::build_bolt(c.mesh, o));
      } catch (const std::invalid_argument& error) {
        reader_.fail(node[i], path, error.what());
      }
    }
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

  // ---- analysis ------------------------------------------------------------------------------

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
        if (!(v > 0.0 && v < 1.0)) reader_.fail(s->value, pf.path_of("tolerance"), fmt::format("must be in (0, 1), got {}", v));
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
