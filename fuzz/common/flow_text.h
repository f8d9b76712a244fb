// Flow text → ParamValue: the initial-state fuzz target's decoder from bytes to a ParamValue
// tree. A small subset of YAML's flow style, enough to write every dictionary of
// doc/initial_state.md on one line:
//   value  := map | list | scalar
//   map    := '{' [ key ':' value { ',' key ':' value } ] '}'
//   list   := '[' [ value { ',' value } ] ']'
//   scalar := "quoted" | word        (a word is read up to one of , : { } [ ] or a newline)
// A word is a bool (true/false), nothing (null, ~), a number when strtod reads all of it (nan,
// inf, 1e400 and hex included) or else a string. '#' starts a comment to the line's end. A
// repeated key keeps its last value (as YAML loaders do). Nesting deeper than kMaxDepth, a
// missing bracket or text after the value is a parse error: the input is then skipped.
#pragma once

#include <optional>
#include <string>

#include "cga_rigid_sim/scene/param_value.h"

namespace cga_rigid_sim {
namespace fuzz {

constexpr int kMaxDepth = 32;

std::optional<scene::ParamValue> parseFlowText(const std::string& text);

}  // namespace fuzz
}  // namespace cga_rigid_sim
