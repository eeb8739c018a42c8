#include "launch/json_writer.h"

#include <gtest/gtest.h>

#include <limits>

namespace haptex::launch {
namespace {

TEST(LaunchJsonWriterTest, NestsObjectsAndArraysWithCommas) {
  JsonWriter json;
  json.BeginObject()
      .Field("a", 1)
      .BeginArray("list")
      .BeginObject()
      .Field("x", 0.5)
      .EndObject()
      .BeginObject()
      .Field("y", true)
      .EndObject()
      .EndArray()
      .Field("s", "q\"uote\n")
      .EndObject();
  EXPECT_EQ(json.str(), R"({"a":1,"list":[{"x":0.5},{"y":true}],"s":"q\"uote\n"})");
}

TEST(LaunchJsonWriterTest, NonFiniteNumbersBecomeNull) {
  JsonWriter json;
  json.BeginObject().Field("nan", std::numeric_limits<double>::quiet_NaN()).EndObject();
  EXPECT_EQ(json.str(), R"({"nan":null})");
}

}  // namespace
}  // namespace haptex::launch
