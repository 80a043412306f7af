// The usage text of the wire_sim command line (wire_sim_usage.cpp).
#pragma once

namespace cws_tools {

extern const char* const kWireSimUsage;

}  // namespace cws_tools
