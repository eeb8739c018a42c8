#include "libs/scene/fabric_database.h"

#include <gtest/gtest.h>

#include "tests/scene/scene_test_support.h"

namespace haptex::scene {
namespace {

TEST(FabricDatabaseTest, ListsAndLoadsFabrics) {
  FabricDatabase db(testing::TestDataDir() + "/fabrics");
  const auto names = db.Names();
  ASSERT_EQ(names.size(), 3u);
  EXPECT_EQ(names[2], "test_cotton");
  const v1::Fabric fabric = db.Load("test_cotton");
  EXPECT_EQ(fabric.name(), "test_cotton");
  EXPECT_DOUBLE_EQ(fabric.warp_tensile().emt_percent(), 5.0);
}

TEST(FabricDatabaseTest, UnknownNameListsTheKnownOnes) {
  FabricDatabase db(testing::TestDataDir() + "/fabrics");
  try {
    db.Load("silk");
    FAIL();
  } catch (const TextProtoError& e) {
    EXPECT_NE(std::string(e.what()).find("no fabric 'silk'"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("test_cotton"), std::string::npos);
  }
}

TEST(FabricDatabaseTest, NameMustMatchTheFile) {
  FabricDatabase db(testing::TestDataDir() + "/fabrics");
  try {
    db.Load("misnamed");
    FAIL();
  } catch (const TextProtoError& e) {
    EXPECT_NE(std::string(e.what()).find("misnamed.textproto:1:1: name 'other_name' differs"), std::string::npos)
        << e.what();
  }
}

TEST(FabricDatabaseTest, BadValuesAreLocated) {
  FabricDatabase db(testing::TestDataDir() + "/fabrics");
  try {
    db.Load("broken_values");
    FAIL();
  } catch (const TextProtoError& e) {
    ASSERT_EQ(e.issues().size(), 2u) << e.what();
    EXPECT_EQ(e.issues()[0].line, 2);  // emt_percent: -5
    EXPECT_EQ(e.issues()[0].column, 16);
    EXPECT_NE(e.issues()[0].message.find("emt_percent"), std::string::npos);
    EXPECT_EQ(e.issues()[1].line, 8);  // weight: nan
    EXPECT_NE(e.issues()[1].message.find("weight_mg_per_cm2"), std::string::npos);
  }
}

TEST(FabricDatabaseTest, MissingDirectoryIsAClearError) {
  EXPECT_THROW(FabricDatabase("/nonexistent/fabrics"), std::runtime_error);
}

}  // namespace
}  // namespace haptex::scene
