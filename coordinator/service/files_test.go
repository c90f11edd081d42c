package service_test

import (
	"bytes"
	"encoding/binary"
	"math"
	"os"
	"strings"
	"testing"

	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"

	"photonfarm/contract/assets"
	"photonfarm/contract/assets/assetstest"
	"photonfarm/contract/scene/scenetest"
	pb "photonfarm/proto/renderfarm/v1"
)

func withMesh(sc *pb.Scene, m *pb.MeshFile) *pb.Scene {
	sc.Shapes = append(sc.Shapes, &pb.Shape{Material: "white", Geometry: &pb.Shape_Mesh{Mesh: m}})
	return sc
}

func TestSubmitAndPlanRefuseABrokenMeshNamingTheShapeTheFileAndTheLine(t *testing.T) {
	f := newFarm(t)
	broken, err := os.ReadFile("../../tests/vectors/meshes/refuse-vertex-out-of-range.obj")
	if err != nil {
		t.Fatal(err)
	}
	bad := f.upload(broken)
	good := f.upload([]byte("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"))
	blobs := f.blobCount()
	const reason = "line 5: face refers to vertex 7 but the file has 3 vertices"
	for _, tc := range []struct {
		name string
		mesh *pb.MeshFile
		want string
	}{
		{"named by path", &pb.MeshFile{Path: "meshes/broken.obj", Digest: bad.Digest}, "meshes/broken.obj: " + reason},
		{"by digest alone", &pb.MeshFile{Digest: bad.Digest}, bad.Digest + ": " + reason},
	} {
		// A good mesh first: the refusal names the broken one's shape.
		sc := withMesh(withMesh(scenetest.Unlit(16, 16), &pb.MeshFile{Path: "tri.obj", Digest: good.Digest}), tc.mesh)
		_, err := f.jobs.SubmitJob(f.ctx, &pb.SubmitJobRequest{Scene: sc})
		wantCode(t, tc.name+": SubmitJob", err, codes.InvalidArgument, "shapes[4].mesh")
		if got := status.Convert(err).Message(); got != "shapes[4].mesh: "+tc.want {
			t.Errorf("%s: message %q, want %q", tc.name, got, "shapes[4].mesh: "+tc.want)
		}
		_, err = f.jobs.PlanScene(f.ctx, &pb.PlanSceneRequest{Scene: sc})
		wantCode(t, tc.name+": PlanScene", err, codes.InvalidArgument, "shapes[4].mesh")
	}
	list, err := f.jobs.ListJobs(f.ctx, &pb.ListJobsRequest{})
	if err != nil || len(list.Jobs) != 0 {
		t.Errorf("ListJobs = %v, %v; want no job for a refused scene", list, err)
	}
	if n := f.blobCount(); n != blobs {
		t.Errorf("%d blobs after the refusals, %d before: the refused scene was stored", n, blobs)
	}
}

func TestPlanSceneNeedsNoUploadedMesh(t *testing.T) {
	f := newFarm(t)
	sc := withMesh(scenetest.Unlit(16, 16), &pb.MeshFile{Path: "later.obj", Digest: "sha256:0000000000000000000000000000000000000000000000000000000000000000"})
	if _, err := f.jobs.PlanScene(f.ctx, &pb.PlanSceneRequest{Scene: sc}); err != nil {
		t.Errorf("PlanScene with a mesh not uploaded yet: %v", err)
	}
}

// TestSubmitRefusesBadTexturesMeshPartsAndReferences: every file a scene names is checked
// on submit by what it holds, naming its field and the file: textures, mesh parts,
// references, and grid media's grid files (hostile ones: cut short, NaN, negative or
// absurdly many cells).
func TestSubmitRefusesBadTexturesMeshPartsAndReferences(t *testing.T) {
	f := newFarm(t)
	grid := func(change func(g *assets.GridData)) string {
		g := assetstest.RampGrid()
		change(g)
		return f.upload(assetstest.EncodedGrid(g)).Digest
	}
	nanGrid := grid(func(g *assets.GridData) { g.Densities[3] = float32(math.NaN()) })
	negativeGrid := grid(func(g *assets.GridData) { g.Densities[0] = -2 })
	cutGrid := f.upload(assetstest.EncodedGrid(assetstest.RampGrid())[:60]).Digest
	hugeGrid := f.upload(func() []byte {
		b := assetstest.EncodedGrid(assetstest.RampGrid())
		binary.LittleEndian.PutUint32(b[12:], 4096)
		binary.LittleEndian.PutUint32(b[16:], 4096)
		binary.LittleEndian.PutUint32(b[20:], 4096)
		return b
	}()).Digest
	smoke := func(digest string) *pb.Medium {
		return &pb.Medium{Coefficients: &pb.Medium_Grid{Grid: &pb.MediumGrid{Path: "fx/smoke.farmgrid", Digest: digest, Albedo: &pb.Color{R: 1, G: 1, B: 1}}}}
	}
	notImage := f.upload([]byte("this is not a picture"))
	var farmMesh bytes.Buffer
	assets.EncodeFarmMesh(&farmMesh, &assets.MeshData{Positions: []float32{0, 0, 0, 1, 0, 0, 0, 1, 0}, Indices: []uint32{0, 1, 2}})
	badMesh := f.upload(farmMesh.Bytes()[:40])
	for _, tc := range []struct {
		name, field, want string
		change            func(sc *pb.Scene)
	}{
		{"a texture that is not an image", "textures[0]", "textures[0]: img/fake.png: not an image this farm reads", func(sc *pb.Scene) {
			sc.Textures = []*pb.Texture{{Name: "fake", Path: "img/fake.png", Digest: notImage.Digest}}
		}},
		{"a cut farm mesh part", "meshes[0].parts[0]", "meshes[0].parts[0]: m.fmesh: byte 40: the file ends inside its positions", func(sc *pb.Scene) {
			sc.Meshes = []*pb.Mesh{{Name: "m", Parts: []*pb.MeshPart{{Path: "m.fmesh", Digest: badMesh.Digest, Material: "white"}}}}
		}},
		{"a grid with a NaN density", "medium.grid", "medium.grid: fx/smoke.farmgrid: byte 60: the density of cell (0, 1, 0) is not finite", func(sc *pb.Scene) {
			sc.Medium = smoke(nanGrid)
		}},
		{"a grid with a negative density in a shape", "shapes[0].interior_medium.grid", "shapes[0].interior_medium.grid: fx/smoke.farmgrid: byte 48: the density of cell (0, 0, 0) is negative: -2", func(sc *pb.Scene) {
			sc.Shapes[0].InteriorMedium = smoke(negativeGrid)
		}},
		{"a grid cut short", "medium.grid", "medium.grid: fx/smoke.farmgrid: byte 60: the file ends inside its densities", func(sc *pb.Scene) {
			sc.Medium = smoke(cutGrid)
		}},
		{"a grid of 4096^3 cells", "medium.grid", "medium.grid: fx/smoke.farmgrid: byte 12: 4096 x 4096 x 4096 = 68719476736 cells, more than the 67108864 of one grid", func(sc *pb.Scene) {
			sc.Medium = smoke(hugeGrid)
		}},
		{"a reference that is not an OpenEXR", "progressive.reference", "progressive.reference: " + notImage.Digest + ": not an image", func(sc *pb.Scene) {
			sc.Progressive = &pb.Progressive{Reference: &pb.ReferenceImage{Digest: notImage.Digest}}
		}},
	} {
		sc := scenetest.Unlit(16, 16)
		tc.change(sc)
		_, err := f.jobs.SubmitJob(f.ctx, &pb.SubmitJobRequest{Scene: sc})
		wantCode(t, tc.name, err, codes.InvalidArgument, tc.field)
		if got := status.Convert(err).Message(); !strings.HasPrefix(got, tc.want) {
			t.Errorf("%s: message %q, want it to start with %q", tc.name, got, tc.want)
		}
	}
}

func TestSubmitRefusesADamagedMeshBlobUntilItIsUploadedAgain(t *testing.T) {
	f := newFarm(t)
	obj := []byte("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
	mesh := f.upload(obj)
	f.truncate(mesh.Digest)
	sc := withMesh(scenetest.Unlit(16, 16), &pb.MeshFile{Path: "tri.obj", Digest: mesh.Digest})
	_, err := f.jobs.SubmitJob(f.ctx, &pb.SubmitJobRequest{Scene: sc})
	wantCode(t, "SubmitJob with a damaged mesh blob", err, codes.InvalidArgument, "shapes[3].mesh.digest")
	if msg := status.Convert(err).Message(); !strings.Contains(msg, "tri.obj: blob "+mesh.Digest+" is damaged") || !strings.HasSuffix(msg, "upload the file again") {
		t.Errorf("message %q, want it to name the file, the damaged blob and the remedy", msg)
	}
	f.upload(obj)
	if _, err := f.jobs.SubmitJob(f.ctx, &pb.SubmitJobRequest{Scene: sc}); err != nil {
		t.Errorf("SubmitJob after uploading the mesh again: %v", err)
	}
}
