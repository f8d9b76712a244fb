// parseFlowText (flow_text.h): recursive descent over a YAML flow value; nesting is bounded so
// that no input can exhaust the stack.
#include "cga_rigid_sim/scene/flow_text.h"

#include <cctype>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>

#include "cga_rigid_sim/format.h"

namespace cga_rigid_sim {
namespace scene {
namespace {

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

FlowValue scalarValue(FlowValue::Type type) {
  FlowValue v;
  v.type = type;
  return v;
}

// A plain YAML scalar: an integer (int), another number (double), a YAML 1.1 boolean, else the
// string itself.
FlowValue plainScalar(const std::string& text) {
  const std::string t = trim(text);
  if (!t.empty()) {
    char* end = nullptr;
    errno = 0;
    const long n = std::strtol(t.c_str(), &end, 10);
    if (end == t.c_str() + t.size() && errno == 0 && n >= INT_MIN && n <= INT_MAX) {
      FlowValue v = scalarValue(FlowValue::Type::kInt);
      v.i = static_cast<int>(n);
      return v;
    }
    const double d = std::strtod(t.c_str(), &end);
    if (end == t.c_str() + t.size()) {
      FlowValue v = scalarValue(FlowValue::Type::kDouble);
      v.d = d;
      return v;
    }
    const std::string l = lower(t);
    if (l == "true" || l == "yes" || l == "on" || l == "false" || l == "no" || l == "off") {
      FlowValue v = scalarValue(FlowValue::Type::kBool);
      v.b = l == "true" || l == "yes" || l == "on";
      return v;
    }
  }
  FlowValue v;
  v.s = t;
  return v;
}

// A key that read as a number or boolean keeps its text ({1: …} names key "1").
std::string keyText(const FlowValue& v) {
  switch (v.type) {
    case FlowValue::Type::kBool:
      return v.b ? "true" : "false";
    case FlowValue::Type::kInt:
      return std::to_string(v.i);
    case FlowValue::Type::kDouble:
      return trim(formatNumber(v.d, 17));
    default:
      return v.s;
  }
}

class FlowParser {
 public:
  explicit FlowParser(const std::string& text) : s_(text) {}
  std::optional<FlowValue> parseWhole() {
    auto v = value(0);
    skipSpace();
    if (!v || i_ != s_.size()) return std::nullopt;
    return v;
  }

 private:
  void skipSpace() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  bool eat(char c) {
    skipSpace();
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  // A scalar: quoted, or plain up to one of `stops` at the top of this level.
  std::optional<FlowValue> scalar(const char* stops) {
    skipSpace();
    if (i_ < s_.size() && (s_[i_] == '"' || s_[i_] == '\'')) {
      const char q = s_[i_++];
      const std::size_t close = s_.find(q, i_);
      if (close == std::string::npos) return std::nullopt;
      FlowValue v;
      v.s = s_.substr(i_, close - i_);
      i_ = close + 1;
      return v;
    }
    const std::size_t from = i_;
    while (i_ < s_.size() && !std::strchr(stops, s_[i_]) && s_[i_] != '[' && s_[i_] != '{') ++i_;
    const std::string t = trim(s_.substr(from, i_ - from));
    if (t.empty()) return std::nullopt;
    return plainScalar(t);
  }
  std::optional<FlowValue> value(int depth) {
    if (depth > kFlowMaxDepth) return std::nullopt;
    if (eat('[')) {
      FlowValue list = scalarValue(FlowValue::Type::kList);
      if (eat(']')) return list;
      do {
        auto item = value(depth + 1);
        if (!item) return std::nullopt;
        list.items.push_back(std::move(*item));
      } while (eat(','));
      if (!eat(']')) return std::nullopt;
      return list;
    }
    if (eat('{')) {
      FlowValue map = scalarValue(FlowValue::Type::kMap);
      if (eat('}')) return map;
      do {
        auto key = scalar(":,}");
        if (!key || !eat(':')) return std::nullopt;
        std::string k = keyText(*key);
        for (const std::string& seen : map.keys)
          if (seen == k) return std::nullopt;
        auto item = value(depth + 1);
        if (!item) return std::nullopt;
        map.keys.push_back(std::move(k));
        map.items.push_back(std::move(*item));
      } while (eat(','));
      if (!eat('}')) return std::nullopt;
      return map;
    }
    return scalar(",]}");
  }

  const std::string& s_;
  std::size_t i_ = 0;
};

}  // namespace

std::optional<FlowValue> parseFlowText(const std::string& text) {
  return FlowParser(text).parseWhole();
}

ParamValue toParamValue(const FlowValue& v) {
  switch (v.type) {
    case FlowValue::Type::kBool:
      return ParamValue(v.b);
    case FlowValue::Type::kInt:
      return ParamValue(v.i);
    case FlowValue::Type::kDouble:
      return ParamValue(v.d);
    case FlowValue::Type::kString:
      return ParamValue(v.s);
    case FlowValue::Type::kList: {
      ParamValue::List list;
      list.reserve(v.items.size());
      for (const FlowValue& item : v.items) list.push_back(toParamValue(item));
      return ParamValue(std::move(list));
    }
    case FlowValue::Type::kMap: {
      ParamValue::Map map;
      for (std::size_t k = 0; k < v.items.size(); ++k)
        map.emplace(v.keys[k], toParamValue(v.items[k]));
      return ParamValue(std::move(map));
    }
  }
  return ParamValue();
}

}  // namespace scene
}  // namespace cga_rigid_sim
