// parseFlowText (scene/flow_text.h): the node's reader of parameters given as text, and the
// initial-state fuzz target's. Truth: the grammar in flow_text.h, value by value.
#include "cga_rigid_sim/scene/flow_text.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace cga_rigid_sim {
namespace scene {
namespace flow_text_test {

using Type = FlowValue::Type;

FlowValue parsed(const std::string& text) {
  const std::optional<FlowValue> v = parseFlowText(text);
  EXPECT_TRUE(v.has_value()) << text;
  return v.value_or(FlowValue());
}

TEST(FlowText, PlainScalarsTakeTheParameterServersTypes) {
  EXPECT_EQ(parsed("42").type, Type::kInt);
  EXPECT_EQ(parsed(" -7 ").i, -7);
  EXPECT_EQ(parsed("4294967296").type, Type::kDouble);  // past int: a double
  EXPECT_EQ(parsed("1e-3").d, 1e-3);                    // YAML 1.1 leaves it a string
  EXPECT_TRUE(std::isnan(parsed("nan").d));
  EXPECT_EQ(parsed("0x10").d, 16.0);  // strtod reads hex
  for (const char* t : {"true", "Yes", "ON"}) {
    EXPECT_EQ(parsed(t).type, Type::kBool) << t;
    EXPECT_TRUE(parsed(t).b) << t;
  }
  for (const char* t : {"false", "no", "Off"}) EXPECT_FALSE(parsed(t).b) << t;
  EXPECT_EQ(parsed("null").type, Type::kString);  // no null: the word
  EXPECT_EQ(parsed("hello world").s, "hello world");
  EXPECT_EQ(parsed("'1.5'").type, Type::kString);  // quoted: always a string
  EXPECT_EQ(parsed("\" a, b \"").s, " a, b ");
}

TEST(FlowText, ListsAndMapsNest) {
  const FlowValue v = parsed("{crate: {position: [0, 0.5, 1e0], rpy: []}, 2: {}, \"k\": [[1]]}");
  ASSERT_EQ(v.type, Type::kMap);
  ASSERT_EQ(v.keys, (std::vector<std::string>{"crate", "2", "k"}));  // text order; 2 as text
  const FlowValue& crate = v.items[0];
  ASSERT_EQ(crate.keys, (std::vector<std::string>{"position", "rpy"}));
  const FlowValue& p = crate.items[0];
  ASSERT_EQ(p.items.size(), 3u);
  EXPECT_EQ(p.items[0].type, Type::kInt);
  EXPECT_EQ(p.items[1].d, 0.5);
  EXPECT_EQ(p.items[2].d, 1.0);
  EXPECT_EQ(crate.items[1].type, Type::kList);
  EXPECT_TRUE(crate.items[1].items.empty());
  EXPECT_EQ(v.items[1].type, Type::kMap);
  EXPECT_EQ(v.items[2].items[0].items[0].i, 1);
  // A double or boolean key keeps its text (17 digits for a double).
  EXPECT_EQ(parsed("{1.5: 0, yes: 1}").keys, (std::vector<std::string>{"1.5", "true"}));
}

TEST(FlowText, WhatIsNotFlowTextIsRefused) {
  for (const char* t :
       {"", "  ", "[1, 2", "{a: 1", "{a 1}", "{a: 1, a: 2}", "[1] x", "'open", "[1,, 2]", "{: 1}"})
    EXPECT_FALSE(parseFlowText(t).has_value()) << t;
  // Nesting up to kFlowMaxDepth is read, one more level is refused (the stack stays bounded).
  const auto nested = [](int levels) {
    return std::string(levels, '[') + "1" + std::string(levels, ']');
  };
  EXPECT_TRUE(parseFlowText(nested(kFlowMaxDepth)).has_value());
  EXPECT_FALSE(parseFlowText(nested(kFlowMaxDepth + 1)).has_value());
}

TEST(FlowText, ToParamValueMakesIntsNumbers) {
  const ParamValue v = toParamValue(parsed("{a: [1, 2.5, true, x]}"));
  const ParamValue::List& a = v.asMap().at("a").asList();
  ASSERT_EQ(a.size(), 4u);
  EXPECT_EQ(a[0].asNumber(), 1.0);
  EXPECT_EQ(a[1].asNumber(), 2.5);
  EXPECT_TRUE(a[2].asBool());
  EXPECT_EQ(a[3].asString(), "x");
}

}  // namespace flow_text_test
}  // namespace scene
}  // namespace cga_rigid_sim
