#include "jointhb/io/vtk_writer.hpp"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <set>
#include <span>
#include <array>
#include <stdexcept>

namespace jointhb::io {

void VtkData::add_point_scalars(std::string name, const Eigen::VectorXd& values) {
  point_data.push_back({std::move(name), values.transpose()});
}
void VtkData::add_point_vectors(std::string name, const Eigen::Matrix3Xd& values) {
  point_data.push_back({std::move(name), values});
}
void VtkData::add_point_dofs(std::string name, const Eigen::VectorXd& dofs) {
  if (dofs.size() % 3 != 0)
    throw std::invalid_argument("VtkData::add_point_dofs: '" + name + "' has " +
                                std::to_string(dofs.size()) + " entries, not a multiple of 3");
  point_data.push_back({std::move(name), dofs.reshaped(3, dofs.size() / 3)});
}
void VtkData::add_cell_scalars(std::string name, const Eigen::VectorXd& values) {
  cell_data.push_back({std::move(name), values.transpose()});
}

namespace {

enum class Kind { float64, int64, int32, uint8 };

const char* type_name(Kind kind) {
  switch (kind) {
    case Kind::float64:
      return "Float64";
    case Kind::int64:
      return "Int64";
    case Kind::int32:
      return "Int32";
    case Kind::uint8:
      return "UInt8";
  }
  return "?";
}

std::size_t value_bytes(Kind kind) {
  switch (kind) {
    case Kind::float64:
      return 8;
    case Kind::int64:
      return 8;
    case Kind::int32:
      return 4;
    case Kind::uint8:
      return 1;
  }
  return 0;
}

// One DataArray: `count` tuples of `components` values at `data` (interleaved).
struct Block {
  std::string name;
  Kind kind = Kind::float64;
  long components = 1;
  std::size_t count = 0;
  const void* data = nullptr;
  [[nodiscard]] std::size_t values() const { return count * static_cast<std::size_t>(components); }
  [[nodiscard]] std::size_t bytes() const { return values() * value_bytes(kind); }
};

std::string xml_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

template <class T>
void append_number(std::string& out, T value) {
  char text[32];
  const auto [end, error] = std::to_chars(text, text + sizeof text, value);
  out.append(text, end);
}

void write_ascii_values(std::ofstream& file, const Block& block) {
  std::string line;
  const auto per_line = static_cast<std::size_t>(block.components);
  for (std::size_t k = 0; k < block.values(); ++k) {
    switch (block.kind) {
      case Kind::float64:
        append_number(line, static_cast<const double*>(block.data)[k]);
        break;
      case Kind::int64:
        append_number(line, static_cast<const std::int64_t*>(block.data)[k]);
        break;
      case Kind::int32:
        append_number(line, static_cast<const std::int32_t*>(block.data)[k]);
        break;
      case Kind::uint8:
        append_number(line, static_cast<unsigned>(static_cast<const std::uint8_t*>(block.data)[k]));
        break;
    }
    if ((k + 1) % per_line == 0 || k + 1 == block.values()) {
      line += '\n';
      file << line;
      line.clear();
    } else {
      line += ' ';
    }
  }
}

// The data arrays of `arrays`, checked against `count` entries; `reserved` may not be used.
std::vector<Block> data_blocks(const std::vector<VtkArray>& arrays, std::size_t count,
                               const char* where, const std::string& reserved) {
  std::vector<Block> blocks;
  std::set<std::string> names;
  for (const auto& array : arrays) {
    const std::string context = std::string("VTK ") + where + " array '" + array.name + "'";
    if (array.name.empty())
      throw std::invalid_argument(std::string("VTK ") + where + " array without a name");
    if (array.name == reserved)
      throw std::invalid_argument(context + ": the name is reserved for the writer's own array");
    if (!names.insert(array.name).second)
      throw std::invalid_argument(context + ": name used twice");
    if (array.values.rows() < 1) throw std::invalid_argument(context + ": no components");
    if (static_cast<std::size_t>(array.values.cols()) != count)
      throw std::invalid_argument(context + ": " + std::to_string(array.values.cols()) +
                                  " entries, expected " + std::to_string(count));
    for (Eigen::Index k = 0; k < array.values.size(); ++k)
      if (!std::isfinite(array.values.data()[k]))
        throw std::invalid_argument(context + ": entry " + std::to_string(k / array.values.rows()) +
                                    " is not finite");
    blocks.push_back({array.name, Kind::float64, static_cast<long>(array.values.rows()), count,
                      array.values.data()});
  }
  return blocks;
}

struct Grid {
  const Eigen::Matrix3Xd* points = nullptr;
  std::vector<std::int64_t> connectivity, offsets;
  std::vector<std::uint8_t> types;
  std::vector<Block> point_blocks, cell_blocks;
};

void write_grid(const std::filesystem::path& path, const Grid& grid, const VtkOptions& options) {
  if (options.ascii_limit < 0)
    throw std::invalid_argument("VtkOptions::ascii_limit: must be >= 0, got " +
                                std::to_string(options.ascii_limit));
  for (Eigen::Index k = 0; k < grid.points->size(); ++k)
    if (!std::isfinite(grid.points->data()[k]))
      throw std::invalid_argument("VTK points: coordinate of node " + std::to_string(k / 3) +
                                  " is not finite");
  const std::size_t n_points = static_cast<std::size_t>(grid.points->cols());
  const std::size_t n_cells = grid.types.size();
  const Block points{"Points", Kind::float64, 3, n_points, grid.points->data()};
  const Block connectivity{"connectivity", Kind::int64, 1, grid.connectivity.size(),
                           grid.connectivity.data()};
  const Block offsets{"offsets", Kind::int64, 1, n_cells, grid.offsets.data()};
  const Block types{"types", Kind::uint8, 1, n_cells, grid.types.data()};

  std::size_t total_values = points.values() + connectivity.values() + 2 * n_cells;
  for (const auto& b : grid.point_blocks) total_values += b.values();
  for (const auto& b : grid.cell_blocks) total_values += b.values();
  const bool ascii = options.encoding == VtkEncoding::ascii ||
                     (options.encoding == VtkEncoding::automatic &&
                      total_values <= static_cast<std::size_t>(options.ascii_limit));

  std::ofstream file(path, std::ios::binary);
  if (!file) throw std::runtime_error("cannot open '" + path.string() + "' for writing");

  std::vector<const Block*> appended;  // in offset order
  std::uint64_t next_offset = 0;
  auto data_array = [&](const Block& b) {
    file << "<DataArray type=\"" << type_name(b.kind) << "\" Name=\"" << xml_escape(b.name) << "\"";
    if (b.components != 1) file << " NumberOfComponents=\"" << b.components << "\"";
    if (ascii) {
      file << " format=\"ascii\">\n";
      write_ascii_values(file, b);
      file << "</DataArray>\n";
    } else {
      file << " format=\"appended\" offset=\"" << next_offset << "\"/>\n";
      next_offset += sizeof(std::uint64_t) + b.bytes();
      appended.push_back(&b);
    }
  };

  const char* byte_order =
      std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";
  file << "<?xml version=\"1.0\"?>\n"
       << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"" << byte_order
       << "\" header_type=\"UInt64\">\n"
       << "<UnstructuredGrid>\n"
       << "<Piece NumberOfPoints=\"" << n_points << "\" NumberOfCells=\"" << n_cells << "\">\n";
  file << "<PointData>\n";
  for (const auto& b : grid.point_blocks) data_array(b);
  file << "</PointData>\n<CellData>\n";
  for (const auto& b : grid.cell_blocks) data_array(b);
  file << "</CellData>\n<Points>\n";
  data_array(points);
  file << "</Points>\n<Cells>\n";
  data_array(connectivity);
  data_array(offsets);
  data_array(types);
  file << "</Cells>\n</Piece>\n</UnstructuredGrid>\n";
  if (!ascii) {
    // Each block: its byte count as UInt64, then the bytes (the header_type above).
    file << "<AppendedData encoding=\"raw\">\n_";
    for (const Block* b : appended) {
      const std::uint64_t bytes = b->bytes();
      file.write(reinterpret_cast<const char*>(&bytes), sizeof bytes);
      file.write(static_cast<const char*>(b->data), static_cast<std::streamsize>(bytes));
    }
    file << "\n</AppendedData>\n";
  }
  file << "</VTKFile>\n";
  file.close();
  if (!file) throw std::runtime_error("writing '" + path.string() + "' failed");
}

}  // namespace

namespace {

// The VTK cell type of an element and, where the node orders differ, the element's local node of
// each VTK point (VTK file formats, "Linear/Non-linear cell types"; mesh.hpp):
//   hex8 12, hex20 25, tet4 10, tet10 24: VTK's order is Abaqus'.
//   wedge6 13, wedge15 26: VTK's triangle (0,1,2) has its right-hand normal pointing away from
//   (3,4,5), Abaqus' towards it, so each triangle is traversed backwards: VTK (0 1 2 3 4 5) =
//   Abaqus (0 2 1 3 5 4); VTK's mid-edge nodes on (0,1), (1,2), (2,0), (3,4), (4,5), (5,3), (0,3),
//   (1,4), (2,5) are then Abaqus' 8, 7, 6, 11, 10, 9, 12, 14, 13.
struct VtkCell {
  std::uint8_t type;
  std::span<const int> order;  // empty: the same order
};

VtkCell vtk_cell(fe::ElementType type) {
  static constexpr std::array<int, 6> wedge6 = {0, 2, 1, 3, 5, 4};
  static constexpr std::array<int, 15> wedge15 = {0, 2, 1, 3, 5, 4, 8, 7, 6, 11, 10, 9, 12, 14, 13};
  switch (type) {
    case fe::ElementType::tet4: return {10, {}};
    case fe::ElementType::tet10: return {24, {}};
    case fe::ElementType::wedge6: return {13, wedge6};
    case fe::ElementType::wedge15: return {26, wedge15};
    default: return {static_cast<std::uint8_t>(fe::node_count(type) == 20 ? 25 : 12), {}};
  }
}

}  // namespace

void write_vtu(const std::filesystem::path& path, const fe::Mesh& mesh, const VtkData& data,
               const VtkOptions& options) {
  const int n_nodes = mesh.num_nodes();
  Grid grid;
  grid.points = &mesh.coordinates;
  std::vector<std::int32_t> part(mesh.elements.size());
  for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
    const auto& element = mesh.elements[e];
    const VtkCell cell = vtk_cell(element.type);
    const auto nodes = element.node_span();
    for (std::size_t a = 0; a < nodes.size(); ++a) {
      const int node = nodes[cell.order.empty() ? a : static_cast<std::size_t>(cell.order[a])];
      if (node < 0 || node >= n_nodes)
        throw std::invalid_argument("write_vtu: element " + std::to_string(e) + " has node " +
                                    std::to_string(node) + ", outside 0.." +
                                    std::to_string(n_nodes - 1));
      grid.connectivity.push_back(node);
    }
    grid.offsets.push_back(static_cast<std::int64_t>(grid.connectivity.size()));
    grid.types.push_back(cell.type);
    part[e] = element.part;
  }
  grid.point_blocks = data_blocks(data.point_data, static_cast<std::size_t>(n_nodes), "point", "");
  grid.cell_blocks = data_blocks(data.cell_data, mesh.elements.size(), "cell", "part");
  grid.cell_blocks.insert(grid.cell_blocks.begin(),
                          Block{"part", Kind::int32, 1, part.size(), part.data()});
  write_grid(path, grid, options);
}

void write_quad_surface_vtu(const std::filesystem::path& path, const Eigen::Matrix3Xd& coordinates,
                            const std::vector<std::vector<int>>& quads, const VtkData& data,
                            const VtkOptions& options) {
  const auto n_nodes = static_cast<int>(coordinates.cols());
  Grid grid;
  grid.points = &coordinates;
  for (std::size_t q = 0; q < quads.size(); ++q) {
    const auto& quad = quads[q];
    if (quad.size() != 3 && quad.size() != 4 && quad.size() != 6 && quad.size() != 8)
      throw std::invalid_argument("write_quad_surface_vtu: face " + std::to_string(q) + " has " +
                                  std::to_string(quad.size()) + " nodes, expected 3, 4, 6 or 8");
    for (int node : quad) {
      if (node < 0 || node >= n_nodes)
        throw std::invalid_argument("write_quad_surface_vtu: quad " + std::to_string(q) +
                                    " has node " + std::to_string(node) + ", outside 0.." +
                                    std::to_string(n_nodes - 1));
      grid.connectivity.push_back(node);
    }
    grid.offsets.push_back(static_cast<std::int64_t>(grid.connectivity.size()));
    // VTK_TRIANGLE 5, VTK_QUAD 9, VTK_QUADRATIC_TRIANGLE 22, VTK_QUADRATIC_QUAD 23 (same node order
    // as the faces: corners, then the mid-edge nodes)
    grid.types.push_back(quad.size() == 3 ? 5 : quad.size() == 4 ? 9 : quad.size() == 6 ? 22 : 23);
  }
  grid.point_blocks = data_blocks(data.point_data, static_cast<std::size_t>(n_nodes), "point", "");
  grid.cell_blocks = data_blocks(data.cell_data, quads.size(), "cell", "");
  write_grid(path, grid, options);
}

void write_pvd(const std::filesystem::path& path,
               const std::vector<std::pair<double, std::filesystem::path>>& datasets) {
  std::ofstream file(path);
  if (!file) throw std::runtime_error("cannot open '" + path.string() + "' for writing");
  file << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n";
  for (const auto& [timestep, dataset] : datasets) {
    if (!std::isfinite(timestep))
      throw std::invalid_argument("write_pvd: timestep of '" + dataset.string() +
                                  "' is not finite");
    std::string step;
    append_number(step, timestep);
    file << "<DataSet timestep=\"" << step << "\" part=\"0\" file=\""
         << xml_escape(dataset.generic_string()) << "\"/>\n";
  }
  file << "</Collection>\n</VTKFile>\n";
  file.close();
  if (!file) throw std::runtime_error("writing '" + path.string() + "' failed");
}

}  // namespace jointhb::io
