// Tetrahedra and wedges through the readers (Abaqus .inp, Gmsh .msh 4.1), the VTK writer and the
// interface builder: node order round trips, faces and the errors that name what is refused.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <array>
#include <sstream>
#include <string>

#include "jointhb/fe/gmsh_reader.hpp"
#include "jointhb/fe/inp_reader.hpp"
#include "jointhb/fe/interface.hpp"
#include "jointhb/fe/mesh_checks.hpp"
#include "jointhb/fe/mesh_file_error.hpp"
#include "jointhb/io/vtk_writer.hpp"
#include "unit/fe/simplex_test_support.hpp"
#include "unit/io/temp_file.hpp"

namespace jointhb::fe {
namespace {

using testing::box_of;
using testing::distort_mesh;
using testing::patch_test;
using testing::steel;

const ElementType kTypes[] = {ElementType::tet4, ElementType::tet10, ElementType::wedge6,
                              ElementType::wedge15};

Mesh distorted_box(ElementType type) {
  const std::array<int, 3> divisions = {2, 2, 2};
  Mesh mesh = box_of(type, {1.0, 1.0, 1.0}, divisions);
  distort_mesh(mesh, divisions, 0.2, 7);
  return mesh;
}

// The mesh as an Abaqus input file: node ids 101.., element ids 1.., 8 node numbers per data line
// (continuation lines), the sides zmax and xmax as element-face surfaces.
std::string to_inp(const Mesh& mesh) {
  std::ostringstream out;
  out << "*NODE\n";
  for (int n = 0; n < mesh.num_nodes(); ++n)
    out << fmt::format("{}, {:.17g}, {:.17g}, {:.17g}\n", 101 + n, mesh.coordinates(0, n),
                       mesh.coordinates(1, n), mesh.coordinates(2, n));
  out << "*ELEMENT, TYPE=" << abaqus_name(mesh.elements[0].type) << ", ELSET=BLOCK\n";
  for (int e = 0; e < mesh.num_elements(); ++e) {
    out << e + 1;
    const auto nodes = mesh.elements[static_cast<std::size_t>(e)].node_span();
    for (std::size_t a = 0; a < nodes.size(); ++a)
      out << (a > 0 && a % 8 == 0 ? ",\n" : ", ") << 101 + nodes[a];
    out << "\n";
  }
  for (const char* side : {"zmax", "xmax"}) {
    out << "*SURFACE, NAME=" << side << "\n";
    for (const Face& f : mesh.surfaces.at(std::string("box.") + side))
      out << f.element + 1 << ", S" << f.face + 1 << "\n";
  }
  return out.str();
}

class SimplexReaders : public ::testing::TestWithParam<ElementType> {};

TEST_P(SimplexReaders, InpRoundTripKeepsNodeOrderAndFaces) {
  const ElementType type = GetParam();
  const Mesh mesh = distorted_box(type);
  const InpResult r = parse_inp(to_inp(mesh), "box.inp");
  ASSERT_EQ(r.mesh.num_elements(), mesh.num_elements());
  for (int e = 0; e < mesh.num_elements(); ++e) {
    EXPECT_EQ(r.mesh.elements[static_cast<std::size_t>(e)].type, type);
    for (int a = 0; a < node_count(type); ++a)
      EXPECT_EQ(r.mesh.elements[static_cast<std::size_t>(e)].nodes[static_cast<std::size_t>(a)],
                mesh.elements[static_cast<std::size_t>(e)].nodes[static_cast<std::size_t>(a)]);
  }
  EXPECT_EQ(r.mesh.surfaces.at("zmax"), mesh.surfaces.at("box.zmax"));
  EXPECT_EQ(r.mesh.surfaces.at("xmax"), mesh.surfaces.at("box.xmax"));
  EXPECT_TRUE(check_mesh(r.mesh).empty());
  const testing::PatchResult p = patch_test(r.mesh, steel());
  EXPECT_LT(p.displacement_error, 1e-10);
  EXPECT_LT(p.stress_error, 1e-9);
}

// Gmsh's mid-edge node order (reference manual, "Node ordering"), written out independently of
// the reader's tables: each entry is the edge (corners) of Gmsh's node corner_count + k.
std::vector<std::array<int, 2>> gmsh_edges(ElementType type) {
  if (type == ElementType::tet10) return {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
  if (type == ElementType::wedge15)
    return {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 4}, {2, 5}, {3, 4}, {3, 5}, {4, 5}};
  return {};
}

// The element's nodes in Gmsh's order: corners as they are, mid-edge nodes found by their edge.
std::vector<int> gmsh_nodes(const Element& element) {
  const auto nodes = element.node_span();
  const int corners = corner_count(element.type);
  std::vector<int> out(nodes.begin(), nodes.begin() + corners);
  const auto ours = edge_corners(element.type);
  for (const auto& [p, q] : gmsh_edges(element.type))
    for (std::size_t k = 0; k < ours.size(); ++k)
      if ((ours[k][0] == p && ours[k][1] == q) || (ours[k][0] == q && ours[k][1] == p))
        out.push_back(nodes[static_cast<std::size_t>(corners) + k]);
  return out;
}

int gmsh_type(ElementType type) {
  switch (type) {
    case ElementType::tet4: return 4;
    case ElementType::tet10: return 11;
    case ElementType::wedge6: return 6;
    default: return 18;
  }
}

// MSH 4.1: nodes (tags 1001..) on volume 1 ("block"), the elements, and the faces of the sides
// zmax (surface 6, "top") and xmax (surface 7, "side") as triangles or quadrangles.
std::string to_msh(const Mesh& mesh) {
  const ElementType type = mesh.elements[0].type;
  std::ostringstream out;
  out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n3\n2 5 \"top\"\n2 8 \"side\"\n"
         "3 1 \"block\"\n$EndPhysicalNames\n$Entities\n0 0 2 1\n"
         "6 0 0 1 1 1 1 1 5 0\n7 1 0 0 1 1 1 1 8 0\n1 0 0 0 1 1 1 1 1 0\n$EndEntities\n";
  out << "$Nodes\n1 " << mesh.num_nodes() << " 1001 " << 1000 + mesh.num_nodes() << "\n3 1 0 "
      << mesh.num_nodes() << "\n";
  for (int n = 0; n < mesh.num_nodes(); ++n) out << 1001 + n << "\n";
  for (int n = 0; n < mesh.num_nodes(); ++n)
    out << fmt::format("{:.17g} {:.17g} {:.17g}\n", mesh.coordinates(0, n), mesh.coordinates(1, n),
                       mesh.coordinates(2, n));
  out << "$EndNodes\n";
  const auto& top = mesh.surfaces.at("box.zmax");
  const auto& side = mesh.surfaces.at("box.xmax");
  const std::size_t total = mesh.elements.size() + top.size() + side.size();
  out << "$Elements\n3 " << total << " 1 " << total << "\n";
  long tag = 1;
  const auto faces = [&](int entity, const std::vector<Face>& list) {
    const int corners = face_corner_count(type, list.front().face);
    const int gmsh = corners == 3 ? (is_quadratic(type) ? 9 : 2) : (is_quadratic(type) ? 16 : 3);
    out << "2 " << entity << " " << gmsh << " " << list.size() << "\n";
    for (const Face& f : list) {
      out << tag++;
      for (int n : face_nodes(mesh, f)) out << " " << 1001 + n;
      out << "\n";
    }
  };
  faces(6, top);
  faces(7, side);
  out << "3 1 " << gmsh_type(type) << " " << mesh.elements.size() << "\n";
  for (const Element& element : mesh.elements) {
    out << tag++;
    for (int n : gmsh_nodes(element)) out << " " << 1001 + n;
    out << "\n";
  }
  out << "$EndElements\n";
  return out.str();
}

TEST_P(SimplexReaders, GmshRoundTripReordersToAbaqusNodeOrder) {
  const ElementType type = GetParam();
  const Mesh mesh = distorted_box(type);
  const Mesh read = parse_gmsh(to_msh(mesh), "box.msh");
  ASSERT_EQ(read.num_elements(), mesh.num_elements());
  for (int e = 0; e < mesh.num_elements(); ++e) {
    EXPECT_EQ(read.elements[static_cast<std::size_t>(e)].type, type);
    for (int a = 0; a < node_count(type); ++a)
      EXPECT_EQ(read.elements[static_cast<std::size_t>(e)].nodes[static_cast<std::size_t>(a)],
                mesh.elements[static_cast<std::size_t>(e)].nodes[static_cast<std::size_t>(a)])
          << "element " << e << " node " << a;
  }
  EXPECT_EQ(read.surfaces.at("top"), mesh.surfaces.at("box.zmax"));
  EXPECT_EQ(read.surfaces.at("side"), mesh.surfaces.at("box.xmax"));
  EXPECT_TRUE(check_mesh(read).empty());
  const testing::PatchResult p = patch_test(read, steel());
  EXPECT_LT(p.displacement_error, 1e-10);
  EXPECT_LT(p.stress_error, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Types, SimplexReaders, ::testing::ValuesIn(kTypes),
                         [](const auto& p) { return std::string(abaqus_name(p.param)); });

TEST(SimplexVtk, CellTypesAndWedgeNodeOrder) {
  for (ElementType type : kTypes) {
  const Mesh mesh = box_of(type, {1.0, 1.0, 1.0}, {1, 1, 1});
  io::testing::TempFile file(std::string(".") + abaqus_name(type) + ".vtu");
  io::write_vtu(file.path(), mesh, {}, {io::VtkEncoding::ascii});
  const std::string text = file.contents();
  const int vtk_type = type == ElementType::tet4    ? 10
                       : type == ElementType::tet10 ? 24
                       : type == ElementType::wedge6 ? 13
                                                     : 26;
  EXPECT_NE(text.find(fmt::format("Name=\"types\" format=\"ascii\">\n{}\n", vtk_type)),
            std::string::npos);
  // VTK's wedge: the base triangle (0, 1, 2) has its right-hand normal pointing away from the top
  // triangle (3, 4, 5) (vtkWedge documentation): check it on the written connectivity.
  if (family(type) == ElementFamily::wedge) {
    const std::size_t at = text.find("Name=\"connectivity\" format=\"ascii\">\n");
    ASSERT_NE(at, std::string::npos);
    std::istringstream in(text.substr(text.find('\n', at) + 1));
    std::vector<int> ids(static_cast<std::size_t>(node_count(type)));
    for (int& id : ids) in >> id;
    const auto x = [&](std::size_t k) -> Eigen::Vector3d { return mesh.coordinates.col(ids[k]); };
    const Eigen::Vector3d normal = (x(1) - x(0)).cross(x(2) - x(0));
    EXPECT_LT(normal.dot(x(3) - x(0)), 0.0);
    if (is_quadratic(type)) {  // VTK's mid-edge points on (0,1), (1,2), (2,0), (3,4), ... (2,5)
      const std::array<std::array<std::size_t, 2>, 9> edges = {
          {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5}, {5, 3}, {0, 3}, {1, 4}, {2, 5}}};
      for (std::size_t k = 0; k < 9; ++k)
        EXPECT_LT((x(6 + k) - 0.5 * (x(edges[k][0]) + x(edges[k][1]))).norm(), 1e-15) << k;
    }
  }
}
}

bool parse_reports(const std::string& text, int line, const std::string& what) {
  try {
    (void)parse_inp(text, "m.inp");
  } catch (const MeshFileError& e) {
    const bool ok = e.line() == line && std::string(e.what()).find(what) != std::string::npos;
    if (!ok) ADD_FAILURE() << e.what();
    return ok;
  }
  ADD_FAILURE() << "no error";
  return false;
}

TEST(SimplexReaders, InpRefusesFacesTheElementDoesNotHave) {
  const std::string nodes = "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n";
  EXPECT_TRUE(parse_reports(nodes + "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n*SURFACE, NAME=S\n1, S5\n", 9,
                      "element 1 is a C3D4 with faces S1..S4, not S5"));
  EXPECT_TRUE(parse_reports(nodes + "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3\n", 7,
                      "element 1: 3 node numbers, C3D4 needs 4"));
  const InpResult r =
      parse_inp(nodes + "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n*SURFACE, NAME=S\n1, S4\n", "m.inp");
  EXPECT_EQ(r.mesh.surfaces.at("S"), (std::vector<Face>{{0, 3}}));
}

TEST(SimplexReaders, GmshRefusesAFifteenNodePrismWithWrongNodeCount) {
  std::string text = to_msh(box_of(ElementType::wedge15, {1, 1, 1}, {1, 1, 1}));
  // Drop the last node of the last element line.
  const std::size_t end = text.find("\n$EndElements");
  const std::size_t space = text.rfind(' ', end);
  text.erase(space, end - space);
  try {
    (void)parse_gmsh(text, "m.msh");
    ADD_FAILURE() << "no error";
  } catch (const MeshFileError& e) {
    EXPECT_NE(std::string(e.what()).find("(type 18 (15-node prism)) has 14 nodes"), std::string::npos)
        << e.what();
  }
}

// Two boxes of `type` stacked along `axis`, the lower one's max side against the upper one's min.
Mesh stacked(ElementType type, int axis) {
  BoxOptions lower, upper;
  lower.type = upper.type = type;
  lower.part = "lower";
  upper.part = "upper";
  lower.divisions = upper.divisions = {2, 2, 2};
  upper.origin[axis] = 1.0;
  Mesh mesh = box_mesh(lower);
  append(mesh, box_mesh(upper));
  return mesh;
}

// Interfaces on the triangular faces: tests/unit/fe/test_interface_mortar.cpp.

TEST(SimplexInterfaces, WedgeQuadrilateralFacesMakeAnInterface) {
  for (ElementType type : {ElementType::wedge6, ElementType::wedge15}) {
    const Mesh mesh = stacked(type, 0);  // x sides: the wedges' quadrilateral faces
    InterfaceOptions o;
    o.name = "joint";
    o.bottom_surface = "lower.xmax";
    o.top_surface = "upper.xmin";
    o.integration = InterfaceIntegration::gauss;
    const Interface joint = build_interface(mesh, o);
    EXPECT_EQ(joint.elements.size(), mesh.surfaces.at("lower.xmax").size());
    double area = 0.0;
    for (const InterfacePoint& p : joint.points) area += p.area;
    EXPECT_NEAR(area, 1.0, 1e-12);
    for (const InterfacePoint& p : joint.points) EXPECT_NEAR(p.frame(2, 0), 1.0, 1e-12);
  }
}

}  // namespace
}  // namespace jointhb::fe
