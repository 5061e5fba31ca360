#include "fe_run.hpp"

#include "fe_dynamics_run.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <optional>

#include "jointhb/fe/assembly.hpp"
#include "jointhb/io/csv_writer.hpp"
#include "jointhb/io/stage_cache.hpp"
#include "jointhb/io/vtk_writer.hpp"
#include "jointhb/modal/modes.hpp"
#include "jointhb/preload/preload_solver.hpp"
#include "interface_fields.hpp"

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
  data.add_point_scalars("pressure", node_average(ci.geometry, s.pressure, mesh.num_nodes()));
  data.add_point_scalars("gap", node_average(ci.geometry, gap, mesh.num_nodes()));
  data.add_point_scalars("traction_1", node_average(ci.geometry, t1, mesh.num_nodes()));
  data.add_point_scalars("traction_2", node_average(ci.geometry, t2, mesh.num_nodes()));
  Eigen::VectorXd cell_pressure(static_cast<Eigen::Index>(quads.size()));
  for (std::size_t e = 0; e < ci.geometry.elements.size(); ++e) {
    const auto& el = ci.geometry.elements[e];
    double f = 0.0;
    for (int p = el.first_point; p < el.first_point + el.num_points; ++p)
      f += ci.geometry.points[static_cast<std::size_t>(p)].area * s.pressure[p];
    cell_pressure[static_cast<Eigen::Index>(e)] = f / el.area;
  }
  data.add_cell_scalars("mean_pressure", cell_pressure);
  io::write_quad_surface_vtu(dir / ("contact_" + label + ".vtu"), mesh.coordinates, quads, data);
}

}  // namespace

int run_fe_case(const io::FeCase& c, const std::filesystem::path& dir, Clock::time_point start,
                const FeRunOptions& run_options) {
  const bool tty = isatty(fileno(stderr)) != 0;
  for (const std::string& w : c.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  ordered_json summary;
  summary["case"] = c.source;
  summary["kind"] = "fe";
  summary["model"] = {{"nodes", c.mesh.num_nodes()},
                      {"elements", c.mesh.num_elements()},
                      {"dofs", c.mesh.num_dofs()},
                      {"parts", c.mesh.parts}};
  int code = 0;
  io::StageCache cache(run_options.cache_dir.empty() ? dir / ".cache" : run_options.cache_dir,
                       run_options.use_cache);
  summary["cache"] = {{"enabled", cache.enabled()}, {"directory", cache.directory().string()}};

  // ---- structure -------------------------------------------------------------------------
  const preload::PreloadModel model = io::preload_model(c);
  const fe::StructuralMatrices& structure = model.structure;
  summary["model"]["mass_kg"] = structure.total_mass;
  summary["timings"]["assembly_seconds"] = structure.seconds;
  std::fprintf(stderr, "model: %d nodes, %d elements, %d DOFs, mass %.4g kg (assembly %.2f s)\n",
               c.mesh.num_nodes(), c.mesh.num_elements(), c.mesh.num_dofs(), structure.total_mass,
               structure.seconds);

  // ---- preload ---------------------------------------------------------------------------
  Eigen::SparseMatrix<double> stiffness = structure.stiffness;
  fe::DofMap dofs = fe::DofMap::from_fixed_nodes(c.mesh.num_nodes(), c.constraints);
  // The dynamic stage needs the preloaded state and the modes about it (defaults when the case
  // does not give analysis.preload / analysis.modes).
  const bool dynamics = c.dynamics.has_value();
  const std::optional<modal::ModalOptions> modal_options =
      c.modes ? c.modes : (dynamics ? std::optional<modal::ModalOptions>(modal::ModalOptions{}) : std::nullopt);
  const bool needs_preload =
      c.preload_requested || ((modal_options || dynamics) && (!c.interfaces.empty() || !c.bolts.empty()));
  preload::PreloadResult p;
  modal::ModalResult m;
  if (needs_preload) {
    preload::PreloadOptions options = c.preload;
    if (tty) {
      options.progress = [](int step, int it, double r) {
        std::fprintf(stderr, "\rpreload step %d iteration %d residual %.2e   ", step, it, r);
      };
    }
    const auto cache_start = Clock::now();
    std::optional<preload::PreloadResult> cached = cache.load_preload(c.fingerprints.preload);
    if (cached && (cached->interfaces.size() != c.interfaces.size() ||
                   cached->bolt_forces.size() != c.bolts.size() ||
                   cached->displacement.size() != c.mesh.num_dofs())) {
      std::fprintf(stderr, "warning: stage cache: %s does not fit this model; recomputing preload\n",
                   cache.file("preload", c.fingerprints.preload).string().c_str());
      cached.reset();
    }
    const bool hit = cached.has_value();
    double cache_seconds = 0.0;
    if (hit) {
      p = std::move(*cached);
      cache_seconds = seconds_since(cache_start);
      std::fprintf(stderr, "preload: from cache (%s): %s (solved in %.2f s, read in %.3f s)\n",
                   cache.file("preload", c.fingerprints.preload).string().c_str(), p.message.c_str(),
                   p.seconds, cache_seconds);
    } else {
      p = preload::solve_preload(model, options);
      if (tty) std::fprintf(stderr, "\n");
      std::fprintf(stderr, "preload: %s (%.2f s)\n", p.message.c_str(), p.seconds);
      if (p.converged) {
        const auto store_start = Clock::now();
        cache.store_preload(c.fingerprints.preload, p);
        cache_seconds = seconds_since(store_start);
      }
    }
    {
      io::CsvWriter steps(dir / "preload_steps.csv",
                          {"step", "load_factor", "iterations", "line_search_cuts", "residual", "converged"});
      for (std::size_t k = 0; k < p.steps.size(); ++k) {
        const auto& s = p.steps[k];
        steps.write_row({static_cast<double>(k + 1), s.load_factor, static_cast<double>(s.iterations),
                         static_cast<double>(s.line_search_cuts), s.residual, s.converged ? 1.0 : 0.0});
      }
    }
    ordered_json pj;
    pj["status"] = p.converged ? "converged" : "failed";
    pj["message"] = p.message;
    pj["load_factor"] = p.load_factor;
    pj["newton_iterations"] = p.total_iterations;
    pj["factorizations"] = p.factor.factorizations;
    pj["support"] = p.support_dofs.empty() ? "user constraints" : "3-2-1 (statically determinate)";
    pj["support_reaction_relative"] = p.support_reaction;
    pj["factor"] = p.factor_statistics;
    pj["bolts"] = ordered_json::array();
    for (std::size_t b = 0; b < c.bolts.size(); ++b)
      pj["bolts"].push_back({{"name", c.bolts[b].name}, {"force", p.bolt_forces[b]},
                             {"head_nodes", c.bolts[b].head_nodes.size()},
                             {"nut_nodes", c.bolts[b].nut_nodes.size()}});
    pj["interfaces"] = ordered_json::array();
    for (std::size_t i = 0; i < p.interfaces.size(); ++i) {
      const auto& r = p.interfaces[i];
      pj["interfaces"].push_back({{"name", r.name},
                                  {"points", c.interfaces[i].geometry.num_points()},
                                  {"area", c.interfaces[i].geometry.total_area},
                                  {"clamping_force", r.clamping_force},
                                  {"closed_area_fraction", r.closed_area_fraction},
                                  {"mean_pressure", r.mean_pressure},
                                  {"max_pressure", r.max_pressure},
                                  {"min_gap", r.min_gap},
                                  {"max_gap", r.max_gap}});
      std::fprintf(stderr, "  interface %s: clamping force %.6g N, closed area %.1f %%, max pressure %.4g Pa\n",
                   r.name.c_str(), r.clamping_force, 100.0 * r.closed_area_fraction, r.max_pressure);
      write_interface(dir, c.mesh, c.interfaces[i], r);
    }
    pj["seconds"] = {{"total", p.seconds}, {"contact", p.contact_seconds},
                     {"assembly", p.assembly_seconds}, {"factor_and_solve", p.factor_seconds}};
    pj["cache"] = hit ? "hit" : "miss";
    pj["cache_seconds"] = cache_seconds;
    summary["preload"] = pj;
    io::VtkData data;
    data.add_point_dofs("displacement", p.displacement);
    io::write_vtu(dir / "preload.vtu", c.mesh, data);
    if (!p.converged) code = 1;
    stiffness = p.dynamic_stiffness;
  }

  // ---- modes -----------------------------------------------------------------------------
  if (modal_options && code == 0) {
    const auto cache_start = Clock::now();
    std::optional<modal::ModalResult> cached = cache.load_modes(c.fingerprints.modes);
    if (cached && cached->shapes.rows() != dofs.num_free()) {
      std::fprintf(stderr, "warning: stage cache: %s does not fit this model; recomputing modes\n",
                   cache.file("modes", c.fingerprints.modes).string().c_str());
      cached.reset();
    }
    const bool hit = cached.has_value();
    double cache_seconds = 0.0;
    if (hit) {
      m = std::move(*cached);
      cache_seconds = seconds_since(cache_start);
      std::fprintf(stderr, "modes: from cache (%s): %s (read in %.3f s)\n",
                   cache.file("modes", c.fingerprints.modes).string().c_str(), m.brief().c_str(),
                   cache_seconds);
    } else {
      const Eigen::SparseMatrix<double> K = dofs.restrict(stiffness);
      const Eigen::SparseMatrix<double> M = dofs.restrict(structure.mass);
      m = modal::compute_modes(K, M, *modal_options);
      std::fprintf(stderr, "modes: %s\n", m.brief().c_str());
      if (m.status == modal::ModalStatus::converged) {
        const auto store_start = Clock::now();
        cache.store_modes(c.fingerprints.modes, m);
        cache_seconds = seconds_since(store_start);
      }
    }
    io::CsvWriter csv(dir / "modes.csv", {"mode", "frequency_hz", "eigenvalue", "residual", "backward_error"});
    io::VtkData data;
    std::vector<std::pair<double, std::filesystem::path>> collection;
    for (Eigen::Index j = 0; j < m.eigenvalues.size(); ++j) {
      csv.write_row({static_cast<double>(j + 1), m.frequencies_hz[j], m.eigenvalues[j], m.residuals[j],
                     m.backward_errors[j]});
      data.add_point_dofs(fmt::format("mode_{}", j + 1), dofs.expand(m.shapes.col(j)));
    }
    if (m.eigenvalues.size() > 0) io::write_vtu(dir / "modes.vtu", c.mesh, data);
    ordered_json mj;
    mj["status"] = m.status == modal::ModalStatus::converged ? "converged" : "failed";
    mj["message"] = m.message;
    mj["frequencies_hz"] = std::vector<double>(m.frequencies_hz.data(), m.frequencies_hz.data() + m.frequencies_hz.size());
    mj["max_residual"] = m.residuals.size() ? m.residuals.maxCoeff() : 0.0;
    mj["max_backward_error"] = m.backward_errors.size() ? m.backward_errors.maxCoeff() : 0.0;
    mj["shift"] = m.shift;
    mj["iterations"] = m.iterations;
    mj["seconds"] = m.seconds;
    mj["cache"] = hit ? "hit" : "miss";
    mj["cache_seconds"] = cache_seconds;
    summary["modes"] = mj;
    if (m.status != modal::ModalStatus::converged) code = 1;
  }

  // ---- condensation, damping curves, FRFs ---------------------------------------------------
  if (dynamics && code == 0) {
    if (c.interfaces.empty()) {
      std::fprintf(stderr, "error: analysis.nonlinear_modes / frf need a model with interfaces (model.interfaces)\n");
      code = 1;
    } else {
      write_summary(dir / "summary.json", summary);
      try {
        code = run_fe_dynamics(c, model, p, m, dir, cache, summary);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        summary["message"] = e.what();
        code = 1;
      }
    }
  }
  summary["status"] = code == 0 ? "ok" : "failed";
  summary["seconds"] = seconds_since(start);
  write_summary(dir / "summary.json", summary);
  std::fprintf(stderr, "done in %.2f s -> %s\n", seconds_since(start), dir.string().c_str());
  return code;
}

}  // namespace jointhb::cli
