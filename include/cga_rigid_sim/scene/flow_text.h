// Flow text: a one-line YAML flow value, as the node reads a parameter given as text (rosrun's
// `_gravity:=[0,0,-9.81]`, `_initial_state:={…}`, a launch file's <param value="…"/>, YAML 1.1's
// `1e-3` read as a string), without ROS. The node turns what it reads into an XmlRpcValue; the
// initial-state fuzz target turns it into a ParamValue (toParamValue) — so the fuzzer exercises
// the node's own parser.
//
// Grammar:
//   value  := list | map | scalar
//   list   := '[' [ value { ',' value } ] ']'
//   map    := '{' [ key ':' value { ',' key ':' value } ] '}'
//   scalar := "text" | 'text' | plain      (plain: up to one of , ] } at its level, or [ {)
//   key    := a scalar read up to one of : , }
// A plain scalar, trimmed, is an int (strtol reads all of it, within int), else a double (strtod
// reads all of it: nan, inf, hex included), else a YAML 1.1 boolean (true/false, yes/no, on/off,
// any case), else the string itself. A key that reads as a number or boolean keeps its text
// ({1: …} names key "1"; a double key is printed with 17 digits). A repeated key, nesting deeper
// than kFlowMaxDepth, a missing bracket or text after the value: not flow text (nullopt).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cga_rigid_sim/scene/param_value.h"

namespace cga_rigid_sim {
namespace scene {

/// A value of flow text, with the parameter server's scalar types (int and double apart).
struct FlowValue {
  enum class Type { kBool, kInt, kDouble, kString, kList, kMap };
  Type type = Type::kString;
  bool b = false;
  int i = 0;
  double d = 0.0;
  std::string s;
  std::vector<FlowValue> items;   ///< kList: the elements; kMap: the values, in the text's order
  std::vector<std::string> keys;  ///< kMap: the keys, distinct, one per item
};

constexpr int kFlowMaxDepth = 32;

/// The value `text` holds, or nullopt when it is not flow text.
std::optional<FlowValue> parseFlowText(const std::string& text);

/// The same value as a ParamValue (bool, int and double → number, string, list, map).
ParamValue toParamValue(const FlowValue& v);

}  // namespace scene
}  // namespace cga_rigid_sim
