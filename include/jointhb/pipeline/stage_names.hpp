#pragma once
// The names of the stored stages, one definition each. A store keeps stage S under key K as
// S-K (io::StageCache: DIR/S-K.bin), and the pipeline's messages name that place
// (StageStore::location(S, K)): with one name for both, a message cannot name a file the cache
// does not write (it once said interface-<key>.bin for interface_model-<key>.bin).

#include <string_view>

namespace jointhb::pipeline::stage_names {

inline constexpr std::string_view preload = "preload";
inline constexpr std::string_view modes = "modes";
inline constexpr std::string_view interface_model = "interface_model";
inline constexpr std::string_view recovery = "recovery";  ///< the full-field recovery of interface_model

}  // namespace jointhb::pipeline::stage_names
