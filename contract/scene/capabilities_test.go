package scene_test

import (
	"testing"

	"google.golang.org/protobuf/reflect/protoreflect"

	"photonfarm/contract/scene"
	pb "photonfarm/proto/renderfarm/v1"
)

// TestEveryMaterialKindHasCapabilities sets each member of Material.kind in turn (read from
// the descriptor, so a kind added to scene.proto is tried too): CapabilitiesOf must know it
// and give it exactly one capability.
func TestEveryMaterialKindHasCapabilities(t *testing.T) {
	kinds := (&pb.Material{}).ProtoReflect().Descriptor().Oneofs().ByName("kind").Fields()
	for i := 0; i < kinds.Len(); i++ {
		fd := kinds.Get(i)
		t.Run(string(fd.Name()), func(t *testing.T) {
			m := &pb.Material{}
			r := m.ProtoReflect()
			r.Set(fd, protoreflect.ValueOfMessage(r.NewField(fd).Message()))
			defer func() {
				if p := recover(); p != nil {
					t.Fatalf("CapabilitiesOf(%s) panicked: %v", fd.Name(), p)
				}
			}()
			c := scene.CapabilitiesOf(m)
			if n := btoi(c.Diffuse) + btoi(c.Specular) + btoi(c.Emissive); n != 1 {
				t.Errorf("CapabilitiesOf(%s) = %+v, want exactly one capability", fd.Name(), c)
			}
		})
	}
}

func TestAMaterialWithoutAKindPanics(t *testing.T) {
	defer func() {
		if recover() == nil {
			t.Error("CapabilitiesOf of a material without a kind did not panic")
		}
	}()
	scene.CapabilitiesOf(&pb.Material{})
}

func btoi(b bool) int {
	if b {
		return 1
	}
	return 0
}
