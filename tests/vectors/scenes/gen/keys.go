package main

import (
	"google.golang.org/protobuf/reflect/protoreflect"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// A key names one check of the contract that a vector exercises: "Film.width:gte" is a
// refusal of a width below its gte bound, "Film.width:gte=" an acceptance of a width at
// it, "Material.kind:one_required" a refusal of a material with no kind set. Fields are
// named by message and field, so a rule declared once (RadianceEstimate.neighbours) is one
// key wherever the message is used.

// ruleKeys returns every key the descriptors of Scene and every message reachable from it
// call for: for each field, its rule's bounds (a refused value past each, an accepted
// value at each inclusive one), default (0 accepted), required, items, bytes, digest and
// note; finiteness and magnitude of every double; a declared value of every enum; each
// required oneof. And the scene limits Validate enforces, each accepted at exactly its
// value.
func ruleKeys() (refused, accepted map[string]bool) {
	refused, accepted = map[string]bool{}, map[string]bool{}
	seen := map[protoreflect.FullName]bool{}
	var walk func(md protoreflect.MessageDescriptor)
	walk = func(md protoreflect.MessageDescriptor) {
		if seen[md.FullName()] {
			return
		}
		seen[md.FullName()] = true
		for i := 0; i < md.Fields().Len(); i++ {
			fd := md.Fields().Get(i)
			name := string(md.Name()) + "." + string(fd.Name())
			switch fd.Kind() {
			case protoreflect.DoubleKind, protoreflect.FloatKind:
				refused[name+":nan"], refused[name+":inf"], refused[name+":magnitude"] = true, true, true
			case protoreflect.EnumKind:
				refused[name+":enum"] = true
			case protoreflect.MessageKind:
				walk(fd.Message())
			}
			if r := rules.Of(fd); r != nil {
				fieldKeys(name, r, refused, accepted)
			}
		}
		for i := 0; i < md.Oneofs().Len(); i++ {
			if od := md.Oneofs().Get(i); rules.OneRequired(od) {
				refused[string(md.Name())+"."+string(od.Name())+":one_required"] = true
			}
		}
	}
	walk((*pb.Scene)(nil).ProtoReflect().Descriptor())
	for _, limit := range []string{"max_magnitude", "max_tiles_per_round", "max_shards_per_map", "max_film_pixels"} {
		accepted["Scene:"+limit+"="] = true
	}
	return refused, accepted
}

// fieldKeys adds the keys of field name's rule r.
func fieldKeys(name string, r *pb.FieldRule, refused, accepted map[string]bool) {
	for _, b := range []struct {
		key       string
		set       bool
		inclusive bool
	}{
		{"gte", r.Gte != nil, true}, {"gt", r.Gt != nil, false}, {"lte", r.Lte != nil, true}, {"lt", r.Lt != nil, false},
		{"min_items", r.MinItems != nil, true}, {"max_items", r.MaxItems != nil, true}, {"max_bytes", r.MaxBytes != nil, true},
		{"required", r.GetRequired(), false}, {"digest", r.GetDigest(), false}, {"note", r.GetNote() != "", false},
	} {
		if !b.set {
			continue
		}
		refused[name+":"+b.key] = true
		if b.inclusive {
			accepted[name+":"+b.key+"="] = true
		}
	}
	if r.DefaultValue != nil {
		accepted[name+":default"] = true
	}
}
