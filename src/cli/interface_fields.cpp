// Interface and volume fields for ParaView (interface_fields.hpp).
#include "interface_fields.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <array>
#include <cmath>
#include <numbers>

#include "jointhb/io/csv_writer.hpp"
#include "jointhb/io/vtk_writer.hpp"
#include "run_support.hpp"

namespace jointhb::cli {

Eigen::VectorXd node_average(const fe::Interface& iface, const Eigen::VectorXd& point_values, int num_nodes) {
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(num_nodes), weight = Eigen::VectorXd::Zero(num_nodes);
  for (const fe::InterfaceElement& e : iface.elements) {
    for (int p = e.first_point; p < e.first_point + e.num_points; ++p) {
      const fe::InterfacePoint& pt = iface.points[static_cast<std::size_t>(p)];
      for (std::size_t k = 0; k < e.bottom_nodes.size(); ++k) {
        const double w = pt.area * pt.shape[k];
        sum[e.bottom_nodes[k]] += w * point_values[p];
        weight[e.bottom_nodes[k]] += w;
      }
    }
  }
  for (int i = 0; i < num_nodes; ++i) sum[i] = weight[i] != 0.0 ? sum[i] / weight[i] : 0.0;
  return sum;
}

std::string file_label(const std::string& name) {
  std::string s = name;
  for (char& ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_') ch = '_';
  return s;
}

std::vector<std::vector<int>> interface_quads(const fe::Interface& iface) {
  std::vector<std::vector<int>> quads;
  quads.reserve(iface.elements.size());
  for (const auto& e : iface.elements) quads.push_back(e.bottom_nodes);
  return quads;
}

std::vector<std::size_t> snapshot_indices(const std::vector<double>& amplitudes, int count) {
  std::vector<std::size_t> out;
  if (amplitudes.empty() || count <= 0) return out;
  const double a = std::log10(amplitudes.front()), b = std::log10(amplitudes.back());
  const int n = std::max(1, count);
  for (int i = 0; i < n; ++i) {
    const double target = n == 1 ? b : a + (b - a) * i / (n - 1);
    std::size_t best = 0;
    for (std::size_t j = 1; j < amplitudes.size(); ++j)
      if (std::abs(std::log10(amplitudes[j]) - target) < std::abs(std::log10(amplitudes[best]) - target)) best = j;
    if (out.empty() || out.back() != best) out.push_back(best);
  }
  if (out.back() != amplitudes.size() - 1) out.push_back(amplitudes.size() - 1);
  return out;
}

namespace {

// `state`: the code of hb::ContactState (0 stuck, 1 microslip, 2 gross slip, 3 gapping, 4 open);
// `limit_ratio`: max_t |t_T|/(μ p_N), the force ratio it is classified by (hb/contact_state.hpp).
constexpr const char* kPointFields[] = {"dissipation",  "tangential_motion", "normal_motion", "pressure_min",
                                        "pressure_max", "open_fraction",     "limit_ratio",   "state"};
constexpr int kPointFieldCount = static_cast<int>(std::size(kPointFields));

// The fields of one summary in the order of kPointFields.
std::array<double, kPointFieldCount> point_values(const hb::InterfacePointSummary& s) {
  return {s.dissipation,  s.tangential_motion, s.normal_motion, s.pressure_min,
          s.pressure_max, s.open_fraction,     s.limit_ratio,   static_cast<double>(s.state)};
}

}  // namespace

FieldFiles write_damping_fields(const std::filesystem::path& dir, int mode, const fe::Mesh& mesh,
                                const preload::PreloadModel& model, const std::vector<int>& patch_of_point,
                                const hb::InterfaceBalance& balance, const reduction::FieldRecovery& recovery,
                                const std::vector<FieldSnapshot>& snapshots) {
  const auto start = Clock::now();
  FieldFiles out;
  const std::string stem = fmt::format("mode{}", mode);
  const std::filesystem::path sub = stem + "_fields";
  std::filesystem::create_directories(dir / sub);
  const int m = balance.basis().size(), ns = balance.modes();
  std::vector<std::vector<std::pair<double, std::filesystem::path>>> contact_series(model.interfaces.size());
  std::vector<std::pair<double, std::filesystem::path>> volume_series;
  std::vector<std::string> columns = {"snapshot", "amplitude", "frequency_hz", "interface", "point", "x", "y", "z", "area"};
  for (const char* f : kPointFields) columns.emplace_back(f);
  io::CsvWriter csv(dir / (stem + "_contact_points.csv"), columns);
  out.files.emplace_back(stem + "_contact_points.csv");
  for (std::size_t i = 0; i < snapshots.size(); ++i) {
    const FieldSnapshot& s = snapshots[i];
    const double time = std::log10(s.amplitude);
    const std::vector<hb::InterfacePointSummary> summaries = balance.point_summaries(s.y);
    // ---- contact surfaces --------------------------------------------------------------------
    int first = 0;
    for (std::size_t g = 0; g < model.interfaces.size(); ++g) {
      const fe::Interface& iface = model.interfaces[g].geometry;
      const int count = iface.num_points();
      Eigen::MatrixXd values(count, kPointFieldCount);
      for (int q = 0; q < count; ++q) {
        const int c = patch_of_point[static_cast<std::size_t>(first + q)];
        const auto v = point_values(summaries[static_cast<std::size_t>(c)]);
        for (int k = 0; k < kPointFieldCount; ++k) values(q, k) = v[static_cast<std::size_t>(k)];
        const fe::InterfacePoint& pt = iface.points[static_cast<std::size_t>(q)];
        std::vector<double> row = {static_cast<double>(i), s.amplitude, s.omega / (2.0 * std::numbers::pi), static_cast<double>(g),
                                   static_cast<double>(q), pt.position.x(), pt.position.y(), pt.position.z(), pt.area};
        row.insert(row.end(), v.begin(), v.end());
        csv.write_row(row);
      }
      io::VtkData data;
      for (int k = 0; k < kPointFieldCount; ++k) data.add_point_scalars(kPointFields[k], node_average(iface, values.col(k), mesh.num_nodes()));
      const std::filesystem::path file = sub / fmt::format("contact_{}_{}.vtu", file_label(iface.name), i);
      io::write_quad_surface_vtu(dir / file, mesh.coordinates, interface_quads(iface), data);
      contact_series[g].emplace_back(time, file);
      out.files.push_back(file);
      first += count;
    }
    // ---- volume (eq. T-33) ---------------------------------------------------------------------
    if (!recovery.empty()) {
      const Eigen::Map<const Eigen::MatrixXd> eta(s.y.data(), m, ns);
      hb::InterfaceBalanceEvaluation e;
      balance.evaluate(s.y, s.omega, s.xi, {}, false, e);
      const Eigen::MatrixXd u = recovery.displacement(balance.basis(), s.omega, eta, e.contact_force, {});
      const int a1 = balance.basis().cosine_index(1);
      io::VtkData data;
      data.add_point_dofs("mean", u.col(0));
      data.add_point_dofs("cos_1", u.col(a1));
      data.add_point_dofs("sin_1", u.col(a1 + 1));
      // per component: the first harmonic's amplitude √(a₁² + b₁²)
      data.add_point_dofs("amplitude_1", (u.col(a1).array().square() + u.col(a1 + 1).array().square()).sqrt().matrix());
      const std::filesystem::path file = sub / fmt::format("volume_{}.vtu", i);
      io::write_vtu(dir / file, mesh, data);
      volume_series.emplace_back(time, file);
      out.files.push_back(file);
    }
  }
  for (std::size_t g = 0; g < model.interfaces.size(); ++g) {
    const std::filesystem::path pvd = fmt::format("{}_contact_{}.pvd", stem, file_label(model.interfaces[g].geometry.name));
    io::write_pvd(dir / pvd, contact_series[g]);
    out.files.push_back(pvd);
  }
  if (!volume_series.empty()) {
    const std::filesystem::path pvd = stem + "_volume.pvd";
    io::write_pvd(dir / pvd, volume_series);
    out.files.push_back(pvd);
  }
  out.seconds = seconds_since(start);
  return out;
}

}  // namespace jointhb::cli
