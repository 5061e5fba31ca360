#pragma once
// `jointhb run` on a finite-element case: the preloaded static state (analysis.preload) and the
// modes about it (analysis.modes). Writes, as far as they are asked for and computed:
//   DIR/preload_steps.csv      load step, load factor, iterations, residual
//   DIR/contact_<iface>.csv    per interface point: position, pressure, gap, tractions, open
//   DIR/contact_<iface>.vtu    the interface facets with node-averaged pressure and gap (ParaView)
//   DIR/preload.vtu            the mesh with the preload displacement
//   DIR/modes.csv              mode, frequency_hz, residual
//   DIR/modes.vtu              the mesh with every mode shape as a point array
//   DIR/summary.json           inputs, per-stage results and timings
#include <filesystem>

#include "jointhb/io/fe_case.hpp"
#include "run_support.hpp"

namespace jointhb::cli {

/// Returns 0, or 1 when a stage failed (what it computed is kept and written).
int run_fe_case(const io::FeCase& c, const std::filesystem::path& dir, Clock::time_point start);

}  // namespace jointhb::cli
