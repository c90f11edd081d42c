package integration

import (
	"context"
	"os"
	"path/filepath"
	"strings"
	"testing"
	"time"

	"google.golang.org/grpc/codes"
	"google.golang.org/grpc/status"

	"photonfarm/client/importer/importertest"
	"photonfarm/contract/assets/assetstest"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

// TestBadModelsAreRefusedBeforeAnyJobIsMade: each broken model of issue 13's acceptance
// (importertest.BadModels: a truncated .glb, a buffer shorter than its accessor, an index
// out of range, a NaN position, an image that is not an image, a 65,536 x 65,536 texture,
// an unsupported required extension, 10,000 nodes deep; and an OBJ whose .mtl is missing)
// given to `farm submit` is refused within seconds, in one line naming the model's file
// and what is wrong; files that a client did not check are refused by the coordinator
// process on submit, naming the field and the file.
// The job store stays empty, and the farm's worker, idle all along, then renders a sound
// model.
func TestBadModelsAreRefusedBeforeAnyJobIsMade(t *testing.T) {
	f := farmtest.StartFarm(t, nil)
	f.StartWorker(t).WorkerID(t, 15*time.Second)

	type bad struct{ name, path, want string }
	var cases []bad
	for _, m := range importertest.BadModels {
		cases = append(cases, bad{m.Name, m.Write(t), m.Want})
	}
	cases = append(cases, bad{"a missing .mtl", importertest.WriteOBJ(t, false), "mtllib look.mtl"})
	for _, c := range cases {
		start := time.Now()
		code, stdout, stderr := farmtest.RunFarm(t, 10*time.Second, nil, "submit", c.path, "--coordinator", f.Addr)
		took := time.Since(start)
		lines := strings.Split(strings.TrimRight(stderr, "\n"), "\n")
		if code == 0 || stdout != "" || len(lines) != 1 || !strings.HasPrefix(lines[0], "farm: "+c.path+": ") ||
			!strings.Contains(lines[0], c.want) || took > 5*time.Second {
			t.Errorf("%s: farm submit exit %d after %v, stdout %q, stderr %q; want one line `farm: %s: ...%s...` within 5s",
				c.name, code, took.Round(time.Millisecond), stdout, stderr, c.path, c.want)
		}
	}

	// The same kinds of file uploaded by a client that does not check them: a 65,536 x
	// 65,536 texture and a farm mesh part with a NaN position.
	ctx := context.Background()
	huge, err := f.Client.UploadBytes(ctx, assetstest.PNGHeader(65536, 65536))
	if err != nil {
		t.Fatal(err)
	}
	nanMesh, err := os.ReadFile(filepath.Join(farmtest.RepoRoot(), "tests", "vectors", "meshes", "refuse-nan-position.farmmesh"))
	if err != nil {
		t.Fatal(err)
	}
	nan, err := f.Client.UploadBytes(ctx, nanMesh)
	if err != nil {
		t.Fatal(err)
	}
	for _, c := range []struct {
		name, want string
		change     func(sc *pb.Scene)
	}{
		{"a 65,536 x 65,536 texture", "textures[0]: huge.png: a png image of 65536x65536 pixels is larger than", func(sc *pb.Scene) {
			sc.Textures = []*pb.Texture{{Name: "huge", Path: "huge.png", Digest: huge}}
			sc.Materials = append(sc.Materials, &pb.Material{Name: "huge", Kind: &pb.Material_Principled{Principled: &pb.Principled{
				BaseColorTexture: &pb.TextureRef{Texture: "huge"}}}})
		}},
		{"a NaN position in a mesh part", "meshes[0].parts[0]: nan.farmmesh: byte 36: position 1 is not finite", func(sc *pb.Scene) {
			sc.Meshes = []*pb.Mesh{{Name: "nan", Parts: []*pb.MeshPart{{Path: "nan.farmmesh", Digest: nan, Material: "white"}}}}
		}},
	} {
		sc := f.TestScene(t, 16, 16, 16, 1)
		c.change(sc)
		_, err := f.Client.Jobs().SubmitJob(ctx, &pb.SubmitJobRequest{Scene: sc})
		if st := status.Convert(err); st.Code() != codes.InvalidArgument || !strings.HasPrefix(st.Message(), c.want) {
			t.Errorf("%s: SubmitJob = %v, want INVALID_ARGUMENT starting %q", c.name, err, c.want)
		}
	}

	if jobs, err := f.Client.ListJobs(ctx); err != nil || len(jobs) != 0 {
		t.Fatalf("after the refusals ListJobs = %v, %v; want no job", jobs, err)
	}
	code, stdout, stderr := farmtest.RunFarm(t, 30*time.Second, nil, "submit", importertest.Save(t, importertest.Model(t), "sound.glb"),
		"--coordinator", f.Addr, "--width", "16")
	if code != 0 {
		t.Fatalf("farm submit of a sound model: exit %d, stderr %q", code, stderr)
	}
	f.Wait(t, strings.TrimSpace(stdout), 60*time.Second) // the id alone: what the import did is on stderr
}
