#include "contract/tasks.h"

#include <algorithm>
#include <set>
#include <stdexcept>

namespace farm::contract {
namespace {

namespace gp = google::protobuf;

template <class Info, class Ext>
const Info* OptionOf(const gp::EnumValueDescriptor* value, const Ext& extension) {
  if (value == nullptr || !value->options().HasExtension(extension)) return nullptr;
  return &value->options().GetExtension(extension);
}

std::vector<PhaseEntry> ReadPhases() {
  std::vector<PhaseEntry> table;
  std::set<pb::ArtifactKind> made;
  const gp::EnumDescriptor& phases = *pb::Phase_descriptor();
  for (int i = 0; i < phases.value_count(); ++i) {
    const gp::EnumValueDescriptor* v = phases.value(i);
    if (v->number() == 0) continue;
    const pb::PhaseInfo* info = OptionOf<pb::PhaseInfo>(v, pb::phase_info);
    if (info == nullptr) throw std::logic_error("contract: phase " + v->name() + " declares no phase_info");
    PhaseEntry entry{static_cast<pb::Phase>(v->number()), static_cast<int>(table.size()) + 1,
                     info->label(), info->executor(), {}, {}};
    for (int k : info->inputs()) {
      const auto kind = static_cast<pb::ArtifactKind>(k);
      if (!made.contains(kind) && !ArtifactOf(kind).previous_round)
        throw std::logic_error("contract: phase " + v->name() + " reads " + pb::ArtifactKind_Name(kind) +
                               ", which no phase before it makes");
      entry.inputs.push_back(kind);
    }
    for (int k : info->outputs()) {
      entry.outputs.push_back(static_cast<pb::ArtifactKind>(k));
      made.insert(static_cast<pb::ArtifactKind>(k));
    }
    table.push_back(std::move(entry));
  }
  return table;
}

}  // namespace

const std::vector<PhaseEntry>& Phases() {
  static const std::vector<PhaseEntry> table = ReadPhases();
  return table;
}

const PhaseEntry* FindPhase(pb::Phase p) {
  const auto& table = Phases();
  const auto it = std::find_if(table.begin(), table.end(), [p](const PhaseEntry& e) { return e.phase == p; });
  return it == table.end() ? nullptr : &*it;
}

std::string PhaseLabel(pb::Phase p) {
  const PhaseEntry* entry = FindPhase(p);
  return entry ? entry->label : "phase " + std::to_string(static_cast<int>(p));
}

pb::Phase SpecPhase(const gp::FieldDescriptor& spec) {
  return spec.options().GetExtension(pb::task_phase);
}

pb::Phase PhaseOf(const pb::Task& task) {
  const gp::OneofDescriptor* spec = pb::Task::descriptor()->FindOneofByName("spec");
  const gp::FieldDescriptor* set = task.GetReflection()->GetOneofFieldDescriptor(task, spec);
  return set ? SpecPhase(*set) : pb::PHASE_UNSPECIFIED;
}

const ArtifactEntry& ArtifactOf(pb::ArtifactKind kind) {
  // Read once: kinds are few, and callers keep references to the names.
  static const std::vector<ArtifactEntry> table = [] {
    const gp::EnumDescriptor& kinds = *pb::ArtifactKind_descriptor();
    std::vector<ArtifactEntry> t(static_cast<std::size_t>(pb::ArtifactKind_MAX) + 1);
    for (int i = 0; i < kinds.value_count(); ++i) {
      const gp::EnumValueDescriptor* v = kinds.value(i);
      if (const pb::ArtifactInfo* info = OptionOf<pb::ArtifactInfo>(v, pb::artifact_info))
        t[static_cast<std::size_t>(v->number())] = {info->name(), info->previous_round()};
    }
    return t;
  }();
  const auto index = static_cast<std::size_t>(kind);
  if (index >= table.size() || table[index].name.empty())
    throw std::logic_error("contract: artifact kind " + std::to_string(static_cast<int>(kind)) +
                           " declares no artifact_info");
  return table[index];
}

FailureEntry FailureOf(pb::FailureKind kind) {
  const pb::FailureInfo* info =
      OptionOf<pb::FailureInfo>(pb::FailureKind_descriptor()->FindValueByNumber(kind), pb::failure_info);
  if (info == nullptr) return FailureOf(pb::FAILURE_KIND_TRANSIENT);
  return {info->permanent(), info->label(), info->blames_worker()};
}

}  // namespace farm::contract
