// Package taskstest builds variants of the contract's Phase enum for tests: the enum as
// job.proto declares it, with one more phase declared where a test asks, so that a test
// can show what adding a phase changes (its rank) and what it does not (any wire number).
package taskstest

import (
	"fmt"

	"google.golang.org/protobuf/proto"
	"google.golang.org/protobuf/reflect/protodesc"
	"google.golang.org/protobuf/reflect/protoreflect"
	"google.golang.org/protobuf/reflect/protoregistry"
	"google.golang.org/protobuf/types/descriptorpb"

	pb "photonfarm/proto/renderfarm/v1"
)

// PhaseEnumWith returns a copy of the Phase enum (in a file and package of its own, so it
// registers nothing) with the value name = number declared right after after, carrying
// info as its phase_info. Every other value keeps its name, number and options.
func PhaseEnumWith(name string, number int32, after pb.Phase, info *pb.PhaseInfo) (protoreflect.EnumDescriptor, error) {
	ed := protodesc.ToEnumDescriptorProto(pb.Phase(0).Descriptor())
	opts := &descriptorpb.EnumValueOptions{}
	proto.SetExtension(opts, pb.E_PhaseInfo, info)
	added := &descriptorpb.EnumValueDescriptorProto{Name: proto.String(name), Number: proto.Int32(number), Options: opts}
	var values []*descriptorpb.EnumValueDescriptorProto
	found := false
	for _, v := range ed.Value {
		values = append(values, v)
		if v.GetNumber() == int32(after) {
			values = append(values, added)
			found = true
		}
	}
	if !found {
		return nil, fmt.Errorf("taskstest: the Phase enum has no value %d", after)
	}
	ed.Value = values
	rules := pb.File_renderfarm_v1_rules_proto
	fd, err := protodesc.NewFile(&descriptorpb.FileDescriptorProto{
		Name:       proto.String("taskstest/phase.proto"),
		Package:    proto.String("renderfarm.taskstest"),
		Syntax:     proto.String("proto3"),
		Dependency: []string{rules.Path()},
		EnumType:   []*descriptorpb.EnumDescriptorProto{ed},
	}, protoregistry.GlobalFiles)
	if err != nil {
		return nil, fmt.Errorf("taskstest: %w", err)
	}
	return fd.Enums().Get(0), nil
}
