// Package rules reads the rules that proto/renderfarm/v1/rules.proto declares as options on
// the contract (field bounds and defaults, scene and RPC limits) and applies them to any
// message by reflection. The worker (worker/contract) reads the same options from its own
// descriptors, so neither side holds a copy of a limit.
package rules

import (
	"google.golang.org/protobuf/proto"
	"google.golang.org/protobuf/reflect/protoreflect"

	pb "photonfarm/proto/renderfarm/v1"
)

// Of returns the rule declared on field fd, or nil.
func Of(fd protoreflect.FieldDescriptor) *pb.FieldRule {
	opts := fd.Options()
	if opts == nil || !proto.HasExtension(opts, pb.E_Rule) {
		return nil
	}
	return proto.GetExtension(opts, pb.E_Rule).(*pb.FieldRule)
}

// OneRequired reports whether exactly one member of oneof od must be set.
func OneRequired(od protoreflect.OneofDescriptor) bool {
	opts := od.Options()
	return opts != nil && proto.GetExtension(opts, pb.E_OneRequired).(bool)
}

// Scene holds the limits of a scene as a whole (the scene_limits option of Scene).
var Scene = sceneLimits()

// RPC holds the limits of the RPC layer (the rpc_limits option of blob.proto).
var RPC = rpcLimits()

func sceneLimits() *pb.SceneLimits {
	opts := (&pb.Scene{}).ProtoReflect().Descriptor().Options()
	l := proto.GetExtension(opts, pb.E_SceneLimits).(*pb.SceneLimits)
	if l.GetMaxMagnitude() <= 0 || l.GetMaxTilesPerRound() == 0 || l.GetMaxShardsPerMap() == 0 ||
		l.GetMaxAssetBytes() == 0 || l.GetMaxMeshVertices() == 0 || l.GetMaxMeshTriangles() == 0 ||
		l.GetMaxMeshLineBytes() == 0 || l.GetMaxSnapshotPhotons() == 0 || l.GetMaxShardPhotons() == 0 || l.GetMaxFilmPixels() == 0 ||
		l.GetMaxTexturePixels() == 0 || l.GetPrincipledSpecularRoughness() <= 0 ||
		!(l.GetPathTracedMediaMinAbsG() > 0 && l.GetPathTracedMediaMinAbsG() < 1) ||
		l.GetMaxGridCells() == 0 || l.GetMaxGridAxisCells() == 0 {
		panic("rules: scene.proto declares no complete scene_limits option on Scene")
	}
	return l
}

func rpcLimits() *pb.RpcLimits {
	opts := pb.File_renderfarm_v1_blob_proto.Options()
	l := proto.GetExtension(opts, pb.E_RpcLimits).(*pb.RpcLimits)
	if l.GetMaxMessageBytes() == 0 || l.GetMaxUploadChunkBytes() == 0 || l.GetMaxDownloadChunkBytes() == 0 ||
		l.GetMaxBlobBytes() == 0 || l.GetMaxErrorBytes() == 0 || l.GetMaxTaskLogBytes() == 0 {
		panic("rules: blob.proto declares no complete rpc_limits option")
	}
	return l
}

// Default returns the value that 0 selects for field name of message m (its rule's
// default_value), and panics if the field declares none: callers name fields that do.
func Default(m proto.Message, name protoreflect.Name) float64 {
	r := declared(m, name)
	if r.DefaultValue == nil {
		panic("rules: " + fieldName(m, name) + " declares no default_value")
	}
	return r.GetDefaultValue()
}

// Max returns field name's upper bound (its rule's lte), and panics if it declares none.
func Max(m proto.Message, name protoreflect.Name) float64 {
	r := declared(m, name)
	if r.Lte == nil {
		panic("rules: " + fieldName(m, name) + " declares no lte bound")
	}
	return r.GetLte()
}

// Min returns field name's lower bound (its rule's gte), and panics if it declares none.
func Min(m proto.Message, name protoreflect.Name) float64 {
	r := declared(m, name)
	if r.Gte == nil {
		panic("rules: " + fieldName(m, name) + " declares no gte bound")
	}
	return r.GetGte()
}

// MaxItems returns the most entries repeated field name may have (its rule's max_items),
// and panics if it declares none.
func MaxItems(m proto.Message, name protoreflect.Name) uint64 {
	r := declared(m, name)
	if r.MaxItems == nil {
		panic("rules: " + fieldName(m, name) + " declares no max_items")
	}
	return r.GetMaxItems()
}

// Keys returns the only keys map field name may have, in the order reports show them (its
// rule's keys), and panics if it declares none.
func Keys(m proto.Message, name protoreflect.Name) []string {
	r := declared(m, name)
	if len(r.GetKeys()) == 0 {
		panic("rules: " + fieldName(m, name) + " declares no keys")
	}
	return r.GetKeys()
}

func declared(m proto.Message, name protoreflect.Name) *pb.FieldRule {
	fd := m.ProtoReflect().Descriptor().Fields().ByName(name)
	if fd == nil || Of(fd) == nil {
		panic("rules: " + fieldName(m, name) + " has no rule")
	}
	return Of(fd)
}

func fieldName(m proto.Message, name protoreflect.Name) string {
	return string(m.ProtoReflect().Descriptor().FullName()) + "." + string(name)
}
