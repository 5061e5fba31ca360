#pragma once
// The physics cards of an Abaqus/CalculiX deck: which cards are read, which have no effect, which
// stop the run (inp_reader.hpp), and the reader of materials, sections, boundary conditions and
// loads on a mesh already read (private to the fe layer).

#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include "inp_card.hpp"
#include "jointhb/fe/inp_reader.hpp"

namespace jointhb::fe::detail {

enum class CardClass {
  mesh,         ///< read by the mesh reader (*NODE, *ELEMENT, sets, surfaces, parts)
  physics,      ///< read by read_physics_cards (materials, sections, *BOUNDARY, loads, *TIE)
  no_effect,    ///< output, procedure and thermal cards: listed, no effect on the results
  unsupported,  ///< changes the physics and is not supported: an error unless ignored
  unknown,      ///< not a card jointhb knows: an error unless ignored
};

/// Node and element ids by scope, from the mesh reader: "" (the flat model and the assembly) and
/// each instance's upper-case name. A deck with one instance has one scope, also listed under its
/// name (then single_instance is that name, and "instance.name" set references drop the prefix).
struct DeckIndex {
  std::map<std::string, const std::unordered_map<long, int>*> nodes, elements;
  std::string single_instance;
};

/// The class of an upper-case keyword without its star ("SOLID SECTION").
[[nodiscard]] CardClass classify_card(const std::string& keyword);

/// Reads the physics cards (in file order) into result.part_materials, constraints, loads and ties, on
/// result.mesh. A card's ids and names resolve in its scope (Card::scope: the instance whose part
/// holds it, e.g. a *SOLID SECTION), then globally; "instance.id" names a node or element of an
/// instance. Throws MeshFileError "FILE:LINE: ..." on any error.
void read_physics_cards(const std::vector<Card>& cards, const std::string& file,
                        const DeckIndex& index, InpResult& result);

}  // namespace jointhb::fe::detail
