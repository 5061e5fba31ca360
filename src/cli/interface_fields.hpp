#pragma once
// Interface and volume fields for ParaView: the contact surfaces of the preload (fe_run.cpp) and
// the snapshots of a damping curve (fe_dynamics_run.cpp, docs/case-files.md "fields").

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "jointhb/fe/interface.hpp"
#include "jointhb/fe/mesh.hpp"
#include "jointhb/hb/interface_balance.hpp"
#include "jointhb/preload/preload_solver.hpp"
#include "jointhb/reduction/field_recovery.hpp"

namespace jointhb::cli {

/// Node values of an interface from its point values: v_i = Σ_p a_p h_i(p) v_p / Σ_p a_p h_i(p)
/// over the bottom face nodes (a lumped L2 projection; with nodal integration the plain average
/// of the points at that node weighted by area). Nodes off the interface get 0.
Eigen::VectorXd node_average(const fe::Interface& iface, const Eigen::VectorXd& point_values, int num_nodes);

/// `name` with every character other than [A-Za-z0-9_-] replaced by '_' (for file names).
std::string file_label(const std::string& name);

/// The bottom-face quads of an interface (for write_quad_surface_vtu).
std::vector<std::vector<int>> interface_quads(const fe::Interface& iface);

/// One accepted point of a damping curve to be written.
struct FieldSnapshot {
  double amplitude = 0.0;  ///< q [m √kg]
  double omega = 0.0;      ///< Ω [rad/s]
  double xi = 0.0;         ///< ξ of the EPMC
  Eigen::VectorXd y;       ///< the balance's unknowns at q (η and gaps, not normalised)
};

struct FieldFiles {
  std::vector<std::filesystem::path> files;  ///< every file written (relative to the output directory)
  double seconds = 0.0;
};

/// Writes, for mode `mode`, under DIR:
///   mode<k>_contact_<interface>.pvd + mode<k>_fields/contact_<interface>_<i>.vtu  (per interface:
///     W_D per unit area per cycle, tangential and normal motion, pressure min/max, open fraction,
///     state 0 stuck / 1 slipping / 2 open, node-averaged from the points of the fine model),
///   mode<k>_contact_points.csv (the same per contact point and snapshot),
///   mode<k>_volume.pvd + mode<k>_fields/volume_<i>.vtu when `recovery` is not empty (the
///     displacement's mean, cos 1 and sin 1 coefficients and first-harmonic amplitude, eq. T-33).
/// The .pvd "timestep" is log10 q. `patch_of_point` maps the fine model's points (the interfaces
/// of `model`, in order) to the balance's points.
FieldFiles write_damping_fields(const std::filesystem::path& dir, int mode, const fe::Mesh& mesh,
                                const preload::PreloadModel& model, const std::vector<int>& patch_of_point,
                                const hb::InterfaceBalance& balance, const reduction::FieldRecovery& recovery,
                                const std::vector<FieldSnapshot>& snapshots);

/// Indices of `count` accepted points spread evenly in log10 q between the first and the last
/// (fewer when the curve has fewer points; always the first and the last).
std::vector<std::size_t> snapshot_indices(const std::vector<double>& amplitudes, int count);

}  // namespace jointhb::cli
