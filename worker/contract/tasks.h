#pragma once

// What the contract declares about a job's work (proto/renderfarm/v1/job.proto and
// rules.proto), read from the compiled descriptors as contract/tasks (Go) reads them:
//
//   Phases()          the phases in the order a round runs them (the order the Phase enum
//                     declares its values, not their numbers), each with its rank (from 1),
//                     label, executor, inputs and outputs (phase_info)
//   PhaseOf(task)     the phase of a task's spec (the task_phase option of Task.spec)
//   ArtifactOf(kind)  an artifact kind's Artifact.name ("tile.exr") and whether the next
//                     round reads it (artifact_info)
//   FailureOf(kind)   whether a failure kind is permanent, and its label (failure_info)
//
// A contract that breaks its own promises (a phase without phase_info, an input no earlier
// phase makes, an artifact kind without a name) makes these throw std::logic_error.

#include <google/protobuf/descriptor.h>

#include <string>
#include <vector>

#include "renderfarm/v1/job.pb.h"
#include "renderfarm/v1/rules.pb.h"

namespace farm::contract {

namespace pb = renderfarm::v1;

struct PhaseEntry {
  pb::Phase phase = pb::PHASE_UNSPECIFIED;
  int rank = 0;  // place in a round, from 1
  std::string label;
  pb::Executor executor = pb::EXECUTOR_UNSPECIFIED;
  std::vector<pb::ArtifactKind> inputs;
  std::vector<pb::ArtifactKind> outputs;
};

const std::vector<PhaseEntry>& Phases();
// Phase p's entry, or null for a number the contract does not declare.
const PhaseEntry* FindPhase(pb::Phase p);
// p's label ("Render tiles"), or its number for an unknown phase.
std::string PhaseLabel(pb::Phase p);

// The phase whose tasks carry spec field `spec` of Task (its task_phase option).
pb::Phase SpecPhase(const google::protobuf::FieldDescriptor& spec);
// The phase of task's spec, or PHASE_UNSPECIFIED if none is set.
pb::Phase PhaseOf(const pb::Task& task);

struct ArtifactEntry {
  std::string name;  // Artifact.name
  bool previous_round = false;
};
const ArtifactEntry& ArtifactOf(pb::ArtifactKind kind);
inline const std::string& ArtifactName(pb::ArtifactKind kind) { return ArtifactOf(kind).name; }

struct FailureEntry {
  bool permanent = false;      // the job fails at once and no worker is blamed
  std::string label;           // "bad input"
  bool blames_worker = false;  // counts toward the worker's blocklist threshold
};
// An undeclared kind is treated as transient, as the coordinator treats it.
FailureEntry FailureOf(pb::FailureKind kind);

}  // namespace farm::contract
