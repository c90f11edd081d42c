package tasks

import (
	"google.golang.org/protobuf/proto"
	"google.golang.org/protobuf/reflect/protoreflect"
)

// valueInfo returns the option ext that enum value v declares (phase_info, artifact_info,
// failure_info), and false if v is nil (an undeclared number) or declares none.
func valueInfo[T proto.Message](v protoreflect.EnumValueDescriptor, ext protoreflect.ExtensionType) (T, bool) {
	var none T
	if v == nil || !proto.HasExtension(v.Options(), ext) {
		return none, false
	}
	return proto.GetExtension(v.Options(), ext).(T), true
}

// infoOf returns the option ext that e's value declares; see valueInfo.
func infoOf[T proto.Message](e protoreflect.Enum, ext protoreflect.ExtensionType) (T, bool) {
	return valueInfo[T](e.Descriptor().Values().ByNumber(e.Number()), ext)
}
