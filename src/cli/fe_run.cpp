#include "fe_run.hpp"

#include "fe_dynamics_run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include "jointhb/fe/assembly.hpp"
#include "jointhb/io/csv_writer.hpp"
#include "jointhb/io/stage_cache.hpp"
#include "jointhb/io/vtk_writer.hpp"
#include "jointhb/modal/modes.hpp"
#include "jointhb/pipeline/fe_pipeline.hpp"
#include "jointhb/preload/preload_solver.hpp"
#include "cli_support.hpp"
#include "interface_fields.hpp"
#include "status_json.hpp"

namespace jointhb::cli {
namespace {

using nlohmann::ordered_json;

void write_interface(const std::filesystem::path& dir, const fe::Mesh& mesh,
                     const preload::ContactInterface& ci, const preload::InterfaceResult& r) {
  const std::string label = file_label(ci.geometry.name);
  io::CsvWriter csv(dir / ("contact_" + label + ".csv"),
                    {"point", "x", "y", "z", "area", "pressure", "gap", "slip_1", "slip_2",
                     "traction_1", "traction_2", "open"});
  const auto& s = r.state;
  for (std::size_t p = 0; p < ci.geometry.points.size(); ++p) {
    const auto i = static_cast<Eigen::Index>(p);
    const auto& pt = ci.geometry.points[p];
    csv.write_row({static_cast<double>(p), pt.position.x(), pt.position.y(), pt.position.z(),
                   pt.area, s.pressure[i], s.gap[3 * i + 2], s.gap[3 * i], s.gap[3 * i + 1],
                   s.traction[3 * i], s.traction[3 * i + 1], s.open[p] ? 1.0 : 0.0});
  }
  const std::vector<std::vector<int>> quads = interface_quads(ci.geometry);
  const Eigen::Index points = ci.geometry.num_points();
  Eigen::VectorXd gap(points), t1(points), t2(points);
  for (Eigen::Index p = 0; p < points; ++p)
    gap[p] = s.gap[3 * p + 2], t1[p] = s.traction[3 * p], t2[p] = s.traction[3 * p + 1];
  io::VtkData data;
  const Eigen::VectorXd node_pressure = node_average(ci.geometry, s.pressure, mesh.num_nodes());
  data.add_point_scalars("pressure", node_pressure);
  data.add_point_scalars("gap", node_average(ci.geometry, gap, mesh.num_nodes()));
  data.add_point_scalars("traction_1", node_average(ci.geometry, t1, mesh.num_nodes()));
  data.add_point_scalars("traction_2", node_average(ci.geometry, t2, mesh.num_nodes()));
  Eigen::VectorXd cell_pressure(static_cast<Eigen::Index>(quads.size()));
  for (std::size_t e = 0; e < ci.geometry.elements.size(); ++e) {
    const auto& el = ci.geometry.elements[e];
    double f = 0.0;
    if (ci.geometry.meshes == fe::InterfaceMeshes::matching || ci.geometry.integration == fe::InterfaceIntegration::gauss) {
      for (int p = el.first_point; p < el.first_point + el.num_points; ++p)
        f += ci.geometry.points[static_cast<std::size_t>(p)].area * s.pressure[p];
      f /= el.area;
    } else {  // dual mortar: a node's point is shared by the faces around it
      for (int n : el.bottom_nodes) f += node_pressure[n];
      f /= static_cast<double>(el.bottom_nodes.size());
    }
    cell_pressure[static_cast<Eigen::Index>(e)] = f;
  }
  data.add_cell_scalars("mean_pressure", cell_pressure);
  io::write_quad_surface_vtu(dir / ("contact_" + label + ".vtu"), mesh.coordinates, quads, data);
}

// The static loads besides the bolts, each with its resultant at the full load (s = 1).
ordered_json static_loads_json(const io::FeCase& c) {
  ordered_json loads = ordered_json::array();
  const auto add = [&](const std::string& label, const char* kind, const fe::StaticLoads& one) {
    const fe::LoadResultant r = fe::load_resultant(c.mesh, fe::static_load_vector(c.mesh, one));
    loads.push_back({{"where", label}, {"kind", kind}, {"resultant", {r.force.x(), r.force.y(), r.force.z()}}});
  };
  for (const fe::NodalForces& f : c.loads.forces) add(f.label, "nodal forces", {{f}, {}});
  for (const fe::SurfacePressure& p : c.loads.pressures) add(p.label, "pressure", {{}, {p}});
  return loads;
}

// The bonded surfaces (fe/tie.hpp): what each ties and its penalty k = α E_max / h (TIE-2).
ordered_json ties_json(const io::FeCase& c) {
  ordered_json ties = ordered_json::array();
  for (std::size_t k = 0; k < c.ties.size(); ++k) {
    const fe::Tie& t = c.ties[k];
    ties.push_back({{"name", t.name},
                    {"slave", t.slave_surface},
                    {"master", t.master_surface},
                    {"where", c.tie_sources[k]},
                    {"points", t.num_tied_points()},
                    {"area", t.area},
                    {"penalty", t.penalty},
                    {"penalty_factor", t.penalty_factor},
                    {"youngs_modulus", t.youngs_modulus},
                    {"element_size", t.element_size}});
  }
  return ties;
}

// Where a bolt clamps, for maps of the contact surface (jointhb_plot.py draws it): the centroid of
// its head footprint, its axis, and the footprint's inner (hole, B-4) and outer radius about the
// axis [m].
ordered_json footprint_json(const fe::Mesh& mesh, const preload::Bolt& bolt) {
  if (bolt.head_nodes.empty()) return ordered_json::object();
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  for (const int n : bolt.head_nodes) center += mesh.coordinates.col(n);
  center /= static_cast<double>(bolt.head_nodes.size());
  double outer = 0.0;
  for (const int n : bolt.head_nodes) {
    const Eigen::Vector3d d = mesh.coordinates.col(n) - center;
    outer = std::max(outer, (d - d.dot(bolt.axis) * bolt.axis).norm());
  }
  return {{"center", {center.x(), center.y(), center.z()}},
          {"axis", {bolt.axis.x(), bolt.axis.y(), bolt.axis.z()}},
          {"hole_radius", bolt.head_inner_radius},
          {"footprint_radius", outer}};
}

ordered_json preload_json(const io::FeCase& c, const preload::PreloadResult& p, const pipeline::StageInfo& info) {
  ordered_json pj;
  put_status(pj, p.status());
  pj["load_factor"] = p.load_factor;
  pj["newton_iterations"] = p.total_iterations;
  pj["factorizations"] = p.factor.factorizations;
  pj["support"] = p.support_dofs.empty() ? "user constraints" : "3-2-1 (statically determinate)";
  pj["support_reaction_relative"] = p.support_reaction;
  pj["factor"] = p.factor_statistics;
  pj["bolts"] = ordered_json::array();
  for (std::size_t b = 0; b < c.bolts.size(); ++b) {
    ordered_json bj = {{"name", c.bolts[b].name}, {"force", p.bolt_forces[b]},
                       {"head_nodes", c.bolts[b].head_nodes.size()}, {"nut_nodes", c.bolts[b].nut_nodes.size()}};
    bj.update(footprint_json(c.mesh, c.bolts[b]));
    pj["bolts"].push_back(std::move(bj));
  }
  pj["static_loads"] = static_loads_json(c);
  pj["interfaces"] = ordered_json::array();
  for (std::size_t i = 0; i < p.interfaces.size(); ++i) {
    const auto& r = p.interfaces[i];
    const fe::Interface& g = c.interfaces[i].geometry;
    pj["interfaces"].push_back({{"name", r.name},
                                {"meshes", fe::to_string(g.meshes)},
                                {"points", g.num_points()},
                                {"area", g.total_area},
                                {"uncovered_area", g.uncovered_area},
                                {"clamping_force", r.clamping_force},
                                {"closed_area_fraction", r.closed_area_fraction},
                                {"mean_pressure", r.mean_pressure},
                                {"max_pressure", r.max_pressure},
                                {"min_gap", r.min_gap},
                                {"max_gap", r.max_gap}});
  }
  pj["seconds"] = {{"total", p.seconds}, {"contact", p.contact_seconds},
                   {"assembly", p.assembly_seconds}, {"factor_and_solve", p.factor_seconds}};
  pj["cache"] = info.from_store ? "hit" : "miss";
  pj["cache_seconds"] = info.store_seconds;
  return pj;
}

// The preload stage's outputs: preload_steps.csv, contact_<iface>.csv/.vtu, preload.vtu.
void write_preload(const std::filesystem::path& dir, const io::FeCase& c, const preload::PreloadResult& p) {
  io::CsvWriter steps(dir / "preload_steps.csv",
                      {"step", "load_factor", "iterations", "line_search_cuts", "residual", "converged"});
  for (std::size_t k = 0; k < p.steps.size(); ++k) {
    const auto& s = p.steps[k];
    // A step that failed on a non-finite residual has no residual to write: -1 (docs/cli.md).
    steps.write_row({static_cast<double>(k + 1), s.load_factor, static_cast<double>(s.iterations),
                     static_cast<double>(s.line_search_cuts), std::isfinite(s.residual) ? s.residual : -1.0,
                     s.status().ok() ? 1.0 : 0.0});
  }
  for (std::size_t i = 0; i < p.interfaces.size(); ++i) {
    const auto& r = p.interfaces[i];
    std::fprintf(stderr, "  interface %s: clamping force %.6g N, closed area %.1f %%, max pressure %.4g Pa\n",
                 r.name.c_str(), r.clamping_force, 100.0 * r.closed_area_fraction, r.max_pressure);
    write_interface(dir, c.mesh, c.interfaces[i], r);
  }
  io::VtkData data;
  data.add_point_dofs("displacement", p.displacement);
  io::write_vtu(dir / "preload.vtu", c.mesh, data);
}

// The modes stage's outputs: modes.csv, modes.vtu.
void write_modes(const std::filesystem::path& dir, const io::FeCase& c, const fe::DofMap& dofs,
                 const modal::ModalResult& m) {
  io::CsvWriter csv(dir / "modes.csv", {"mode", "frequency_hz", "eigenvalue", "residual", "backward_error"});
  io::VtkData data;
  for (Eigen::Index j = 0; j < m.eigenvalues.size(); ++j) {
    csv.write_row({static_cast<double>(j + 1), m.frequencies_hz[j], m.eigenvalues[j], m.residuals[j],
                   m.backward_errors[j]});
    data.add_point_dofs(fmt::format("mode_{}", j + 1), dofs.expand(m.shapes.col(j)));
  }
  if (m.eigenvalues.size() > 0) io::write_vtu(dir / "modes.vtu", c.mesh, data);
}

ordered_json modes_json(const modal::ModalResult& m, const pipeline::StageInfo& info) {
  ordered_json mj;
  put_status(mj, m.status());
  mj["frequencies_hz"] = std::vector<double>(m.frequencies_hz.data(), m.frequencies_hz.data() + m.frequencies_hz.size());
  mj["max_residual"] = m.residuals.size() ? m.residuals.maxCoeff() : 0.0;
  mj["max_backward_error"] = m.backward_errors.size() ? m.backward_errors.maxCoeff() : 0.0;
  mj["shift"] = m.shift;
  mj["iterations"] = m.iterations;
  mj["seconds"] = m.seconds;
  mj["cache"] = info.from_store ? "hit" : "miss";
  mj["cache_seconds"] = info.store_seconds;
  return mj;
}

}  // namespace

int run_fe_case(const io::FeCase& c, const std::filesystem::path& dir, Clock::time_point start,
                const FeRunOptions& run_options) {
  const bool tty = stderr_is_terminal();
  for (const std::string& w : c.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  ordered_json summary;
  summary["case"] = c.source;
  summary["kind"] = "fe";
  summary["model"] = {{"nodes", c.mesh.num_nodes()},
                      {"elements", c.mesh.num_elements()},
                      {"dofs", c.mesh.num_dofs()},
                      {"parts", c.mesh.parts}};
  if (!c.ties.empty()) summary["model"]["ties"] = ties_json(c);
  std::vector<NamedStatus> parts;  // the stages and curves run, for the run's status
  const auto all_ok = [&parts] { return worst(parts).ok(); };
  auto cache = std::make_shared<io::StageCache>(run_options.cache_dir.empty() ? dir / ".cache" : run_options.cache_dir,
                                                run_options.use_cache);
  summary["cache"] = {{"enabled", cache->enabled()}, {"directory", cache->directory().string()}};
  write_summary(dir / "summary.json", summary);  // "status": "running" before any stage
  pipeline::FeAnalysis analysis = c;
  analysis.solvers = run_options.solvers;
  summary["solvers"] = {{"linear", fe::to_string(run_options.solvers.linear)},
                        {"eigen", run_options.solvers.eigen == modal::ModalOptions::EigenSolver::slepc ? "slepc" : "arpack"},
                        {"ranks", run_options.ranks}};
  if (run_options.solvers.linear == fe::LinearSolver::cg) {
    summary["solvers"]["preconditioner"] = fe::to_string(run_options.solvers.iterative.preconditioner);
    summary["solvers"]["relative_tolerance"] = run_options.solvers.iterative.relative_tolerance;
  }
  // Progress of the preload: every Newton iteration on a terminal, the heartbeat's line in a log.
  analysis.preload.progress = [tty](int step, int it, double r) {
    if (tty)
      std::fprintf(stderr, "\rpreload step %d iteration %d residual %.2e   ", step, it, r);
    else
      progress_activity("preload step {} iteration {} residual {:.2e}", step, it, r);
  };
  pipeline::FePipeline pipe(c, std::move(analysis), cache);

  // ---- structure -------------------------------------------------------------------------
  progress_activity("assembly of the model");
  const fe::StructuralMatrices& structure = pipe.structure().structure;
  summary["model"]["mass_kg"] = structure.total_mass;
  summary["timings"]["assembly_seconds"] = structure.seconds;
  std::fprintf(stderr, "model: %d nodes, %d elements, %d DOFs, mass %.4g kg (assembly %.2f s)\n",
               c.mesh.num_nodes(), c.mesh.num_elements(), c.mesh.num_dofs(), structure.total_mass,
               structure.seconds);
  for (const fe::Tie& t : c.ties)
    std::fprintf(stderr, "  tie %s: slave %s, master %s, %d points, area %.6g m^2, penalty %.4g Pa/m\n", t.name.c_str(),
                 t.slave_surface.c_str(), t.master_surface.c_str(), t.num_tied_points(), t.area, t.penalty);

  // ---- preload ---------------------------------------------------------------------------
  if (pipe.needs_preload()) {
    progress_activity("preload");
    const preload::PreloadResult& p = pipe.preload();
    const pipeline::StageInfo& info = pipe.preload_info();
    if (!info.warning.empty()) std::fprintf(stderr, "warning: stage cache: %s\n", info.warning.c_str());
    if (info.from_store) {
      std::fprintf(stderr, "preload: from cache (%s): %s (solved in %.2f s, read in %.3f s)\n", info.location.c_str(),
                   p.status().brief().c_str(), p.seconds, info.store_seconds);
    } else {
      if (tty) std::fprintf(stderr, "\n");
      std::fprintf(stderr, "preload: %s (%.2f s)\n", p.status().brief().c_str(), p.seconds);
    }
    write_preload(dir, c, p);
    summary["preload"] = preload_json(c, p, info);
    parts.push_back({"preload", p.status()});
  }

  // ---- modes -----------------------------------------------------------------------------
  if (pipe.modal_options() && all_ok()) {
    progress_activity("modes");
    const modal::ModalResult& m = pipe.modes();
    const pipeline::StageInfo& info = pipe.modes_info();
    if (!info.warning.empty()) std::fprintf(stderr, "warning: stage cache: %s\n", info.warning.c_str());
    if (info.from_store)
      std::fprintf(stderr, "modes: from cache (%s): %s (read in %.3f s)\n", info.location.c_str(), m.brief().c_str(),
                   info.store_seconds);
    else
      std::fprintf(stderr, "modes: %s\n", m.brief().c_str());
    write_modes(dir, c, pipe.dofs(), m);
    summary["modes"] = modes_json(m, info);
    parts.push_back({"modes", m.status()});
  }

  // ---- condensation, damping curves, FRFs ---------------------------------------------------
  if (c.dynamics && all_ok()) {
    if (c.interfaces.empty()) {
      parts.push_back({"dynamics", {Termination::failed, "analysis.nonlinear_modes / frf need a model with interfaces (model.interfaces)"}});
    } else {
      write_summary(dir / "summary.json", summary);
      try {
        const std::vector<NamedStatus> curves = run_fe_dynamics(pipe, dir, summary);
        parts.insert(parts.end(), curves.begin(), curves.end());
      } catch (const std::exception& e) {
        parts.push_back({"dynamics", {Termination::failed, e.what()}});
      }
    }
  }
  const Status run = worst(parts);
  put_run_status(summary, run);
  summary["seconds"] = seconds_since(start);
  write_summary(dir / "summary.json", summary);
  if (!run.ok()) {
    // One error line in the form of every jointhb error, and no "done": a script reading stderr
    // must not take a failed run for a finished one (the exit code says the same).
    std::fprintf(stderr, "jointhb run: %s: failed: %s (after %.2f s; results so far in %s)\n", c.source.c_str(),
                 io::printable_one_line(run.message).c_str(), seconds_since(start), dir.string().c_str());
    return exit_failure;
  }
  stop_progress_heartbeat();  // no progress line after the run's last one (cli.run_progress_log)
  std::fprintf(stderr, "done in %.2f s -> %s\n", seconds_since(start), dir.string().c_str());
  return exit_ok;
}

}  // namespace jointhb::cli
