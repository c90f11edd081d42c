#pragma once

// The contract's field rules (proto/renderfarm/v1/rules.proto), read from the compiled C++
// descriptors: no limit or default of the contract is written in the worker's code.
//
// CheckRules(m) is contract/rules.Check (Go) line for line: fields in declaration order,
// depth first; a map's entries in the order of their keys (each key one of the rule's keys,
// if it names any, then the value), a list's max_items then min_items and then its elements
// (`shapes[2]`); an unset message is "missing" when required and skipped otherwise; of a
// oneof only the member that is set; after a message's fields, each (one_required) oneof
// with nothing set is refused at the message's path. Numbers: doubles finite and within
// SceneLimits().max_magnitude(), then 0 passes when the rule has a default_value, else the
// bounds; a Color or Vec3 field's bounds apply to its components that have no rule of
// their own (`materials[0].lambert.reflectance.r`). Strings: required, max_bytes, digest.
// Enums: a declared value. Messages are Go's, word for word: "must be in [8, 256] (0
// selects 32), got 4".
//
// The accessors name a message type and one of its fields: Default<pb::Sampling>(
// "light_samples") is 16, Max<pb::Indirect>("gather_rays") is 4096, and
// OrDefault<pb::Film>(film.tile_size(), "tile_size") is the tile size a film gets.
// They throw std::logic_error for a field that declares no such rule: a typo in the
// worker, found by its tests.

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>

#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "renderfarm/v1/blob.pb.h"
#include "renderfarm/v1/rules.pb.h"
#include "renderfarm/v1/scene.pb.h"

namespace farm::contract {

namespace pb = renderfarm::v1;

// Which field of a message is wrong and why.
struct FieldError {
  std::string field;    // .proto field names from the checked message: "shapes[2].sphere.radius"
  std::string message;  // "must be > 0, got -1"

  std::string ToString() const { return field + ": " + message; }
};

// The first field of m that breaks its rule, or nothing. Paths start with `path` (the
// message's own path within a larger one; empty for a root).
std::optional<FieldError> CheckRules(const google::protobuf::Message& m, std::string_view path = "");

// The rule declared on a field; an empty rule (no bounds, nothing required) if none is.
const pb::FieldRule& RuleOf(const google::protobuf::FieldDescriptor& field);
// Whether exactly one member of the oneof must be set.
bool OneRequired(const google::protobuf::OneofDescriptor& oneof);

// "must be in [8, 256] (0 selects 32)": the numbers a rule allows, in words.
std::string Describe(const pb::FieldRule& rule);

// The scene_limits option of Scene and the rpc_limits option of blob.proto. Throw
// std::logic_error if the contract declares them incompletely.
const pb::SceneLimits& SceneLimits();
const pb::RpcLimits& RpcLimits();

// The value 0 selects for a field (its default_value) and its upper bound (lte).
double Default(const google::protobuf::Descriptor& message, std::string_view field);
double Max(const google::protobuf::Descriptor& message, std::string_view field);

template <class M>
double Default(std::string_view field) {
  return Default(*M::descriptor(), field);
}

template <class M>
double Max(std::string_view field) {
  return Max(*M::descriptor(), field);
}

// The only keys a map field may have, in the order reports show them (its rule's keys).
std::vector<std::string> Keys(const google::protobuf::Descriptor& message, std::string_view field);

template <class M>
std::vector<std::string> Keys(std::string_view field) {
  return Keys(*M::descriptor(), field);
}

// `value`, or the field's default when value is 0 (an unset field), as the field's type.
template <class M, class T>
T OrDefault(T value, std::string_view field) {
  if (value != T{}) return value;
  const double d = Default<M>(field);
  if constexpr (std::is_enum_v<T>) {
    return static_cast<T>(static_cast<int>(d));
  } else {
    return static_cast<T>(d);
  }
}

}  // namespace farm::contract
