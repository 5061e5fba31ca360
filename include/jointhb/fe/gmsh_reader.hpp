#pragma once
// The mesh of a Gmsh file in MSH 4.1 ASCII format (Gmsh reference manual, "MSH file format",
// version 4.1): sections $MeshFormat, $PhysicalNames, $Entities, $Nodes and $Elements; other
// sections are skipped.
//
//   hexahedra (type 5, 8 nodes; type 17, 20 nodes), tetrahedra (type 4, 4 nodes -> C3D4; type
//     11, 10 nodes -> C3D10) and prisms (type 6, 6 nodes -> C3D6; type 18, 15 nodes -> C3D15) in
//     volume entities -> elements. The parts are the physical volumes, named by their physical
//     name ("volume_<tag>" when unnamed); elements of volumes in no physical group go to the part
//     "default". Each part is also an element set. Node order (Gmsh reference manual, "Node
//     ordering"), reordered to Abaqus' (mesh.hpp):
//       20-node hexahedron: mid-edge nodes by edge 0-1, 0-3, 0-4, 1-2, 1-5, 2-3, 2-6, 3-7, 4-5,
//         4-7, 5-6, 6-7 (Abaqus: 0-1, 1-2, 2-3, 3-0, 4-5, 5-6, 6-7, 7-4, 0-4, 1-5, 2-6, 3-7);
//       10-node tetrahedron: mid-edge nodes by edge 0-1, 1-2, 2-0, 0-3, 2-3, 1-3, i.e. Gmsh's
//         nodes 8 and 9 swapped relative to Abaqus/VTK (0-1, 1-2, 2-0, 0-3, 1-3, 2-3);
//       15-node prism (type 18; type 13 is the 18-node prism): mid-edge nodes by edge 0-1, 0-2,
//         0-3, 1-2, 1-4, 2-5, 3-4, 3-5, 4-5 (Abaqus: 0-1, 1-2, 2-0, 3-4, 4-5, 5-3, 0-3, 1-4, 2-5);
//       the corners agree for every type (4-node tetrahedron and 6-node prism: no reordering).
//   quadrangles (type 3, 4 nodes; type 16, 8 nodes) and triangles (type 2, 3 nodes; type 9, 6
//     nodes) in physical surfaces -> a surface and a node set named by the physical name
//     ("surface_<tag>" when unnamed): each is matched by its corner nodes to the one element face
//     it lies on.
//   points and lines, and surface elements in no physical group, are ignored.
// Errors ("FILE:LINE: problem", MeshFileError): binary files and versions other than 4.1,
// partitioned meshes, other element types in volumes (pyramids, 27-node hexahedra, 18-node
// prisms, ...), other element types in a physical surface, a quadrangle or triangle that is no
// element face or is a face of two elements, a volume in two physical volumes, unknown or
// duplicate node tags.

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
