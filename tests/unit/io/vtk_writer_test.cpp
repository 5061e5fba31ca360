// VTK XML writer: files parse back (here and with Python's xml module), arrays have the
// declared lengths, values round-trip exactly in both encodings.

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>

#include "jointhb/io/vtk_writer.hpp"
#include "unit/io/temp_file.hpp"

namespace {

using jointhb::fe::ElementType;
using jointhb::fe::Mesh;
using jointhb::io::VtkData;
using jointhb::io::VtkEncoding;
using jointhb::io::VtkOptions;
using jointhb::io::testing::TempFile;

// Two hex8 elements (part 0) sharing a face, and one hex20 element (part 1) beside them.
Mesh small_mesh() {
  Mesh mesh;
  std::mt19937 random(5);
  std::uniform_real_distribution<double> jitter(-0.01, 0.01);
  const int n_nodes = 12 + 20;
  mesh.coordinates.resize(3, n_nodes);
  for (int i = 0; i < 12; ++i)  // 3 × 2 × 2 lattice
    mesh.coordinates.col(i) << (i % 3) + jitter(random), ((i / 3) % 2) + jitter(random), i / 6;
  for (int i = 12; i < n_nodes; ++i)
    mesh.coordinates.col(i) << 5.0 + jitter(random), jitter(random), i * 0.1 + 1.0 / 3.0;
  mesh.node_ids.resize(n_nodes);
  for (int i = 0; i < n_nodes; ++i) mesh.node_ids[static_cast<std::size_t>(i)] = i + 1;
  mesh.parts = {"block", "quadratic"};
  jointhb::fe::Element a{ElementType::hex8, 0, {0, 1, 4, 3, 6, 7, 10, 9}};
  jointhb::fe::Element b{ElementType::hex8_incompatible, 0, {1, 2, 5, 4, 7, 8, 11, 10}};
  jointhb::fe::Element c{ElementType::hex20, 1, {}};
  for (int k = 0; k < 20; ++k) c.nodes[static_cast<std::size_t>(k)] = 12 + k;
  mesh.elements = {a, b, c};
  mesh.element_ids = {1, 2, 3};
  return mesh;
}

// Python's xml module parses the file (the XML part before the raw appended block), and every
// DataArray holds as many values as its parent (points, cells) requires; cell offsets and types
// agree. Exit status 0 when all holds.
constexpr const char* kPythonCheck = R"PY(
import struct, sys, xml.etree.ElementTree as ET
data = open(sys.argv[1], 'rb').read()
marker = b'<AppendedData encoding="raw">'
pos = data.find(marker)
if pos >= 0:
    root = ET.fromstring(data[:pos] + b'</VTKFile>')
    start = data.index(b'_', pos) + 1
else:
    root = ET.fromstring(data)
    start = None
assert root.tag == 'VTKFile' and root.get('type') == 'UnstructuredGrid'
assert root.get('header_type') == 'UInt64'
order = '<' if root.get('byte_order') == 'LittleEndian' else '>'
piece = root.find('UnstructuredGrid/Piece')
npts, ncells = int(piece.get('NumberOfPoints')), int(piece.get('NumberOfCells'))
codes = {'Float64': ('d', 8), 'Int64': ('q', 8), 'Int32': ('i', 4), 'UInt8': ('B', 1)}
def values(da):
    code, size = codes[da.get('type')]
    if da.get('format') == 'ascii':
        return [float(t) if code == 'd' else int(t) for t in da.text.split()]
    assert da.get('format') == 'appended' and start is not None
    off = start + int(da.get('offset'))
    (nbytes,) = struct.unpack(order + 'Q', data[off:off + 8])
    assert nbytes % size == 0
    return list(struct.unpack(order + '%d%s' % (nbytes // size, code), data[off + 8:off + 8 + nbytes]))
def check(parent, count):
    for da in parent.findall('DataArray'):
        v = values(da)
        assert len(v) == int(da.get('NumberOfComponents', '1')) * count, da.get('Name')
check(piece.find('PointData'), npts)
check(piece.find('CellData'), ncells)
check(piece.find('Points'), npts)
cells = {da.get('Name'): values(da) for da in piece.find('Cells').findall('DataArray')}
conn, offsets, types = cells['connectivity'], cells['offsets'], cells['types']
assert len(offsets) == ncells and len(types) == ncells
nodes = {9: 4, 23: 8, 12: 8, 25: 20}
previous = 0
for o, t in zip(offsets, types):
    assert o - previous == nodes[t], (o, previous, t)
    previous = o
assert previous == len(conn) and all(0 <= c < npts for c in conn)
)PY";

// The files are also read by an independent parser, /usr/bin/python3 (installed by the setup step,
// .ci/setup): a missing interpreter fails the test instead of skipping the check.
bool python_available() {
  const bool present = std::filesystem::exists("/usr/bin/python3");
  EXPECT_TRUE(present) << "/usr/bin/python3 is missing: the independent check of the file cannot run";
  return present;
}

int run_python_check(const std::filesystem::path& file) {
  TempFile script(".py", kPythonCheck);
  const std::string command =
      "/usr/bin/python3 '" + script.path().string() + "' '" + file.string() + "'";
  return std::system(command.c_str());
}

std::string attribute(const std::string& text, const std::string& name, std::size_t from = 0) {
  const auto pos = text.find(name + "=\"", from);
  if (pos == std::string::npos) return {};
  const auto begin = pos + name.size() + 2;
  return text.substr(begin, text.find('"', begin) - begin);
}

VtkData sample_data(const Mesh& mesh) {
  VtkData data;
  Eigen::VectorXd mode(mesh.num_dofs());
  for (Eigen::Index k = 0; k < mode.size(); ++k)
    mode(k) = std::sin(0.3 * static_cast<double>(k)) / 3.0;
  data.add_point_dofs("mode_1", mode);
  data.add_point_scalars("temperature", Eigen::VectorXd::LinSpaced(mesh.num_nodes(), 0.0, 1.0));
  data.add_cell_scalars("von_mises", Eigen::Vector3d(1.5e8, 2.25e8, 1.0 / 7.0));
  return data;
}

TEST(VtkWriter, AsciiVolumeMeshIsWellFormedAndRoundTrips) {
  const Mesh mesh = small_mesh();
  const VtkData data = sample_data(mesh);
  TempFile file(".vtu");
  jointhb::io::write_vtu(file.path(), mesh, data, {VtkEncoding::ascii});
  const std::string text = file.contents();
  EXPECT_EQ(attribute(text, "NumberOfPoints"), "32");
  EXPECT_EQ(attribute(text, "NumberOfCells"), "3");
  EXPECT_NE(text.find("Name=\"types\" format=\"ascii\">\n12\n12\n25\n</DataArray>"),
            std::string::npos);
  EXPECT_NE(text.find("Name=\"offsets\" format=\"ascii\">\n8\n16\n36\n</DataArray>"),
            std::string::npos);
  EXPECT_NE(text.find("Name=\"part\" format=\"ascii\">\n0\n0\n1\n</DataArray>"), std::string::npos);
  // Shortest round-trip decimal: 1/7 comes back exactly.
  const auto cell = text.find("Name=\"von_mises\"");
  ASSERT_NE(cell, std::string::npos);
  const auto values = text.find('>', cell) + 1;
  char* end = nullptr;
  const double v0 = std::strtod(text.c_str() + values, &end);
  const double v1 = std::strtod(end, &end);
  const double v2 = std::strtod(end, &end);
  EXPECT_EQ(v0, 1.5e8);
  EXPECT_EQ(v1, 2.25e8);
  EXPECT_EQ(v2, 1.0 / 7.0);
  if (python_available()) {
    EXPECT_EQ(run_python_check(file.path()), 0);
  }
}

TEST(VtkWriter, AppendedRawBinaryHasCorrectBlockSizesAndExactBytes) {
  const Mesh mesh = small_mesh();
  const VtkData data = sample_data(mesh);
  TempFile file(".vtu");
  jointhb::io::write_vtu(file.path(), mesh, data, {VtkEncoding::appended_raw});
  const std::string text = file.contents();
  const auto appended = text.find("<AppendedData encoding=\"raw\">\n_");
  ASSERT_NE(appended, std::string::npos);
  const std::size_t start = text.find('_', appended) + 1;
  // The Points block holds the coordinates bit for bit.
  const auto points = text.find("Name=\"Points\"");
  ASSERT_NE(points, std::string::npos);
  const std::size_t offset = std::stoul(attribute(text, "offset", points));
  std::uint64_t bytes = 0;
  std::memcpy(&bytes, text.data() + start + offset, sizeof bytes);
  ASSERT_EQ(bytes, static_cast<std::uint64_t>(mesh.coordinates.size()) * 8);
  EXPECT_EQ(std::memcmp(text.data() + start + offset + 8, mesh.coordinates.data(), bytes), 0);
  // The mode block: 3 components × 32 points.
  const auto mode = text.find("Name=\"mode_1\"");
  std::memcpy(&bytes, text.data() + start + std::stoul(attribute(text, "offset", mode)), 8);
  EXPECT_EQ(bytes, 3u * 32u * 8u);
  EXPECT_NE(text.find("</AppendedData>\n</VTKFile>\n", start), std::string::npos);
  if (python_available()) {
    EXPECT_EQ(run_python_check(file.path()), 0);
  }
}

TEST(VtkWriter, AutomaticEncodingSwitchesToBinaryAboveTheLimit) {
  const Mesh mesh = small_mesh();
  TempFile small(".s.vtu"), large(".l.vtu");
  jointhb::io::write_vtu(small.path(), mesh, {}, {VtkEncoding::automatic, 1000});
  jointhb::io::write_vtu(large.path(), mesh, {}, {VtkEncoding::automatic, 10});
  EXPECT_EQ(small.contents().find("AppendedData"), std::string::npos);
  EXPECT_NE(large.contents().find("AppendedData"), std::string::npos);
}

TEST(VtkWriter, QuadSurfaceWithLinearAndQuadraticFacets) {
  const Mesh mesh = small_mesh();
  // Top faces (S2) of the hex8 elements and one 8-node face of the hex20.
  std::vector<std::vector<int>> quads = {jointhb::fe::face_nodes(mesh, {0, 1}),
                                         jointhb::fe::face_nodes(mesh, {1, 1}),
                                         jointhb::fe::face_nodes(mesh, {2, 1})};
  ASSERT_EQ(quads[2].size(), 8u);
  VtkData data;
  data.add_cell_scalars("pressure", Eigen::Vector3d(1e6, 2e6, 0.0));
  data.add_point_scalars("gap", Eigen::VectorXd::Constant(mesh.num_nodes(), 1e-6));
  for (auto encoding : {VtkEncoding::ascii, VtkEncoding::appended_raw}) {
    TempFile file(encoding == VtkEncoding::ascii ? ".a.vtu" : ".b.vtu");
    jointhb::io::write_quad_surface_vtu(file.path(), mesh.coordinates, quads, data, {encoding});
    const std::string text = file.contents();
    EXPECT_EQ(attribute(text, "NumberOfCells"), "3");
    if (encoding == VtkEncoding::ascii) {
      EXPECT_NE(text.find("Name=\"types\" format=\"ascii\">\n9\n9\n23\n"), std::string::npos);
    }
    if (python_available()) {
      EXPECT_EQ(run_python_check(file.path()), 0);
    }
  }
}

TEST(VtkWriter, RejectsInconsistentDataNamingTheArray) {
  const Mesh mesh = small_mesh();
  TempFile file(".vtu");
  VtkData wrong_length;
  wrong_length.add_point_scalars("gap", Eigen::VectorXd::Zero(5));
  try {
    jointhb::io::write_vtu(file.path(), mesh, wrong_length);
    FAIL() << "wrong length accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("'gap'"), std::string::npos) << error.what();
  }
  VtkData not_finite;
  Eigen::VectorXd values = Eigen::VectorXd::Zero(mesh.num_nodes());
  values(3) = std::numeric_limits<double>::quiet_NaN();
  not_finite.add_point_scalars("u", values);
  EXPECT_THROW(jointhb::io::write_vtu(file.path(), mesh, not_finite), std::invalid_argument);
  VtkData reserved;
  reserved.add_cell_scalars("part", Eigen::Vector3d::Zero());
  EXPECT_THROW(jointhb::io::write_vtu(file.path(), mesh, reserved), std::invalid_argument);
  VtkData twice;
  twice.add_cell_scalars("s", Eigen::Vector3d::Zero());
  twice.add_cell_scalars("s", Eigen::Vector3d::Zero());
  EXPECT_THROW(jointhb::io::write_vtu(file.path(), mesh, twice), std::invalid_argument);
  EXPECT_THROW(jointhb::io::write_quad_surface_vtu(file.path(), mesh.coordinates, {{0, 1, 2, 3, 4}}),
               std::invalid_argument);
  EXPECT_THROW(jointhb::io::write_quad_surface_vtu(file.path(), mesh.coordinates, {{0, 1, 2, 99}}),
               std::invalid_argument);
  EXPECT_THROW(jointhb::io::write_vtu("/nonexistent-dir/x.vtu", mesh), std::runtime_error);
}

TEST(VtkWriter, PvdCollectionListsTheDatasets) {
  TempFile file(".pvd");
  jointhb::io::write_pvd(file.path(), {{0.0, "mode_1.vtu"}, {123.25, "mode_2.vtu"}});
  const std::string text = file.contents();
  EXPECT_NE(text.find("<DataSet timestep=\"123.25\" part=\"0\" file=\"mode_2.vtu\"/>"),
            std::string::npos);
  if (python_available()) {
    TempFile script(
        ".py",
        "import sys, xml.etree.ElementTree as ET\n"
        "r = ET.parse(sys.argv[1]).getroot()\n"
        "assert r.get('type') == 'Collection'\n"
        "assert [d.get('file') for d in r.iter('DataSet')] == ['mode_1.vtu', 'mode_2.vtu']\n");
    const std::string command =
        "/usr/bin/python3 '" + script.path().string() + "' '" + file.path().string() + "'";
    EXPECT_EQ(std::system(command.c_str()), 0);
  }
}

}  // namespace
