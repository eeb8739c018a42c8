#include "libs/codec/file_descriptor_set.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/descriptor.pb.h>

#include <set>
#include <string>

namespace haptex::codec {
namespace {

void AddWithDependencies(const google::protobuf::FileDescriptor* file, std::set<std::string>& added,
                         google::protobuf::FileDescriptorSet& set) {
  if (!added.insert(file->name()).second) return;
  for (int i = 0; i < file->dependency_count(); ++i) AddWithDependencies(file->dependency(i), added, set);
  file->CopyTo(set.add_file());
}

}  // namespace

std::string FileDescriptorSetOf(const google::protobuf::Descriptor* type) {
  google::protobuf::FileDescriptorSet set;
  std::set<std::string> added;
  if (type != nullptr) AddWithDependencies(type->file(), added, set);
  return set.SerializeAsString();
}

}  // namespace haptex::codec
