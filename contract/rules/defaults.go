package rules

import (
	"sync"

	"google.golang.org/protobuf/proto"
	"google.golang.org/protobuf/reflect/protoreflect"
)

// ApplyDefaults sets every number and enum field of m that is 0 (or -0) and whose rule has a
// default_value to that value: in m, in its set messages, and in unset singular messages
// (which it creates) that hold such a field somewhere below them. Repeated fields and
// oneof members are filled only where present, so that nothing is set that was not asked
// for.
func ApplyDefaults(m proto.Message) { applyDefaults(m.ProtoReflect()) }

func applyDefaults(msg protoreflect.Message) {
	fields := msg.Descriptor().Fields()
	for i := 0; i < fields.Len(); i++ {
		fd := fields.Get(i)
		switch {
		case fd.IsMap():
		case fd.IsList():
			if fd.Kind() == protoreflect.MessageKind {
				list := msg.Get(fd).List()
				for j := 0; j < list.Len(); j++ {
					applyDefaults(list.Get(j).Message())
				}
			}
		case fd.Kind() == protoreflect.MessageKind:
			if msg.Has(fd) || (fd.ContainingOneof() == nil && holdsDefaults(fd.Message())) {
				applyDefaults(msg.Mutable(fd).Message())
			}
		default:
			r := Of(fd)
			if r == nil || r.DefaultValue == nil || !isZero(fd, msg.Get(fd)) {
				continue
			}
			msg.Set(fd, numberValue(fd, r.GetDefaultValue()))
		}
	}
}

// isZero reports whether number v of field fd is 0, as Check reads it: -0 too (which a
// protobuf message holds as set).
func isZero(fd protoreflect.FieldDescriptor, v protoreflect.Value) bool {
	switch fd.Kind() {
	case protoreflect.FloatKind, protoreflect.DoubleKind:
		return v.Float() == 0
	case protoreflect.EnumKind:
		return v.Enum() == 0
	case protoreflect.Uint32Kind, protoreflect.Uint64Kind, protoreflect.Fixed32Kind, protoreflect.Fixed64Kind:
		return v.Uint() == 0
	}
	return v.Int() == 0
}

// numberValue converts a default to field fd's kind.
func numberValue(fd protoreflect.FieldDescriptor, v float64) protoreflect.Value {
	switch fd.Kind() {
	case protoreflect.FloatKind:
		return protoreflect.ValueOfFloat32(float32(v))
	case protoreflect.DoubleKind:
		return protoreflect.ValueOfFloat64(v)
	case protoreflect.EnumKind:
		return protoreflect.ValueOfEnum(protoreflect.EnumNumber(v))
	case protoreflect.Uint32Kind, protoreflect.Fixed32Kind:
		return protoreflect.ValueOfUint32(uint32(v))
	case protoreflect.Uint64Kind, protoreflect.Fixed64Kind:
		return protoreflect.ValueOfUint64(uint64(v))
	case protoreflect.Int32Kind, protoreflect.Sint32Kind, protoreflect.Sfixed32Kind:
		return protoreflect.ValueOfInt32(int32(v))
	case protoreflect.Int64Kind, protoreflect.Sint64Kind, protoreflect.Sfixed64Kind:
		return protoreflect.ValueOfInt64(int64(v))
	}
	panic("rules: default_value on " + string(fd.FullName()) + ", a " + fd.Kind().String() + " field")
}

var holds sync.Map // protoreflect.FullName -> bool

// holdsDefaults reports whether a message of type md, once created, has a field with a
// default somewhere in its singular, non-oneof fields.
func holdsDefaults(md protoreflect.MessageDescriptor) bool {
	if v, ok := holds.Load(md.FullName()); ok {
		return v.(bool)
	}
	holds.Store(md.FullName(), false) // breaks cycles (a message that holds itself)
	found := false
	fields := md.Fields()
	for i := 0; i < fields.Len() && !found; i++ {
		fd := fields.Get(i)
		switch {
		case fd.IsList() || fd.IsMap() || fd.ContainingOneof() != nil:
		case fd.Kind() == protoreflect.MessageKind:
			found = holdsDefaults(fd.Message())
		default:
			r := Of(fd)
			found = r != nil && r.DefaultValue != nil
		}
	}
	holds.Store(md.FullName(), found)
	return found
}
