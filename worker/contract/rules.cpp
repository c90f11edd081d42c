#include "contract/rules.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "contract/digest.h"
#include "contract/go_text.h"

namespace farm::contract {
namespace {

namespace gp = google::protobuf;
using FD = gp::FieldDescriptor;

std::string Join(std::string_view path, std::string_view name) {
  if (path.empty()) return std::string(name);
  return std::string(path) + "." + std::string(name);
}

std::string Indexed(std::string_view path, std::string_view key) {
  return std::string(path) + "[" + std::string(key) + "]";
}

FieldError Error(std::string_view path, std::string message) {
  return FieldError{std::string(path), std::move(message)};
}

bool HasBounds(const pb::FieldRule& r) {
  return r.has_gte() || r.has_gt() || r.has_lte() || r.has_lt();
}

bool IsNumber(const FD& fd) {
  switch (fd.cpp_type()) {
    case FD::CPPTYPE_INT32:
    case FD::CPPTYPE_INT64:
    case FD::CPPTYPE_UINT32:
    case FD::CPPTYPE_UINT64:
    case FD::CPPTYPE_DOUBLE:
    case FD::CPPTYPE_FLOAT:
      return true;
    case FD::CPPTYPE_BOOL:
    case FD::CPPTYPE_ENUM:
    case FD::CPPTYPE_STRING:
    case FD::CPPTYPE_MESSAGE:
      return false;
  }
  return false;
}

// One value of a field: the field's own (index < 0) or element `index` of a list.
struct Value {
  const gp::Message& owner;
  const FD& fd;
  int index = -1;

  const gp::Reflection& refl() const { return *owner.GetReflection(); }
  const gp::Message& message() const {
    return index < 0 ? refl().GetMessage(owner, &fd) : refl().GetRepeatedMessage(owner, &fd, index);
  }
  std::string string() const {
    return index < 0 ? refl().GetString(owner, &fd) : refl().GetRepeatedString(owner, &fd, index);
  }
  int enum_number() const {
    return index < 0 ? refl().GetEnumValue(owner, &fd) : refl().GetRepeatedEnumValue(owner, &fd, index);
  }
  double floating() const {
    if (fd.cpp_type() == FD::CPPTYPE_FLOAT)
      return index < 0 ? refl().GetFloat(owner, &fd) : refl().GetRepeatedFloat(owner, &fd, index);
    return index < 0 ? refl().GetDouble(owner, &fd) : refl().GetRepeatedDouble(owner, &fd, index);
  }
  std::uint64_t unsigned_integer() const {
    if (fd.cpp_type() == FD::CPPTYPE_UINT32)
      return index < 0 ? refl().GetUInt32(owner, &fd) : refl().GetRepeatedUInt32(owner, &fd, index);
    return index < 0 ? refl().GetUInt64(owner, &fd) : refl().GetRepeatedUInt64(owner, &fd, index);
  }
  std::int64_t signed_integer() const {
    if (fd.cpp_type() == FD::CPPTYPE_INT32)
      return index < 0 ? refl().GetInt32(owner, &fd) : refl().GetRepeatedInt32(owner, &fd, index);
    return index < 0 ? refl().GetInt64(owner, &fd) : refl().GetRepeatedInt64(owner, &fd, index);
  }
  // A map key as Go's protoreflect.MapKey.String() spells it.
  std::string key_text() const {
    switch (fd.cpp_type()) {
      case FD::CPPTYPE_STRING: return string();
      case FD::CPPTYPE_BOOL: return refl().GetBool(owner, &fd) ? "true" : "false";
      case FD::CPPTYPE_UINT32:
      case FD::CPPTYPE_UINT64: return std::to_string(unsigned_integer());
      default: return std::to_string(signed_integer());
    }
  }
};

std::optional<FieldError> CheckMessage(const gp::Message& msg, std::string_view path,
                                       const pb::FieldRule* inherited);

// A number against r's bounds (shown as `shown`); 0 passes when r has a default.
std::optional<FieldError> CheckBounds(std::string_view path, double v, const std::string& shown,
                                      const pb::FieldRule& r) {
  if (!HasBounds(r) || (v == 0 && r.has_default_value())) return std::nullopt;
  const bool ok = (!r.has_gte() || v >= r.gte()) && (!r.has_gt() || v > r.gt()) &&
                  (!r.has_lte() || v <= r.lte()) && (!r.has_lt() || v < r.lt());
  if (ok) return std::nullopt;
  return Error(path, Describe(r) + ", got " + shown);
}

std::optional<FieldError> CheckString(std::string_view path, const std::string& s,
                                      const pb::FieldRule& r) {
  const std::size_t n = s.size();
  if (r.required() && n == 0) return Error(path, "missing");
  if (r.has_max_bytes() && n > r.max_bytes())
    return Error(path, "must be at most " + std::to_string(r.max_bytes()) + " bytes, got " +
                           std::to_string(n));
  if (r.digest() && n > 0 && !IsDigest(s))
    return Error(path, "must be \"sha256:\" followed by 64 lowercase hex digits, got " +
                           GoQuote(Truncate(s, 80)));
  return std::nullopt;
}

// One value of field fd (its value, an element of a list, or a map's value) against r.
std::optional<FieldError> CheckValue(const Value& v, std::string_view path, const pb::FieldRule& r) {
  switch (v.fd.cpp_type()) {
    case FD::CPPTYPE_MESSAGE:
      return CheckMessage(v.message(), path, HasBounds(r) ? &r : nullptr);
    case FD::CPPTYPE_STRING:
      return CheckString(path, v.string(), r);
    case FD::CPPTYPE_ENUM: {
      const int n = v.enum_number();
      if (v.fd.enum_type()->FindValueByNumber(n) == nullptr)
        return Error(path, "unknown " + v.fd.enum_type()->name() + " value " + std::to_string(n));
      return std::nullopt;
    }
    case FD::CPPTYPE_BOOL:
      return std::nullopt;
    case FD::CPPTYPE_FLOAT:
    case FD::CPPTYPE_DOUBLE: {
      const double f = v.floating();
      if (!std::isfinite(f)) return Error(path, "must be a finite number, got " + GoNumber(f));
      const double limit = SceneLimits().max_magnitude();
      if (std::abs(f) > limit)
        return Error(path, "must be within ±" + GoNumber(limit) + ", got " + GoNumber(f));
      return CheckBounds(path, f, GoNumber(f), r);
    }
    case FD::CPPTYPE_UINT32:
    case FD::CPPTYPE_UINT64: {
      const std::uint64_t u = v.unsigned_integer();
      return CheckBounds(path, static_cast<double>(u), std::to_string(u), r);
    }
    case FD::CPPTYPE_INT32:
    case FD::CPPTYPE_INT64: {
      const std::int64_t i = v.signed_integer();
      return CheckBounds(path, static_cast<double>(i), std::to_string(i), r);
    }
  }
  return std::nullopt;
}

std::optional<FieldError> CheckMap(const gp::Message& msg, const FD& fd, std::string_view path,
                                   const pb::FieldRule& r) {
  const gp::Reflection& refl = *msg.GetReflection();
  std::vector<std::pair<std::string, const gp::Message*>> entries;
  for (int i = 0; i < refl.FieldSize(msg, &fd); ++i) {
    const gp::Message& entry = refl.GetRepeatedMessage(msg, &fd, i);
    entries.emplace_back(Value{entry, *fd.message_type()->map_key()}.key_text(), &entry);
  }
  std::sort(entries.begin(), entries.end());
  for (const auto& [key, entry] : entries) {
    const auto& keys = r.keys();
    if (!keys.empty() && std::find(keys.begin(), keys.end(), key) == keys.end()) {
      std::string allowed;
      for (const std::string& k : keys) allowed += (allowed.empty() ? "" : ", ") + k;
      return Error(Indexed(path, key), "is not a key it may have (" + allowed + ")");
    }
    if (auto err = CheckValue(Value{*entry, *fd.message_type()->map_value()}, Indexed(path, key), r))
      return err;
  }
  return std::nullopt;
}

std::optional<FieldError> CheckList(const gp::Message& msg, const FD& fd, std::string_view path,
                                    const pb::FieldRule& r) {
  const int size = msg.GetReflection()->FieldSize(msg, &fd);
  const auto n = static_cast<std::uint64_t>(size);
  if (r.has_max_items() && n > r.max_items())
    return Error(path, "must have at most " + std::to_string(r.max_items()) + " entries, got " +
                           std::to_string(n));
  if (r.has_min_items() && n < r.min_items())
    return Error(path, "must have at least " + std::to_string(r.min_items()) + " entries, got " +
                           std::to_string(n));
  for (int i = 0; i < size; ++i) {
    if (auto err = CheckValue(Value{msg, fd, i}, Indexed(path, std::to_string(i)), r)) return err;
  }
  return std::nullopt;
}

std::optional<FieldError> CheckField(const gp::Message& msg, const FD& fd, std::string_view path,
                                     const pb::FieldRule& r) {
  if (fd.is_map()) return CheckMap(msg, fd, path, r);
  if (fd.is_repeated()) return CheckList(msg, fd, path, r);
  if (fd.cpp_type() == FD::CPPTYPE_MESSAGE && !msg.GetReflection()->HasField(msg, &fd)) {
    if (r.required()) return Error(path, "missing");
    return std::nullopt;
  }
  return CheckValue(Value{msg, fd}, path, r);
}

// msg, found at path; inherited is the rule of the field that holds it when that rule
// bounds the components of a value message (Color, Vec3).
std::optional<FieldError> CheckMessage(const gp::Message& msg, std::string_view path,
                                       const pb::FieldRule* inherited) {
  const gp::Descriptor& md = *msg.GetDescriptor();
  const gp::Reflection& refl = *msg.GetReflection();
  for (int i = 0; i < md.field_count(); ++i) {
    const FD& fd = *md.field(i);
    if (fd.containing_oneof() != nullptr && !refl.HasField(msg, &fd)) continue;
    const bool own = fd.options().HasExtension(pb::rule);
    const pb::FieldRule& r = !own && inherited != nullptr && IsNumber(fd) ? *inherited : RuleOf(fd);
    if (auto err = CheckField(msg, fd, Join(path, fd.name()), r)) return err;
  }
  for (int i = 0; i < md.oneof_decl_count(); ++i) {
    const gp::OneofDescriptor& od = *md.oneof_decl(i);
    if (!OneRequired(od) || refl.HasOneof(msg, &od)) continue;
    std::string names;
    for (int j = 0; j < od.field_count(); ++j) names += (j ? ", " : "") + od.field(j)->name();
    return Error(path, "exactly one of " + names + " must be set");
  }
  return std::nullopt;
}

// The rule of field `name` of `message`, which must declare one.
const pb::FieldRule& Declared(const gp::Descriptor& message, std::string_view name) {
  const FD* fd = message.FindFieldByName(std::string(name));
  if (fd == nullptr || !fd->options().HasExtension(pb::rule))
    throw std::logic_error("contract: " + message.full_name() + "." + std::string(name) +
                           " has no rule");
  return fd->options().GetExtension(pb::rule);
}

// One number of the rule of field `name` (its default, a bound), which it must declare.
double DeclaredValue(const gp::Descriptor& message, std::string_view name, bool (pb::FieldRule::*has)() const,
                     double (pb::FieldRule::*value)() const, const char* what) {
  const pb::FieldRule& r = Declared(message, name);
  if (!(r.*has)())
    throw std::logic_error("contract: " + message.full_name() + "." + std::string(name) + " declares no " + what);
  return (r.*value)();
}

std::string Bound(bool exclusive_set, double exclusive, bool inclusive_set, double inclusive,
                  bool& open) {
  open = exclusive_set;
  if (exclusive_set) return GoNumber(exclusive);
  if (inclusive_set) return GoNumber(inclusive);
  return "";
}

}  // namespace

std::optional<FieldError> CheckRules(const gp::Message& m, std::string_view path) {
  return CheckMessage(m, path, nullptr);
}

const pb::FieldRule& RuleOf(const FD& field) {
  if (!field.options().HasExtension(pb::rule)) return pb::FieldRule::default_instance();
  return field.options().GetExtension(pb::rule);
}

bool OneRequired(const gp::OneofDescriptor& oneof) {
  return oneof.options().GetExtension(pb::one_required);
}

std::string Describe(const pb::FieldRule& r) {
  bool lo_open = false, hi_open = false;
  const std::string lo = Bound(r.has_gt(), r.gt(), r.has_gte(), r.gte(), lo_open);
  const std::string hi = Bound(r.has_lt(), r.lt(), r.has_lte(), r.lte(), hi_open);
  std::string s;
  if (!lo.empty() && !hi.empty()) {
    s = "must be in " + std::string(lo_open ? "(" : "[") + lo + ", " + hi + (hi_open ? ")" : "]");
  } else if (!lo.empty()) {
    s = "must be " + std::string(lo_open ? "> " : ">= ") + lo;
  } else {
    s = "must be " + std::string(hi_open ? "< " : "<= ") + hi;
  }
  if (r.has_default_value()) s += " (0 selects " + GoNumber(r.default_value()) + ")";
  return s;
}

const pb::SceneLimits& SceneLimits() {
  static const pb::SceneLimits& limits = [] () -> const pb::SceneLimits& {
    const pb::SceneLimits& l = pb::Scene::descriptor()->options().GetExtension(pb::scene_limits);
    if (!(l.max_magnitude() > 0) || l.max_tiles_per_round() == 0 || l.max_shards_per_map() == 0 ||
        l.max_asset_bytes() == 0 || l.max_mesh_vertices() == 0 || l.max_mesh_triangles() == 0 ||
        l.max_mesh_line_bytes() == 0 || l.max_snapshot_photons() == 0 || l.max_shard_photons() == 0 ||
        l.max_film_pixels() == 0)
      throw std::logic_error("contract: scene.proto declares no complete scene_limits option on Scene");
    return l;
  }();
  return limits;
}

const pb::RpcLimits& RpcLimits() {
  static const pb::RpcLimits& limits = [] () -> const pb::RpcLimits& {
    const pb::RpcLimits& l =
        pb::DownloadBlobRequest::descriptor()->file()->options().GetExtension(pb::rpc_limits);
    if (l.max_message_bytes() == 0 || l.max_upload_chunk_bytes() == 0 ||
        l.max_download_chunk_bytes() == 0 || l.max_blob_bytes() == 0 || l.max_error_bytes() == 0 ||
        l.max_task_log_bytes() == 0)
      throw std::logic_error("contract: blob.proto declares no complete rpc_limits option");
    return l;
  }();
  return limits;
}

double Default(const gp::Descriptor& message, std::string_view field) {
  return DeclaredValue(message, field, &pb::FieldRule::has_default_value, &pb::FieldRule::default_value,
                       "default_value");
}

double Max(const gp::Descriptor& message, std::string_view field) {
  return DeclaredValue(message, field, &pb::FieldRule::has_lte, &pb::FieldRule::lte, "lte bound");
}

std::vector<std::string> Keys(const gp::Descriptor& message, std::string_view field) {
  const pb::FieldRule& r = Declared(message, field);
  if (r.keys().empty())
    throw std::logic_error("contract: " + message.full_name() + "." + std::string(field) + " declares no keys");
  return {r.keys().begin(), r.keys().end()};
}

}  // namespace farm::contract
