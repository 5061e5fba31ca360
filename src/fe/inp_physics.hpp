#pragma once
// The physics cards of an Abaqus/CalculiX deck: which cards are read, which have no effect, which
// stop the run (inp_reader.hpp), and the reader of materials, sections, boundary conditions and
// loads on a mesh already read (private to the fe layer).

#include <string>
#include <vector>

#include "inp_card.hpp"
#include "jointhb/fe/inp_reader.hpp"

namespace jointhb::fe::detail {

enum class CardClass {
  mesh,         ///< read by the mesh reader (*NODE, *ELEMENT, sets, surfaces, parts)
  physics,      ///< read by read_physics_cards (materials, sections, *BOUNDARY, loads)
  no_effect,    ///< output, procedure and thermal cards: listed, no effect on the results
  unsupported,  ///< changes the physics and is not supported: an error unless ignored
  unknown,      ///< not a card jointhb knows: an error unless ignored
};

/// The class of an upper-case keyword without its star ("SOLID SECTION").
[[nodiscard]] CardClass classify_card(const std::string& keyword);

/// Reads the physics cards (in file order) into result.part_materials, constraints and loads, on
/// result.mesh. `instance`: the name of the deck's single *INSTANCE (sets may be prefixed by
/// "instance."), or empty. Throws MeshFileError "FILE:LINE: ..." on any error.
void read_physics_cards(const std::vector<Card>& cards, const std::string& file,
                        const std::string& instance, InpResult& result);

}  // namespace jointhb::fe::detail
