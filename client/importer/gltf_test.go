package importer_test

import (
	"bytes"
	"context"
	"image"
	"image/png"
	"math"
	"os"
	"path/filepath"
	"strings"
	"testing"

	"github.com/qmuntal/gltf"
	"github.com/qmuntal/gltf/ext/lightspunctual"
	"github.com/qmuntal/gltf/modeler"

	"photonfarm/client/importer"
	"photonfarm/contract/assets"
	"photonfarm/contract/scene"
	pb "photonfarm/proto/renderfarm/v1"
)

// model is a small glTF document: one textured quad mesh placed by two nodes (one a
// child of the other), a camera, a point light and an emissive material.
func model(t *testing.T) *gltf.Document {
	t.Helper()
	doc := gltf.NewDocument()
	var img bytes.Buffer
	if err := png.Encode(&img, image.NewRGBA(image.Rect(0, 0, 4, 4))); err != nil {
		t.Fatal(err)
	}
	imageIndex, err := modeler.WriteImage(doc, "checker", "image/png", &img)
	if err != nil {
		t.Fatal(err)
	}
	doc.Textures = []*gltf.Texture{{Source: gltf.Index(imageIndex)}}
	doc.Materials = []*gltf.Material{{
		Name: "painted",
		PBRMetallicRoughness: &gltf.PBRMetallicRoughness{
			BaseColorFactor:  &[4]float64{0.8, 0.5, 0.2, 1},
			BaseColorTexture: &gltf.TextureInfo{Index: 0},
			MetallicFactor:   gltf.Float(0.25),
			RoughnessFactor:  gltf.Float(0.5),
		},
		AlphaMode:   gltf.AlphaMask,
		AlphaCutoff: gltf.Float(0.3),
	}}
	attrs, err := modeler.WritePrimitiveAttributes(doc,
		modeler.PrimitiveAttribute{Name: gltf.POSITION, Data: [][3]float32{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}},
		modeler.PrimitiveAttribute{Name: gltf.NORMAL, Data: [][3]float32{{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}}},
		modeler.PrimitiveAttribute{Name: gltf.TEXCOORD_0, Data: [][2]float32{{0, 1}, {1, 1}, {1, 0}, {0, 0}}})
	if err != nil {
		t.Fatal(err)
	}
	doc.Meshes = []*gltf.Mesh{{Name: "quad", Primitives: []*gltf.Primitive{{
		Attributes: attrs, Indices: gltf.Index(modeler.WriteIndices(doc, []uint16{0, 1, 2, 0, 2, 3})), Material: gltf.Index(0),
	}}}}
	doc.Cameras = []*gltf.Camera{{Perspective: &gltf.Perspective{Yfov: math.Pi / 4, AspectRatio: gltf.Float(2)}}}
	doc.Extensions = gltf.Extensions{lightspunctual.ExtensionName: map[string]any{"lights": lightspunctual.Lights{
		{Type: lightspunctual.TypePoint, Color: &[3]float64{1, 1, 1}, Intensity: gltf.Float(683)},
	}}}
	doc.ExtensionsUsed = []string{lightspunctual.ExtensionName}
	doc.Nodes = []*gltf.Node{
		{Name: "first", Mesh: gltf.Index(0), Children: []int{1}, Translation: [3]float64{2, 0, 0}, Rotation: gltf.DefaultRotation, Scale: gltf.DefaultScale, Matrix: gltf.DefaultMatrix},
		{Name: "second", Mesh: gltf.Index(0), Translation: [3]float64{0, 3, 0}, Rotation: gltf.DefaultRotation, Scale: [3]float64{2, 2, 2}, Matrix: gltf.DefaultMatrix},
		{Name: "eye", Camera: gltf.Index(0), Translation: [3]float64{0, 0, 10}, Rotation: gltf.DefaultRotation, Scale: gltf.DefaultScale, Matrix: gltf.DefaultMatrix},
		{Name: "lamp", Translation: [3]float64{0, 5, 0}, Rotation: gltf.DefaultRotation, Scale: gltf.DefaultScale, Matrix: gltf.DefaultMatrix,
			Extensions: gltf.Extensions{lightspunctual.ExtensionName: map[string]int{"light": 0}}},
	}
	doc.Scenes = []*gltf.Scene{{Nodes: []int{0, 2, 3}}}
	doc.Scene = gltf.Index(0)
	return doc
}

func save(t *testing.T, doc *gltf.Document, name string) string {
	t.Helper()
	path := filepath.Join(t.TempDir(), name)
	var err error
	if strings.HasSuffix(name, ".glb") {
		err = gltf.SaveBinary(doc, path)
	} else {
		err = gltf.Save(doc, path)
	}
	if err != nil {
		t.Fatal(err)
	}
	return path
}

func TestImportGLBPlacesOneMeshTwiceWithItsMaterialTextureCameraAndLight(t *testing.T) {
	for _, name := range []string{"model.glb", "model.gltf"} {
		t.Run(name, func(t *testing.T) {
			out := t.TempDir()
			r, err := importer.Import(context.Background(), save(t, model(t), name), out, importer.Options{Width: 200})
			if err != nil {
				t.Fatal(err)
			}
			s := r.Scene
			if err := scene.Validate(s); err != nil && !strings.Contains(err.Error(), "digest") {
				t.Errorf("the imported scene does not validate: %v", err)
			}
			if len(s.GetMeshes()) != 1 || len(s.GetShapes()) != 2 {
				t.Fatalf("%d meshes and %d shapes, want one mesh placed twice", len(s.GetMeshes()), len(s.GetShapes()))
			}
			// The child's world transform is the parent's translation, then its own.
			m := s.GetShapes()[1].GetInstance().GetTransform().GetMatrix()
			want := []float64{2, 0, 0, 2, 0, 2, 0, 3, 0, 0, 2, 0}
			for i := range want {
				if math.Abs(m[i]-want[i]) > 1e-12 {
					t.Fatalf("second instance's matrix %v, want %v", m, want)
				}
			}
			if f := s.GetFilm(); f.GetWidth() != 200 || f.GetHeight() != 100 {
				t.Errorf("film %dx%d, want 200x100 (the camera's aspect ratio of 2)", f.GetWidth(), f.GetHeight())
			}
			if c := s.GetCamera(); c.GetPosition().GetZ() != 10 || c.GetLookAt().GetZ() != 9 || math.Abs(c.GetVerticalFovDegrees()-45) > 1e-9 {
				t.Errorf("camera %v, want at z 10 looking down -z with a 45-degree view", c)
			}
			if l := s.GetLights(); len(l) != 1 || l[0].GetPoint().GetIntensity().GetR() != 1 || l[0].GetPoint().GetPosition().GetY() != 5 {
				t.Errorf("lights %v, want one point light of intensity 1 (683 cd) at y 5", l)
			}
			p := s.GetMaterials()[0].GetPrincipled()
			if p.GetMetallic() != 0.25 || p.GetRoughness() != 0.5 || p.GetAlphaMode() != pb.AlphaMode_ALPHA_MODE_MASK ||
				p.GetAlphaCutoff() != 0.3 || p.GetBaseColorTexture().GetTexture() != s.GetTextures()[0].GetName() {
				t.Errorf("material %v does not carry the glTF material", p)
			}
			for _, f := range scene.Files(s) {
				if f.Path == "" || !fileExists(filepath.Join(out, f.Path)) {
					t.Errorf("%s names %q, which the import did not write", f.Field, f.Path)
				}
			}
			part := s.GetMeshes()[0].GetParts()[0]
			data, _ := os.ReadFile(filepath.Join(out, part.GetPath()))
			if !assets.IsFarmMesh(data) {
				t.Errorf("%s is not a farm mesh file", part.GetPath())
			}
		})
	}
}

func fileExists(p string) bool { _, err := os.Stat(p); return err == nil }
