#pragma once
// VTK XML output for ParaView (VTK file format documentation, "XML File Formats",
// https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html):
//   * the volume mesh as an UnstructuredGrid (.vtu): hex8 → VTK_HEXAHEDRON (12), hex20 →
//     VTK_QUADRATIC_HEXAHEDRON (25), tet4 → VTK_TETRA (10), tet10 → VTK_QUADRATIC_TETRA (24) —
//     Abaqus' node order is VTK's (fe/mesh.hpp), so nodes are written as they are; wedge6 →
//     VTK_WEDGE (13), wedge15 → VTK_QUADRATIC_WEDGE (26) with each triangle traversed the other
//     way (VTK's base triangle faces away from the top one: vtk_writer.cpp); cell data "part"
//     (the part index) is always written;
//   * a quad surface (interface facets: 4-node → VTK_QUAD (9), 8-node → VTK_QUADRATIC_QUAD (23),
//     4 corners then the 4 mid-edge nodes, as fe::face_nodes lists them) over the same points;
//   * a .pvd collection of such files (e.g. one per mode, "timestep" = frequency).
// Point and cell data: named Float64 arrays of 1 or 3 components (or any count ≥ 1).
//
// Encoding: ASCII (readable, round-trip exact with 17 significant digits) or raw appended binary
// (<AppendedData encoding="raw">, header_type="UInt64", byte_order of this machine), chosen by
// VtkOptions. Non-finite values are rejected (std::invalid_argument): no NaN reaches a file.

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "jointhb/fe/mesh.hpp"

namespace jointhb::io {

/// One data array: values(c, k) = component c of entry k (point or cell k).
struct VtkArray {
  std::string name;
  Eigen::MatrixXd values;  ///< components × entries
};

/// The point and cell data written with a mesh.
struct VtkData {
  std::vector<VtkArray> point_data;
  std::vector<VtkArray> cell_data;

  void add_point_scalars(std::string name, const Eigen::VectorXd& values);
  void add_point_vectors(std::string name, const Eigen::Matrix3Xd& values);
  /// A vector field given in the mesh's DOF numbering (u[3i + d] = node i, axis d), e.g. a
  /// displacement or a mode shape; size must be a multiple of 3.
  void add_point_dofs(std::string name, const Eigen::VectorXd& dofs);
  void add_cell_scalars(std::string name, const Eigen::VectorXd& values);
};

enum class VtkEncoding {
  automatic,     ///< ASCII up to VtkOptions::ascii_limit values in total, raw appended above
  ascii,         ///< format="ascii"
  appended_raw,  ///< format="appended", <AppendedData encoding="raw">, UInt64 block headers
};

struct VtkOptions {
  VtkEncoding encoding = VtkEncoding::automatic;
  long ascii_limit = 200000;  ///< ≥ 0: values (coordinates + data) up to which automatic is ASCII
};

/// Writes `mesh` (all nodes and elements) with `data` to `path` (.vtu). Point arrays must have
/// mesh.num_nodes() entries, cell arrays mesh.num_elements(); names unique and non-empty ("part"
/// is reserved). Throws std::invalid_argument on inconsistent data and std::runtime_error when
/// the file cannot be written (naming the path).
void write_vtu(const std::filesystem::path& path, const fe::Mesh& mesh, const VtkData& data = {},
               const VtkOptions& options = {});

/// Writes a surface of faces (each 3, 4, 6 or 8 node indices into `coordinates`: tri3, quad4,
/// tri6, quad8; mixed is allowed) to
/// `path` (.vtu). All points are written, so point data has coordinates.cols() entries and a
/// field of the volume mesh can be shown on the interface unchanged; cell arrays have one entry
/// per quad. Same errors as write_vtu.
void write_quad_surface_vtu(const std::filesystem::path& path, const Eigen::Matrix3Xd& coordinates,
                            const std::vector<std::vector<int>>& quads, const VtkData& data = {},
                            const VtkOptions& options = {});

/// Writes a ParaView collection (.pvd) listing `datasets` as (timestep, file) pairs, e.g.
/// (frequency in Hz, "mode_3.vtu"). Relative file names are written as given (ParaView resolves
/// them against the .pvd's folder).
void write_pvd(const std::filesystem::path& path,
               const std::vector<std::pair<double, std::filesystem::path>>& datasets);

}  // namespace jointhb::io
