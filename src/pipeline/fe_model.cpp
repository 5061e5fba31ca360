// Typed keys of the finite-element stages (pipeline/fe_model.hpp).
#include "jointhb/pipeline/fe_model.hpp"

#include <cmath>

#include "jointhb/contact/gaul_mayer_law.hpp"
#include "jointhb/pipeline/fingerprint.hpp"

#ifndef JOINTHB_VERSION
#define JOINTHB_VERSION "unknown"
#endif

namespace jointhb::pipeline {
namespace {

void add_doubles(Fingerprint& f, const double* data, Eigen::Index n) {
  f.add(static_cast<std::int64_t>(n));
  f.add_bytes(data, static_cast<std::size_t>(n) * sizeof(double));
}

void add_ints(Fingerprint& f, const std::vector<int>& v) { f.add_bytes(v.data(), v.size() * sizeof(int)); }

void add_sparse(Fingerprint& f, Eigen::SparseMatrix<double> a) {
  a.makeCompressed();
  f.add(static_cast<std::int64_t>(a.rows())).add(static_cast<std::int64_t>(a.cols()));
  f.add_bytes(a.outerIndexPtr(), static_cast<std::size_t>(a.outerSize() + 1) * sizeof(int));
  f.add_bytes(a.innerIndexPtr(), static_cast<std::size_t>(a.nonZeros()) * sizeof(int));
  f.add_bytes(a.valuePtr(), static_cast<std::size_t>(a.nonZeros()) * sizeof(double));
}

void add_mesh(Fingerprint& f, const fe::Mesh& mesh) {
  f.add("mesh");
  add_doubles(f, mesh.coordinates.data(), mesh.coordinates.size());
  f.add(mesh.num_elements());
  for (const fe::Element& e : mesh.elements) {
    f.add(static_cast<int>(e.type)).add(e.part);
    const auto nodes = e.node_span();
    f.add_bytes(nodes.data(), nodes.size() * sizeof(int));
  }
}

void add_law(Fingerprint& f, const contact::ContactPoint& law) {
  const contact::ContactPointOptions& o = law.options();
  f.add("law").add(std::string_view(law.law().name())).add(law_exponent(law));
  f.add(o.normal.reference_pressure).add(o.normal.decay).add(o.normal.reference_gap);
  if (o.normal.kind != contact::NormalLawKind::exponential || std::isfinite(o.normal.cutoff_gap))  // absent from older keys
    f.add(static_cast<int>(o.normal.kind)).add(o.normal.cutoff_gap).add(o.normal.penalty_stiffness);
  f.add(o.friction_coefficient).add(static_cast<int>(o.stiffness_model)).add(o.stiffness_ratio);
  f.add(o.tangential_stiffness).add(o.gap_pressure_ratio);
}

void add_interface(Fingerprint& f, const preload::ContactInterface& ci) {
  const fe::Interface& g = ci.geometry;
  f.add("interface").add(static_cast<int>(g.integration)).add(g.num_mesh_nodes).add(g.num_points());
  for (const fe::InterfacePoint& p : g.points) {
    add_doubles(f, p.position.data(), 3);
    add_doubles(f, p.frame.data(), 9);
    f.add(p.area);
  }
  for (const fe::NodePair& n : g.node_pairs) f.add(n.bottom).add(n.top);
  add_sparse(f, g.gap_operator);
  add_law(f, ci.law);
}

void add_bolt(Fingerprint& f, const preload::Bolt& b) {
  f.add("bolt");
  add_doubles(f, b.axis.data(), 3);
  add_ints(f, b.head_nodes);
  add_ints(f, b.nut_nodes);
  f.add(b.head_area).add(b.nut_area).add(b.axial_stiffness).add(b.preload);
  if (b.head_inner_radius != 0.0 || b.nut_inner_radius != 0.0)  // absent from the keys of disc footprints
    f.add("annulus").add(b.head_inner_radius).add(b.nut_inner_radius);
  const Eigen::SparseVector<double>& c = b.coupling;
  f.add(static_cast<std::int64_t>(c.size())).add(static_cast<std::int64_t>(c.nonZeros()));
  f.add_bytes(c.innerIndexPtr(), static_cast<std::size_t>(c.nonZeros()) * sizeof(int));
  f.add_bytes(c.valuePtr(), static_cast<std::size_t>(c.nonZeros()) * sizeof(double));
}

}  // namespace

double law_exponent(const contact::ContactPoint& law) {
  if (const auto* gm = dynamic_cast<const contact::GaulMayerLaw*>(&law.law())) return gm->exponent();
  return 0.0;
}

FeStageKeys fe_stage_keys(const FeModel& model, const FeAnalysis& analysis) {
  FeStageKeys keys;
  Fingerprint m;
  m.add("jointhb fe model").add(fe_stage_version).add(JOINTHB_VERSION);
  add_mesh(m, model.mesh);
  m.add(static_cast<int>(model.material_per_part.size()));
  for (const fe::Material& mat : model.material_per_part) m.add(mat.youngs_modulus).add(mat.poissons_ratio).add(mat.density);
  m.add(static_cast<int>(model.interfaces.size()));
  for (const auto& ci : model.interfaces) add_interface(m, ci);
  m.add(static_cast<int>(model.bolts.size()));
  for (const auto& b : model.bolts) add_bolt(m, b);
  m.add(static_cast<int>(model.constraints.size()));
  for (const fe::FixedNodes& c : model.constraints) {
    add_ints(m, c.nodes);
    m.add(c.directions[0]).add(c.directions[1]).add(c.directions[2]);
  }
  if (!model.loads.empty()) {  // absent from the keys of models without static loads
    const Eigen::VectorXd f = fe::static_load_vector(model.mesh, model.loads);
    m.add("static loads");
    add_doubles(m, f.data(), f.size());
  }
  if (!model.ties.empty()) {  // absent from the keys of models without ties
    m.add("ties").add(static_cast<int>(model.ties.size()));
    for (const fe::Tie& t : model.ties) {
      add_sparse(m, t.geometry.gap_operator);
      add_doubles(m, t.point_area.data(), t.point_area.size());
      m.add(t.penalty);
    }
  }
  keys.model = m.hex();

  const preload::PreloadOptions& p = analysis.preload;
  Fingerprint pk = Fingerprint::chain(keys.model);
  pk.add("preload").add(p.load_steps).add(p.max_iterations).add(p.residual_tolerance).add(p.max_line_search);
  pk.add(p.reuse_factor_ratio).add(p.closed_pressure_fraction);
  keys.preload = pk.hex();

  const modal::ModalOptions o = analysis.modes.value_or(modal::ModalOptions{});
  Fingerprint mk = Fingerprint::chain(keys.preload);
  mk.add("modes").add(o.count).add(o.shift).add(o.tolerance).add(o.max_iterations).add(o.ncv).add(o.seed);
  keys.modes = mk.hex();
  return keys;
}

preload::PreloadModel preload_model(const FeModel& model) {
  preload::PreloadModel p;
  p.mesh = &model.mesh;
  p.structure = fe::assemble(model.mesh, model.material_per_part);
  if (!model.ties.empty()) {
    p.structure.stiffness += fe::tie_stiffness(model.ties, model.mesh.num_dofs());
    p.structure.stiffness.makeCompressed();
  }
  p.interfaces = model.interfaces;
  p.bolts = model.bolts;
  p.constraints = model.constraints;
  p.loads = model.loads;
  p.ties = model.ties;
  return p;
}

}  // namespace jointhb::pipeline
