package scene_test

import (
	"math"
	"testing"

	"google.golang.org/protobuf/reflect/protoreflect"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene"
	pb "photonfarm/proto/renderfarm/v1"
)

// TestEveryMaterialKindHasCapabilities sets each member of Material.kind in turn (read from
// the descriptor, so a kind added to scene.proto is tried too): CapabilitiesOf must know it
// and give it a capability.
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
			if !c.Diffuse && !c.Specular && !c.Emissive {
				t.Errorf("CapabilitiesOf(%s) = %+v, want some capability", fd.Name(), c)
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

// TestPrincipledCapabilities: the microfacet lobe is specular below the contract's
// roughness threshold (read from the one place it is declared), the diffuse base counts
// unless a smooth lobe is all there is, and a positive emission makes an area light.
func TestPrincipledCapabilities(t *testing.T) {
	threshold := rules.Scene.GetPrincipledSpecularRoughness()
	texture := &pb.TextureRef{Texture: "mr"}
	tests := []struct {
		name string
		p    *pb.Principled
		want scene.Capabilities
	}{
		{"rough dielectric", &pb.Principled{Roughness: 0.5}, scene.Capabilities{Diffuse: true}},
		{"rough metal", &pb.Principled{Roughness: 0.5, Metallic: 1}, scene.Capabilities{Diffuse: true}},
		{"at the threshold", &pb.Principled{Roughness: threshold, Metallic: 1}, scene.Capabilities{Diffuse: true}},
		{"just below it", &pb.Principled{Roughness: math.Nextafter(threshold, 0), Metallic: 1}, scene.Capabilities{Specular: true}},
		{"smooth metal", &pb.Principled{Metallic: 1}, scene.Capabilities{Specular: true}},
		{"smooth metal, textured metallic", &pb.Principled{Metallic: 1, MetallicRoughnessTexture: texture},
			scene.Capabilities{Diffuse: true, Specular: true}},
		{"smooth partly metal", &pb.Principled{Metallic: 0.5}, scene.Capabilities{Diffuse: true, Specular: true}},
		{"rough, textured roughness", &pb.Principled{Roughness: 1, MetallicRoughnessTexture: texture},
			scene.Capabilities{Diffuse: true}},
		{"emits", &pb.Principled{Roughness: 1, Emission: &pb.Color{G: 2}}, scene.Capabilities{Diffuse: true, Emissive: true}},
		{"black emission", &pb.Principled{Roughness: 1, Emission: &pb.Color{}}, scene.Capabilities{Diffuse: true}},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			m := &pb.Material{Name: "m", Kind: &pb.Material_Principled{Principled: tt.p}}
			if got := scene.CapabilitiesOf(m); got != tt.want {
				t.Errorf("CapabilitiesOf(%v) = %+v, want %+v", tt.p, got, tt.want)
			}
		})
	}
}

// TestEmissiveCapabilities: an emissive material is an area light, and diffuse too where it
// has a reflectance (a light fixture the room lights).
func TestEmissiveCapabilities(t *testing.T) {
	tests := []struct {
		name string
		e    *pb.Emissive
		want scene.Capabilities
	}{
		{"no reflectance", &pb.Emissive{Radiance: &pb.Color{R: 1}}, scene.Capabilities{Emissive: true}},
		{"black reflectance", &pb.Emissive{Radiance: &pb.Color{R: 1}, Reflectance: &pb.Color{}}, scene.Capabilities{Emissive: true}},
		{"reflects", &pb.Emissive{Radiance: &pb.Color{R: 1}, Reflectance: &pb.Color{B: 0.5}}, scene.Capabilities{Diffuse: true, Emissive: true}},
	}
	for _, tt := range tests {
		t.Run(tt.name, func(t *testing.T) {
			m := &pb.Material{Name: "m", Kind: &pb.Material_Emissive{Emissive: tt.e}}
			if got := scene.CapabilitiesOf(m); got != tt.want {
				t.Errorf("CapabilitiesOf(%v) = %+v, want %+v", tt.e, got, tt.want)
			}
		})
	}
}
