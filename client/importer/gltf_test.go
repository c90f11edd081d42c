package importer_test

import (
	"context"
	"math"
	"os"
	"path/filepath"
	"strings"
	"testing"

	"photonfarm/client/importer"
	"photonfarm/client/importer/importertest"
	"photonfarm/contract/assets"
	"photonfarm/contract/scene"
	pb "photonfarm/proto/renderfarm/v1"
)

func TestImportGLBPlacesOneMeshTwiceWithItsMaterialTextureCameraAndLight(t *testing.T) {
	// A binary, a .gltf with its buffer embedded (a data: URI) and one with it in a file.
	for _, tc := range []struct {
		name     string
		external bool
	}{{"model.glb", false}, {"model.gltf", false}, {"external.gltf", true}} {
		t.Run(tc.name, func(t *testing.T) {
			doc := importertest.Model(t)
			if tc.external {
				importertest.ExternalBuffers(doc, "external")
			}
			src := importertest.Save(t, doc, tc.name)
			if tc.external && !fileExists(filepath.Join(filepath.Dir(src), "external-0.bin")) {
				t.Fatalf("the model's buffer was not saved beside %s", src)
			}
			out := t.TempDir()
			r, err := importer.Import(context.Background(), src, out, importer.Options{Width: 200})
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
