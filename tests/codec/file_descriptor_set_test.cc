#include "libs/codec/file_descriptor_set.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/descriptor.pb.h>
#include <google/protobuf/descriptor_database.h>
#include <google/protobuf/dynamic_message.h>
#include <gtest/gtest.h>

#include <memory>
#include <set>
#include <string>

#include "foxglove/SceneUpdate.pb.h"
#include "haptex/v1/cloth_frame.pb.h"
#include "haptex/v1/envelope.pb.h"

namespace haptex::codec {
namespace {

google::protobuf::FileDescriptorSet Parse(const std::string& bytes) {
  google::protobuf::FileDescriptorSet set;
  EXPECT_TRUE(set.ParseFromString(bytes));
  return set;
}

// Every file comes after all the files it imports, and each file once.
void ExpectDependenciesFirst(const google::protobuf::FileDescriptorSet& set) {
  std::set<std::string> seen;
  for (const auto& file : set.file()) {
    for (const auto& dependency : file.dependency()) {
      EXPECT_TRUE(seen.count(dependency)) << file.name() << " comes before its import " << dependency;
    }
    EXPECT_TRUE(seen.insert(file.name()).second) << file.name() << " twice";
  }
}

TEST(FileDescriptorSetOfTest, AFileWithoutImportsIsAlone) {
  const auto set = Parse(FileDescriptorSetOf(haptex::v1::ClothFrame::descriptor()));
  ASSERT_EQ(set.file_size(), 1);
  EXPECT_EQ(set.file(0).name(), "haptex/v1/cloth_frame.proto");
  EXPECT_EQ(set.file(0).package(), "haptex.v1");
}

TEST(FileDescriptorSetOfTest, SceneUpdateCarriesEveryImportDependenciesFirst) {
  const auto set = Parse(FileDescriptorSetOf(foxglove::SceneUpdate::descriptor()));
  ExpectDependenciesFirst(set);
  std::set<std::string> names;
  for (const auto& file : set.file()) names.insert(file.name());
  for (const char* expected :
       {"foxglove/SceneUpdate.proto", "foxglove/SceneEntity.proto", "foxglove/Pose.proto", "foxglove/Vector3.proto",
        "foxglove/Quaternion.proto", "foxglove/Color.proto", "foxglove/TriangleListPrimitive.proto",
        "google/protobuf/timestamp.proto", "google/protobuf/duration.proto"}) {
    EXPECT_TRUE(names.count(expected)) << expected;
  }
  EXPECT_EQ(set.file(set.file_size() - 1).name(), "foxglove/SceneUpdate.proto");
}

// A client holding only the set can decode the message: build the types anew from it.
TEST(FileDescriptorSetOfTest, IsEnoughToDecodeTheMessage) {
  const auto set = Parse(FileDescriptorSetOf(haptex::v1::Envelope::descriptor()));
  ExpectDependenciesFirst(set);
  google::protobuf::SimpleDescriptorDatabase database;
  for (const auto& file : set.file()) ASSERT_TRUE(database.Add(file));
  google::protobuf::DescriptorPool pool(&database);
  const google::protobuf::Descriptor* type = pool.FindMessageTypeByName("haptex.v1.Envelope");
  ASSERT_NE(type, nullptr);

  const auto scene_set = Parse(FileDescriptorSetOf(foxglove::SceneUpdate::descriptor()));
  google::protobuf::SimpleDescriptorDatabase scene_database;
  for (const auto& file : scene_set.file()) ASSERT_TRUE(scene_database.Add(file));
  google::protobuf::DescriptorPool scene_pool(&scene_database);
  const google::protobuf::Descriptor* scene_type = scene_pool.FindMessageTypeByName("foxglove.SceneUpdate");
  ASSERT_NE(scene_type, nullptr);

  foxglove::SceneUpdate update;
  auto* entity = update.add_entities();
  entity->set_id("cloth");
  entity->add_triangles()->add_points()->set_z(0.25);
  google::protobuf::DynamicMessageFactory factory(&scene_pool);
  std::unique_ptr<google::protobuf::Message> decoded(factory.GetPrototype(scene_type)->New());
  ASSERT_TRUE(decoded->ParseFromString(update.SerializeAsString()));
  EXPECT_EQ(decoded->ShortDebugString(), update.ShortDebugString());
}

TEST(FileDescriptorSetOfTest, NoTypeGivesAnEmptySet) { EXPECT_EQ(Parse(FileDescriptorSetOf(nullptr)).file_size(), 0); }

}  // namespace
}  // namespace haptex::codec
