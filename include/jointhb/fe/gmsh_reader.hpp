#pragma once
// The mesh of a Gmsh file in MSH 4.1 ASCII format (Gmsh reference manual, "MSH file format",
// version 4.1): sections $MeshFormat, $PhysicalNames, $Entities, $Nodes and $Elements; other
// sections are skipped.
//
//   hexahedra (type 5, 8 nodes; type 17, 20 nodes) in volume entities -> elements. The parts are
//     the physical volumes, named by their physical name ("volume_<tag>" when unnamed); elements
//     of volumes in no physical group go to the part "default". Each part is also an element set.
//     Gmsh's 20-node hexahedron lists its mid-edge nodes by edge 0-1, 0-3, 0-4, 1-2, 1-5, 2-3,
//     2-6, 3-7, 4-5, 4-7, 5-6, 6-7; they are reordered to Abaqus' (mesh.hpp). The corners agree.
//   quadrangles (type 3, 4 nodes; type 16, 8 nodes) in physical surfaces -> a surface and a node
//     set named by the physical name ("surface_<tag>" when unnamed): each quadrangle is matched
//     by its corner nodes to the one hexahedron face it lies on.
//   points and lines, and surface elements in no physical group, are ignored.
// Errors ("FILE:LINE: problem", MeshFileError): binary files and versions other than 4.1,
// partitioned meshes, other element types in volumes (tetrahedra, prisms, pyramids, 27-node
// hexahedra), triangles in a physical surface, a quadrangle that is no hexahedron face or is a
// face of two hexahedra, a volume in two physical volumes, unknown or duplicate node tags.

#include <filesystem>
#include <string>
#include <string_view>

#include "jointhb/fe/mesh.hpp"

namespace jointhb::fe {

struct GmshOptions {
  ElementType hex8_type =
      ElementType::hex8_incompatible;           ///< for type 5: hex8 or hex8_incompatible
  ElementType hex20_type = ElementType::hex20;  ///< for type 17: hex20 or hex20_reduced

  /// Empty when valid, else "field: constraint, got value".
  [[nodiscard]] std::string validate() const;
};

/// Reads `file`. Throws MeshFileError ("FILE:LINE: problem") on any error in the file and
/// std::invalid_argument for invalid options.
[[nodiscard]] Mesh read_gmsh(const std::filesystem::path& file, const GmshOptions& options = {});

/// Reads the contents of a .msh file; `file_name` is used in error messages only.
[[nodiscard]] Mesh parse_gmsh(std::string_view text, const std::string& file_name,
                              const GmshOptions& options = {});

}  // namespace jointhb::fe
