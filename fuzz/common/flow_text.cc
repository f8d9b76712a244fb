#include "common/flow_text.h"

#include <cctype>
#include <cstdlib>

namespace cga_rigid_sim {
namespace fuzz {
namespace {

using scene::ParamValue;

class Parser {
 public:
  explicit Parser(const std::string& text) : s_(text) {}

  std::optional<ParamValue> parseDocument() {
    std::optional<ParamValue> v = value(0);
    skipSpace();
    if (!v || i_ != s_.size()) return std::nullopt;
    return v;
  }

 private:
  void skipSpace() {
    while (i_ < s_.size()) {
      const char c = s_[i_];
      if (c == '#') {
        while (i_ < s_.size() && s_[i_] != '\n') ++i_;
      } else if (std::isspace(static_cast<unsigned char>(c))) {
        ++i_;
      } else {
        return;
      }
    }
  }
  bool take(char c) {
    skipSpace();
    if (i_ < s_.size() && s_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }

  std::optional<ParamValue> value(int depth) {
    if (depth > kMaxDepth) return std::nullopt;
    skipSpace();
    if (take('{')) return map(depth);
    if (take('[')) return list(depth);
    return scalar();
  }

  std::optional<ParamValue> map(int depth) {
    ParamValue::Map m;
    if (take('}')) return ParamValue(std::move(m));
    do {
      std::optional<std::string> key = word();
      if (!key || !take(':')) return std::nullopt;
      std::optional<ParamValue> v = value(depth + 1);
      if (!v) return std::nullopt;
      m[*key] = std::move(*v);
    } while (take(','));
    if (!take('}')) return std::nullopt;
    return ParamValue(std::move(m));
  }

  std::optional<ParamValue> list(int depth) {
    ParamValue::List l;
    if (take(']')) return ParamValue(std::move(l));
    do {
      std::optional<ParamValue> v = value(depth + 1);
      if (!v) return std::nullopt;
      l.push_back(std::move(*v));
    } while (take(','));
    if (!take(']')) return std::nullopt;
    return ParamValue(std::move(l));
  }

  // A quoted string or a bare word (trailing spaces dropped); nullopt when there is none.
  std::optional<std::string> word() {
    skipSpace();
    if (i_ < s_.size() && s_[i_] == '"') {
      const std::size_t end = s_.find('"', i_ + 1);
      if (end == std::string::npos) return std::nullopt;
      std::string w = s_.substr(i_ + 1, end - i_ - 1);
      i_ = end + 1;
      return w;
    }
    const std::size_t start = i_;
    while (i_ < s_.size() && std::string(",:{}[]\n#").find(s_[i_]) == std::string::npos) ++i_;
    std::size_t end = i_;
    while (end > start && std::isspace(static_cast<unsigned char>(s_[end - 1]))) --end;
    if (end == start) return std::nullopt;
    return s_.substr(start, end - start);
  }

  std::optional<ParamValue> scalar() {
    skipSpace();
    const bool quoted = i_ < s_.size() && s_[i_] == '"';
    std::optional<std::string> w = word();
    if (!w) return std::nullopt;
    if (quoted) return ParamValue(*w);
    if (*w == "true") return ParamValue(true);
    if (*w == "false") return ParamValue(false);
    if (*w == "null" || *w == "~") return ParamValue();
    const char* begin = w->c_str();
    char* end = nullptr;
    const double d = std::strtod(begin, &end);
    if (end == begin + w->size()) return ParamValue(d);
    return ParamValue(*w);
  }

  const std::string& s_;
  std::size_t i_ = 0;
};

}  // namespace

std::optional<scene::ParamValue> parseFlowText(const std::string& text) {
  return Parser(text).parseDocument();
}

}  // namespace fuzz
}  // namespace cga_rigid_sim
