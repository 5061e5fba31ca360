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
//   *PART / *END PART, *ASSEMBLY / *END ASSEMBLY, *INSTANCE, NAME=i, PART=p / *END INSTANCE with
//                                       an optional translation line "dx, dy, dz" and rotation
//                                       line "a1, a2, a3, b1, b2, b3, angle" (translation first,
//                                       then the rotation by angle degrees about the axis a → b)
// Keywords, parameters and set names are case-insensitive (a set keeps the spelling of its first
// definition); "**" starts a comment; blank lines are skipped. Repeating *NSET or *ELSET with the
// same name adds to the set.
//
// Parts of the Mesh: the ELSET named on each *ELEMENT card, else the enclosing *PART, else
// "default"; each part is also an element set of the same name. Assemblies: every instance
// places a copy of its part's nodes and elements (and applies its *SOLID SECTION). With one
// instance, names are the part's own (also reachable as "instance.name"); with several, each
// instance is a mesh part named like the instance ("instance.ELSET" for ELSETs on *ELEMENT), and
// its sets and surfaces are named "instance.name". Node and element ids are per part; data lines
// at assembly level name them "instance.id", or with INSTANCE= on *NSET/*ELSET/*SURFACE.
//
// Physics cards (inp_physics.cpp, docs/case-files.md §"Abaqus/CalculiX decks"):
//   *MATERIAL, NAME=m with *ELASTIC (isotropic: E, ν) and *DENSITY (ρ); *SOLID SECTION, ELSET=e,
//   MATERIAL=m → InpResult::part_materials (one material per part: a section must cover whole
//   parts);
//   *BOUNDARY (zero displacements: node or node set, first DOF [, last DOF [, 0]], or ENCASTRE,
//   PINNED, XSYMM, YSYMM, ZSYMM, XASYMM, YASYMM, ZASYMM) → InpResult::constraints;
//   *CLOAD (node or node set, DOF 1..3, force), *DSLOAD (surface, P, pressure), *DLOAD (element or
//   element set, P1..P6, pressure) → InpResult::loads, applied in the preload;
//   *TIE, NAME=t [, POSITION TOLERANCE=d, ADJUST=YES|NO, TIED NSET=n, TYPE=SURFACE TO SURFACE|
//   NODE TO SURFACE] with one data line "slave surface, master surface" → InpResult::ties (built
//   by the case reader as fe/tie.hpp ties, docs/ties.md §"Decks").
// Cards with no effect on a linear-elastic vibration analysis about the preload (output, print,
// heading, step and procedure cards such as *STEP, *STATIC, *FREQUENCY, unused *AMPLITUDE, thermal
// material data) are listed in InpResult::ignored_cards so that the caller can say so once. Every
// other card — one that changes the physics and is not supported (*EQUATION, *COUPLING,
// *CONTACT PAIR, *DAMPING, *TEMPERATURE, ...) or one not known at all — stops with a
// MeshFileError "FILE:LINE: ..." naming it, unless InpOptions::ignore_cards names it (then it is
// listed in InpResult::skipped_cards). So are unsupported parameters of the cards read (other
// element types, *NGEN, *INCLUDE, TYPE=NODE surfaces, translated instances, a load with an
// AMPLITUDE, a nonzero prescribed displacement, a second *STEP, ...).

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <optional>

#include "jointhb/fe/assembly.hpp"
#include "jointhb/fe/material.hpp"
#include "jointhb/fe/mesh.hpp"
#include "jointhb/fe/static_load.hpp"

namespace jointhb::fe {

/// A card skipped by the reader.
struct IgnoredCard {
  std::string keyword;  ///< upper case with its star, e.g. "*SOLID SECTION"
  int line = 0;         ///< 1-based line of the keyword
};

/// A *TIE of the deck, its names resolved in the mesh (the tie itself needs the materials, which
/// the case may override: the case reader builds it, fe/tie.hpp).
struct InpTie {
  std::string name;            ///< NAME=
  std::string slave_surface;   ///< Mesh::surfaces key of the first surface of the data line
  std::string master_surface;  ///< Mesh::surfaces key of the second
  std::vector<int> tied_nodes;  ///< TIED NSET= (node indices); empty: every slave node
  int line = 0;                 ///< the card's line
};

struct InpOptions {
  /// Cards to skip although they change the physics or are unknown ("*EQUATION", "EQUATION" or
  /// "*equation"; a physics card read by jointhb, such as "*TIE", can be skipped too):
  /// the caller's explicit decision, reported in InpResult::skipped_cards.
  std::vector<std::string> ignore_cards;
};

struct InpResult {
  Mesh mesh;
  /// Per part of `mesh` (Mesh::parts order): the material of its *SOLID SECTION, or none.
  std::vector<std::optional<Material>> part_materials;
  std::vector<FixedNodes> constraints;   ///< *BOUNDARY, one entry per data line
  std::vector<std::string> constraint_labels;  ///< "FILE:LINE" of each constraint
  StaticLoads loads;                     ///< *CLOAD, *DSLOAD, *DLOAD (labels "FILE:LINE")
  std::vector<InpTie> ties;              ///< *TIE, in file order
  std::vector<IgnoredCard> ignored_cards;  ///< cards without effect, in file order
  std::vector<IgnoredCard> skipped_cards;  ///< cards skipped on request (InpOptions::ignore_cards)
};

/// Reads `file`. Throws MeshFileError ("FILE:LINE: problem") on any error.
[[nodiscard]] InpResult read_inp(const std::filesystem::path& file, const InpOptions& options = {});

/// Reads the contents of an .inp file; `file_name` is used in error messages only.
[[nodiscard]] InpResult parse_inp(std::string_view text, const std::string& file_name,
                                  const InpOptions& options = {});

}  // namespace jointhb::fe
