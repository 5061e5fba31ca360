// A non-matching interface inside the preload (case file → pipeline → preload::solve_preload):
// two blocks meshed independently (hexahedra 2 × 2 below, 3 × 3 hexahedra or tetrahedra above),
// stacked on symmetry supports, joined by a frictionless linear-penalty interface (k_N) and loaded
// by a uniform pressure p on top. The exact solution is uniaxial stress in both blocks with a
// uniform interface closure p / k_N:
//   lower: u_z = −p z / E;  upper: u_z = −p z / E − p / k_N;  both: u_x = ν p x / E, u_y = ν p y / E,
// which trilinear elements and the mortar interface (patch test) reproduce exactly — with any
// mesh on either side. Also: the case key `meshes` and its errors.
#include <gtest/gtest.h>

#include <string>

#include "jointhb/io/fe_case.hpp"
#include "jointhb/io/input_error.hpp"
#include "jointhb/pipeline/fe_model.hpp"
#include "jointhb/preload/preload_solver.hpp"

namespace {

using namespace jointhb;

constexpr double kE = 70.0e9, kNu = 0.33, kP = 2.0e6, kKn = 1.0e13, kH = 0.005;

std::string stacked_case(const std::string& upper_element, const std::string& upper_divisions,
                         const std::string& meshes) {
  return R"(model:
  type: fe
  materials: {al: {youngs_modulus: 70.0e9, poissons_ratio: 0.33, density: 2700.0}}
  parts:
    - {name: lower, material: al, element: C3D8, box: {size: [0.02, 0.02, 0.005], divisions: [2, 2, 1]}}
    - {name: upper, material: al, element: )" + upper_element + R"(, box: {origin: [0.0, 0.0, 0.005], size: [0.02, 0.02, 0.005], divisions: )" + upper_divisions + R"(}}
  interfaces:
    - {name: lap, bottom: lower.zmax, top: upper.zmin, integration: nodal)" + meshes + R"(, contact: {normal_stiffness: 1.0e13, law: frictionless}}
  constraints:
    - {node_set: lower.zmin, fix: [z]}
    - {node_set: lower.xmin, fix: [x]}
    - {node_set: lower.ymin, fix: [y]}
    - {node_set: upper.xmin, fix: [x]}
    - {node_set: upper.ymin, fix: [y]}
  loads: [{surface: upper.zmax, pressure: 2.0e6}]
)";
}

std::string preload_error_of(const std::string& text) {
  try {
    (void)io::parse_fe_case(text, "stack.yaml");
  } catch (const io::InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST(PreloadNonMatching, UniformPressureThroughANonMatchingInterfaceIsExact) {
  for (const auto& [element, divisions] : {std::pair{"C3D8", "[3, 3, 1]"}, {"C3D8", "[5, 2, 2]"}, {"C3D4", "[3, 2, 1]"}}) {
    SCOPED_TRACE(std::string(element) + " " + divisions);
    const io::FeCase c = io::parse_fe_case(stacked_case(element, divisions, ", meshes: non-matching"), "stack.yaml");
    ASSERT_EQ(c.interfaces[0].geometry.meshes, fe::InterfaceMeshes::non_matching);
    const preload::PreloadModel model = pipeline::preload_model(c);
    preload::PreloadOptions options;
    options.load_steps = 1;
    options.residual_tolerance = 1e-12;
    const preload::PreloadResult r = preload::solve_preload(model, options);
    ASSERT_TRUE(r.status().ok()) << r.status().brief();
    std::vector<bool> upper(static_cast<std::size_t>(c.mesh.num_nodes()), false);
    for (const fe::Element& e : c.mesh.elements)
      if (c.mesh.parts[static_cast<std::size_t>(e.part)] == "upper")
        for (int n : e.node_span()) upper[static_cast<std::size_t>(n)] = true;
    double worst = 0.0;
    for (int i = 0; i < c.mesh.num_nodes(); ++i) {
      const Eigen::Vector3d x = c.mesh.coordinates.col(i);
      Eigen::Vector3d exact(kNu * kP * x.x() / kE, kNu * kP * x.y() / kE, -kP * x.z() / kE);
      if (upper[static_cast<std::size_t>(i)]) exact.z() -= kP / kKn;
      worst = std::max(worst, (r.displacement.segment<3>(3 * i) - exact).norm());
    }
    EXPECT_LT(worst, 1e-9 * kP * kH / kE);
    // The interface carries the load: clamping force p A, uniform pressure p.
    EXPECT_NEAR(r.interfaces[0].clamping_force, kP * 0.02 * 0.02, 1e-9 * kP * 0.02 * 0.02);
    EXPECT_NEAR(r.interfaces[0].max_pressure, kP, 1e-8 * kP);
  }
}

TEST(PreloadNonMatching, MeshesKeyChoosesTheConstructionAndNamesErrors) {
  const std::string without = preload_error_of(stacked_case("C3D8", "[3, 3, 1]", ""));
  EXPECT_NE(without.find("matching meshes are required"), std::string::npos) << without;
  EXPECT_NE(without.find("set meshes: non-matching"), std::string::npos) << without;
  const io::FeCase automatic = io::parse_fe_case(stacked_case("C3D8", "[3, 3, 1]", ", meshes: automatic"), "stack.yaml");
  EXPECT_EQ(automatic.interfaces[0].geometry.meshes, fe::InterfaceMeshes::non_matching);
  const io::FeCase same = io::parse_fe_case(stacked_case("C3D8", "[2, 2, 1]", ", meshes: automatic"), "stack.yaml");
  EXPECT_EQ(same.interfaces[0].geometry.meshes, fe::InterfaceMeshes::matching);
  const std::string bad = preload_error_of(stacked_case("C3D8", "[3, 3, 1]", ", meshes: mortar"));
  EXPECT_NE(bad.find("model.interfaces[0].meshes"), std::string::npos) << bad;
}
