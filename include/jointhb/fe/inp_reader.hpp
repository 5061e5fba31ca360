#pragma once
// The mesh of an Abaqus/CalculiX input file (.inp), following the Abaqus Keywords Reference:
//   *NODE [, NSET=n]                    id, x [, y [, z]]              (missing coordinates = 0)
//   *ELEMENT, TYPE=t [, ELSET=e]        id, n1, ..., nk  continued on further lines until k nodes
//                                       (t = C3D8, C3D8I, C3D20, C3D20R, C3D4, C3D10, C3D6,
//                                       C3D15; node order as Abaqus' = mesh.hpp's, kept as is)
//   *NSET, NSET=n [, GENERATE]          ids or set names; GENERATE: first, last [, increment]
//   *ELSET, ELSET=e [, GENERATE]        likewise
//   *SURFACE, NAME=s [, TYPE=ELEMENT]   element id or element set, S1..S6 (hexahedra), S1..S4
//                                       (tetrahedra), S1..S5 (wedges)
//   *PART / *END PART, *ASSEMBLY / *END ASSEMBLY, *INSTANCE / *END INSTANCE: one part with one
//                                       instance that is neither translated nor rotated
// Keywords, parameters and set names are case-insensitive (a set keeps the spelling of its first
// definition); "**" starts a comment; blank lines are skipped. Repeating *NSET or *ELSET with the
// same name adds to the set.
//
// Parts of the Mesh: the ELSET named on each *ELEMENT card, else the enclosing *PART, else
// "default"; each part is also an element set of the same name.
//
// Material, section, step, load, output and constraint cards (*MATERIAL, *ELASTIC, *SOLID
// SECTION, *STEP, *BOUNDARY, *EQUATION, ...) are skipped and listed in InpResult::ignored_cards so
// that the caller can warn. Every other card, and every unsupported parameter of a mesh card
// (other element types, *NGEN, *INCLUDE, TYPE=NODE surfaces, translated instances, ...), stops
// with a MeshFileError "FILE:LINE: ..." naming the card.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "jointhb/fe/mesh.hpp"

namespace jointhb::fe {

/// A card skipped by the reader.
struct IgnoredCard {
  std::string keyword;  ///< upper case with its star, e.g. "*SOLID SECTION"
  int line = 0;         ///< 1-based line of the keyword
};

struct InpResult {
  Mesh mesh;
  std::vector<IgnoredCard> ignored_cards;  ///< in file order
};

/// Reads `file`. Throws MeshFileError ("FILE:LINE: problem") on any error.
[[nodiscard]] InpResult read_inp(const std::filesystem::path& file);

/// Reads the contents of an .inp file; `file_name` is used in error messages only.
[[nodiscard]] InpResult parse_inp(std::string_view text, const std::string& file_name);

}  // namespace jointhb::fe
