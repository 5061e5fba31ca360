#pragma once
// Shape functions, integration rules and the inverse map of the element faces that carry
// zero-thickness interface elements (interface.cpp, interface_mortar.cpp;
// docs/zero-thickness-elements.md §Faces).
//
// A face is identified by its node count: 3 (tri3), 6 (tri6), 4 (quad4), 8 (quad8), its nodes in
// face_nodes() order (corners with the outward normal by the right-hand rule, then the mid-edge
// node between corners k and k+1). Natural coordinates (ξ, η):
//   quadrilaterals: corner k at (ξ_k, η_k) = (-1,-1), (1,-1), (1,1), (-1,1);
//   triangles: corners at (0,0), (1,0), (0,1) (area coordinates L0 = 1-ξ-η, L1 = ξ, L2 = η),
// so that ∂x/∂ξ × ∂x/∂η is the outward normal for both.

#include <Eigen/Core>
#include <array>
#include <vector>

#include "jointhb/fe/interface.hpp"

namespace jointhb::fe::face {

/// Values and derivatives of the face's shape functions at (ξ, η) (first `nodes` entries used).
struct Shape {
  std::array<double, 8> h{};
  std::array<double, 8> dxi{};
  std::array<double, 8> deta{};
};

[[nodiscard]] constexpr bool is_triangle(int nodes) { return nodes == 3 || nodes == 6; }
[[nodiscard]] constexpr int corner_count(int nodes) { return is_triangle(nodes) ? 3 : 4; }

/// Shape functions: quad4 bilinear (eq. 14), quad8 serendipity, tri3 linear (L_k), tri6
/// quadratic (corners L_k(2L_k - 1), mid-edge 4 L_k L_{k+1}).
[[nodiscard]] Shape shape(int nodes, double xi, double eta);

/// Natural coordinates of corner k.
[[nodiscard]] Eigen::Vector2d corner(int nodes, int k);

/// Centre of the reference face: (0, 0) or (1/3, 1/3).
[[nodiscard]] Eigen::Vector2d centre(int nodes);

struct RulePoint {
  double xi = 0.0, eta = 0.0, weight = 0.0;
};

/// Rule on the reference face for `integration`:
///   nodal: the corners, weight 1 (quad4) or 1/6 (tri3) — Lobatto / Newton–Cotes, ∫N_k dA lumped;
///   gauss: 2×2 (quad4), 3×3 (quad8) Gauss–Legendre; collapsed Gauss 2×2 (tri3) or 3×3 (tri6).
/// Throws std::invalid_argument for nodal integration of a quadratic face.
[[nodiscard]] std::vector<RulePoint> rule(InterfaceIntegration integration, int nodes);

/// n-point Gauss–Legendre rule on [-1, 1], n = 1..5 (exact to degree 2n-1).
[[nodiscard]] std::vector<std::array<double, 2>> gauss_legendre(int n);

/// Collapsed (Duffy) n×n Gauss rule on the reference triangle (0,0), (1,0), (0,1), weights summing
/// to its area 1/2: ξ = s, η = t (1 - s), dξ dη = (1 - s) ds dt — exact for polynomials of total
/// degree ≤ 2n - 2.
[[nodiscard]] std::vector<RulePoint> triangle_rule(int n);

/// (ξ, η) of the point `x` of the face's plane, where `nodes2d` (2 × nodes) are the face's node
/// coordinates in that plane: Newton's method on Σ h_k(ξ, η) X_k = x from the centre. Returns
/// false when it does not converge to 1e-12 of the face size in 30 iterations (degenerate face).
[[nodiscard]] bool inverse_map(const Eigen::Matrix2Xd& nodes2d, const Eigen::Vector2d& x,
                               Eigen::Vector2d& natural);

}  // namespace jointhb::fe::face
