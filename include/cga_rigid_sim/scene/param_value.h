// ParamValue: a ROS-parameter-style dictionary (bool, int, double, string, list, map) without
// ROS. The node converts XmlRpcValue into it; tests and the ROS-free demos build it directly.
// It carries the initial-state dictionary (README: "Initial state").
#pragma once

#include <map>
#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace cga_rigid_sim {
namespace scene {

class ParamValue {
 public:
  using List = std::vector<ParamValue>;
  using Map = std::map<std::string, ParamValue>;

  ParamValue() = default;
  ParamValue(bool b) : v_(b) {}                        // NOLINT
  ParamValue(int i) : v_(static_cast<double>(i)) {}    // NOLINT: ints are numbers
  ParamValue(double d) : v_(d) {}                      // NOLINT
  ParamValue(const char* s) : v_(std::string(s)) {}    // NOLINT
  ParamValue(std::string s) : v_(std::move(s)) {}      // NOLINT
  ParamValue(List l) : v_(std::make_shared<List>(std::move(l))) {}  // NOLINT
  ParamValue(Map m) : v_(std::make_shared<Map>(std::move(m))) {}    // NOLINT

  bool isNone() const { return v_.index() == 0; }
  bool isBool() const { return std::holds_alternative<bool>(v_); }
  bool isNumber() const { return std::holds_alternative<double>(v_); }
  bool isString() const { return std::holds_alternative<std::string>(v_); }
  bool isList() const { return std::holds_alternative<std::shared_ptr<List>>(v_); }
  bool isMap() const { return std::holds_alternative<std::shared_ptr<Map>>(v_); }

  bool asBool() const { return std::get<bool>(v_); }
  double asNumber() const { return std::get<double>(v_); }
  const std::string& asString() const { return std::get<std::string>(v_); }
  const List& asList() const { return *std::get<std::shared_ptr<List>>(v_); }
  const Map& asMap() const { return *std::get<std::shared_ptr<Map>>(v_); }
  /// A short name of the held type, for error messages ("number", "list", …).
  const char* typeName() const {
    static const char* const kNames[] = {"nothing", "bool", "number", "string", "list", "map"};
    return kNames[v_.index()];
  }

 private:
  std::variant<std::monostate, bool, double, std::string, std::shared_ptr<List>,
               std::shared_ptr<Map>>
      v_;
};

}  // namespace scene
}  // namespace cga_rigid_sim
