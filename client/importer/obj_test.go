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
	"photonfarm/contract/scene"
	pb "photonfarm/proto/renderfarm/v1"
)

func TestImportOBJMakesOneMeshWithAPartPerMaterial(t *testing.T) {
	out := t.TempDir()
	r, err := importer.Import(context.Background(), importertest.WriteOBJ(t, true), out, importer.Options{Width: 64})
	if err != nil {
		t.Fatal(err)
	}
	s := r.Scene
	if len(s.GetMeshes()) != 1 || len(s.GetMeshes()[0].GetParts()) != 2 || len(s.GetShapes()) != 1 {
		t.Fatalf("meshes %v, shapes %v: want one mesh of two parts placed once", s.GetMeshes(), s.GetShapes())
	}
	mats := map[string]*pb.Material{}
	for _, m := range s.GetMaterials() {
		mats[m.GetName()] = m
	}
	p := mats["painted"].GetPrincipled()
	wantRoughness := math.Pow(2.0/100, 0.25)
	if p == nil || p.GetBaseColor().GetG() != 0.25 || math.Abs(p.GetRoughness()-wantRoughness) > 1e-12 ||
		p.GetBaseColorTexture().GetTexture() != "paint.png" {
		t.Errorf("painted = %v, want base colour (0.5, 0.25, 1), roughness %v, texture paint.png", p, wantRoughness)
	}
	if g := mats["glass"].GetDielectric(); g == nil || g.GetIor() != 1.45 || g.GetTransmittance().GetB() != 1 {
		t.Errorf("glass = %v, want a dielectric of ior 1.45 tinted (0.9, 0.9, 1)", mats["glass"])
	}
	if len(s.GetLights()) != 0 || s.GetEnvironment().GetRadiance().GetR() != 1 || len(r.Chose) == 0 {
		t.Errorf("a model without lights gets a white sky, and says so: %v, chose %v", s.GetEnvironment(), r.Chose)
	}
	for _, f := range scene.Files(s) {
		if _, err := os.Stat(filepath.Join(out, f.Path)); err != nil {
			t.Errorf("%s: %v", f.Field, err)
		}
	}
}

func TestImportOBJRefusesAMissingMTL(t *testing.T) {
	path := importertest.WriteOBJ(t, false)
	_, err := importer.Import(context.Background(), path, t.TempDir(), importer.Options{})
	if err == nil || !strings.Contains(err.Error(), "mtllib look.mtl") || !strings.HasPrefix(err.Error(), path) {
		t.Errorf("Import = %v, want the missing look.mtl named", err)
	}
}

func TestImportOBJRefusesWhatTheCheckerRefuses(t *testing.T) {
	dir := t.TempDir()
	path := filepath.Join(dir, "bad.obj")
	os.WriteFile(path, []byte("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"), 0o644)
	_, err := importer.Import(context.Background(), path, t.TempDir(), importer.Options{})
	if err == nil || !strings.Contains(err.Error(), "line 4: face refers to vertex 7 but the file has 3 vertices") {
		t.Errorf("Import = %v, want the checker's line and reason", err)
	}
}

func TestImportLightsAModelWithTheEnvironmentItIsGiven(t *testing.T) {
	path := importertest.WriteOBJ(t, true)
	sky := filepath.Join(filepath.Dir(path), "sky.hdr")
	os.WriteFile(sky, []byte("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n\x80\x80\x80\x80\x80\x80\x80\x80"), 0o644)
	r, err := importer.Import(context.Background(), path, t.TempDir(), importer.Options{Environment: sky})
	if err != nil {
		t.Fatal(err)
	}
	env := r.Scene.GetEnvironment()
	if env.GetMap().GetTexture() != "environment" || env.GetRadiance() != nil || len(r.Chose) != 1 {
		t.Errorf("environment %v, chose %v: want the given map and no white sky", env, r.Chose)
	}
}
