#include "server/web/foxglove/foxglove_schema.h"

#include <set>

#include <google/protobuf/descriptor.pb.h>

namespace omniview::foxglove_schema {

namespace pb = google::protobuf;

namespace {

// Dependencies first, as a FileDescriptorSet reader builds its pool.
void add_file(const pb::FileDescriptor* file, std::set<std::string>& seen, pb::FileDescriptorSet& set) {
  if (!seen.insert(file->name()).second) return;
  for (int i = 0; i < file->dependency_count(); ++i) add_file(file->dependency(i), seen, set);
  file->CopyTo(set.add_file());
}

}  // namespace

std::string descriptor_set(const pb::Descriptor* message_type) {
  pb::FileDescriptorSet set;
  std::set<std::string> seen;
  add_file(message_type->file(), seen, set);
  return set.SerializeAsString();
}

}  // namespace omniview::foxglove_schema
