// The checks by kind that every scene and fabric field gets.
#include "libs/scene/field_checks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "haptex/v1/scene.pb.h"

namespace haptex::scene {
namespace {

std::vector<TextIssue> Issues(const v1::Scene& scene, const std::map<std::string, std::size_t>& max_bytes = {}) {
  std::vector<TextIssue> issues;
  CheckEveryField(scene, FieldLocator(nullptr, {7, 3, ""}), &issues, max_bytes);
  return issues;
}

TEST(FieldChecksTest, NumbersEnumsAndStringsByKind) {
  v1::Scene scene;
  scene.set_name("fine");
  scene.set_description("two\nlines\tand a tab");
  scene.mutable_cloth()->set_width_m(0.2);
  scene.add_fingers()->set_finger(v1::FINGER_THUMB);
  EXPECT_TRUE(Issues(scene).empty());

  scene.mutable_cloth()->mutable_stand_position_w_m()->set_y(std::numeric_limits<double>::quiet_NaN());
  scene.add_loads()->mutable_force_w_n()->set_z(-std::numeric_limits<double>::infinity());
  scene.add_fingers()->set_finger(static_cast<v1::Finger>(99));
  scene.set_description("bell\a");
  const auto issues = Issues(scene);
  ASSERT_EQ(issues.size(), 4u);
  EXPECT_EQ(issues[0].message, "description holds a control character (only tab and newline may appear)");
  EXPECT_EQ(issues[1].message, "cloth.stand_position_w_m.y must be a finite number, got nan");
  EXPECT_EQ(issues[2].message, "loads[0].force_w_n.z must be a finite number, got -inf");
  EXPECT_EQ(issues[3].message, "fingers[1].finger: 99 is not a value of Finger (FINGER_THUMB, FINGER_INDEX)");
  for (const TextIssue& issue : issues) {
    EXPECT_EQ(issue.line, 7) << "without a parse tree, the fallback location";
    EXPECT_EQ(issue.column, 3);
  }
}

TEST(FieldChecksTest, StringsAreBounded) {
  v1::Scene scene;
  scene.set_name(std::string(101, 'n'));
  EXPECT_TRUE(Issues(scene).empty());
  const auto named = Issues(scene, {{"haptex.v1.Scene.name", 100}});
  ASSERT_EQ(named.size(), 1u);
  EXPECT_EQ(named[0].message, "name has 101 bytes, at most 100");
  scene.set_name(std::string(kMaxStringBytes + 1, 'n'));
  ASSERT_EQ(Issues(scene).size(), 1u);
  scene.set_name("\xc3\x28");
  ASSERT_EQ(Issues(scene).size(), 1u);
  EXPECT_EQ(Issues(scene)[0].message, "name is not valid UTF-8");
}

TEST(FieldChecksTest, Utf8AndPlainNames) {
  EXPECT_TRUE(IsValidUtf8("plain ascii"));
  EXPECT_TRUE(
      IsValidUtf8("Gl\xc3\xb6"
                  "ckner \xe2\x82\xac \xf0\x9f\x91\x8d"));
  EXPECT_FALSE(IsValidUtf8("\xff"));
  EXPECT_FALSE(IsValidUtf8("\xc0\xaf"));          // overlong '/'
  EXPECT_FALSE(IsValidUtf8("\xed\xa0\x80"));      // a surrogate
  EXPECT_FALSE(IsValidUtf8("\xf4\x90\x80\x80"));  // beyond U+10FFFF
  EXPECT_FALSE(IsValidUtf8("\xe2\x82"));          // cut short
  EXPECT_TRUE(IsWellFormedText("a\tb\nc"));
  EXPECT_FALSE(IsWellFormedText("a\rb"));
  EXPECT_FALSE(IsWellFormedText("a\x7f"));
  EXPECT_TRUE(IsPlainName("wang2011_black_denim_11oz", 100));
  EXPECT_TRUE(IsPlainName("lab-1.local", 64));
  EXPECT_FALSE(IsPlainName("", 64));
  EXPECT_FALSE(IsPlainName("..", 64));
  EXPECT_FALSE(IsPlainName(".hidden", 64));
  EXPECT_FALSE(IsPlainName("a/b", 64));
  EXPECT_FALSE(IsPlainName("a b", 64));
  EXPECT_FALSE(IsPlainName(std::string(65, 'a'), 64));
}

TEST(FieldChecksTest, IssuesSortByLocation) {
  std::vector<TextIssue> issues = {{3, 1, "c"}, {1, 9, "b"}, {1, 2, "a"}, {3, 1, "d"}};
  SortByLocation(&issues);
  EXPECT_EQ(issues[0].message, "a");
  EXPECT_EQ(issues[1].message, "b");
  EXPECT_EQ(issues[2].message, "c");
  EXPECT_EQ(issues[3].message, "d");
}

}  // namespace
}  // namespace haptex::scene
