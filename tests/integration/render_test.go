package integration

import (
	"bytes"
	"context"
	"math"
	"testing"
	"time"

	"photonfarm/client/importer/importertest"
	"photonfarm/contract/assets"
	"photonfarm/contract/assets/assetstest"
	"photonfarm/contract/tasks"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/scenes/atrium"
	"photonfarm/tests/farmtest"
)

// The scenes these tests render: scenes/test-small.json at a larger size. A tile of the
// stitch scene takes tens of milliseconds on one thread, so that both workers get tiles;
// a tile of the lease scene takes a few hundred, so that a kill lands while a lease is
// held.
var (
	stitchScene = sceneSize{width: 192, height: 128, tile: 16, spp: 4} // 96 tiles, tens of ms each (64 gather rays a sample)
	leaseScene  = sceneSize{width: 96, height: 64, tile: 32, spp: 24}  // 6 tiles, a few hundred ms each
	// The lease scene in fog (foggy): its media make a sample several times dearer.
	foggyLeaseScene = sceneSize{width: 96, height: 64, tile: 32, spp: 6}
)

type sceneSize struct{ width, height, tile, spp uint32 }

func sizedScene(t *testing.T, f *farmtest.Farm, s sceneSize) *pb.Scene {
	return f.TestScene(t, s.width, s.height, s.tile, s.spp)
}

// filtered gives s a pixel filter wider than a pixel, so that every tile also renders the
// samples of a margin about it (docs/pixel-filters.md): Mitchell's (radius 2, a margin of
// 2 pixels, negative lobes) or the Gaussian (radius 1.5, a margin of 1).
func filtered(s *pb.Scene, filter *pb.PixelFilter) *pb.Scene {
	s.Film.Filter = filter
	return s
}

var (
	mitchell = &pb.PixelFilter{Kind: &pb.PixelFilter_Mitchell{Mitchell: &pb.MitchellFilter{}}}
	gaussian = &pb.PixelFilter{Kind: &pb.PixelFilter_Gaussian{Gaussian: &pb.GaussianFilter{}}}
)

// outdoors lights s as the issue 13 lights do besides its lamp: the atrium's
// equirectangular sky (a Radiance HDR map, which the camera sees) and a sun with a disc,
// each emitting photons through the scene's disc; and textures its floor: a principled
// material whose base colour is a checker (a PNG, sRGB), a blob as the sky's map is.
func outdoors(t *testing.T, f *farmtest.Farm, s *pb.Scene) *pb.Scene {
	t.Helper()
	upload := func(name string, data []byte) string {
		digest, err := f.Client.UploadBytes(context.Background(), data)
		if err != nil {
			t.Fatalf("upload %s: %v", name, err)
		}
		s.Textures = append(s.Textures, &pb.Texture{Name: name, Path: name, Digest: digest})
		return name
	}
	s.Environment = &pb.Environment{Map: &pb.TextureRef{Texture: upload("sky.hdr", atrium.Sky(64, 32))}, RotationDegrees: 30}
	s.Lights = append(s.Lights, &pb.Light{Kind: &pb.Light_Sun{Sun: &pb.SunLight{
		Direction: &pb.Vec3{X: -0.4, Y: -1, Z: -0.3}, Irradiance: &pb.Color{R: 2, G: 1.9, B: 1.7}, AngularDiameterDegrees: 3}}})
	s.Materials = append(s.Materials, &pb.Material{Name: "checker", Kind: &pb.Material_Principled{Principled: &pb.Principled{
		BaseColor: &pb.Color{R: 0.8, G: 0.7, B: 0.6}, BaseColorTexture: &pb.TextureRef{Texture: upload("checker.png", importertest.Checker(t, 16))},
		Roughness: 0.6,
	}}})
	s.Shapes[0].Material = "checker" // the floor
	return s
}

func checkOutputs(t *testing.T, f *farmtest.Farm, job *pb.Job, s sceneSize) []byte {
	t.Helper()
	exr := f.Output(t, job, "image.exr")
	if err := checkFinalEXR(exr, int(s.width), int(s.height), int(s.tile)); err != nil {
		t.Error(err)
	}
	w, h, err := pngSize(f.Output(t, job, "preview.png"))
	if err != nil || w != int(s.width) || h != int(s.height) {
		t.Errorf("preview.png: %dx%d, %v; want %dx%d", w, h, err, s.width, s.height)
	}
	return exr
}

// checkAllSucceeded checks that every task of a succeeded job succeeded.
func checkAllSucceeded(t *testing.T, list []*pb.Task) {
	t.Helper()
	for _, task := range list {
		if task.GetState() != pb.TaskState_TASK_STATE_SUCCEEDED {
			t.Errorf("task %s is %v after the job succeeded: %s", task.GetId(), task.GetState(), task.GetError())
		}
	}
}

// checkBothWorkers checks that the tasks of phase were shared by the farm's two workers.
func checkBothWorkers(t *testing.T, list []*pb.Task, phase pb.Phase) {
	t.Helper()
	perWorker := map[string]int{}
	for _, task := range farmtest.TasksOf(list, phase) {
		perWorker[task.GetWorkerId()]++
	}
	t.Logf("%s tasks per worker: %v", tasks.Name(phase), perWorker)
	if len(perWorker) != 2 || perWorker[""] != 0 {
		t.Errorf("%s tasks were done by %v; want both workers", tasks.Name(phase), perWorker)
	}
}

// The textured, sky-lit scene with Mitchell's filter: tiles that share the samples of their
// margins on different workers stitch into the bytes one worker makes.
func TestTwoWorkersStitchBitIdenticalToOneWorker(t *testing.T) {
	checkTwoWorkersStitchAsOne(t, func(f *farmtest.Farm) *pb.Scene {
		return filtered(outdoors(t, f, sizedScene(t, f, stitchScene)), mitchell)
	})
}

// The scene in fog with a murky sphere and a sphere of smoke (docs/media.md): single
// scattering's random numbers come from each sample's own dimensions too, and tracking's
// through the smoke's grid from the query itself.
func TestFoggySceneTwoWorkersBitIdenticalToOneWorker(t *testing.T) {
	checkTwoWorkersStitchAsOne(t, func(f *farmtest.Farm) *pb.Scene { return foggy(t, f, sizedScene(t, f, stitchScene)) })
}

// foggy fills s with a thin forward-scattering fog (its multiple scattering from the
// volume photon map), turns its first sphere into murky glass (a dielectric with a denser,
// coloured medium inside, scattering forwards sharply enough, g 0.95, at least the
// contract's path_traced_media_min_abs_g, that its multiple scattering is path traced)
// and its second into a glass jar of smoke: a grid medium (a farm grid file, uploaded to
// f) whose density grows along x and falls off from the jar's centre. Both ways of
// multiple scattering, single scattering's two strategies and grid tracking in one render.
func foggy(t *testing.T, f *farmtest.Farm, s *pb.Scene) *pb.Scene {
	t.Helper()
	s.Materials = append(s.Materials, &pb.Material{Name: "murky-glass", Kind: &pb.Material_Dielectric{Dielectric: &pb.Dielectric{Ior: 1.5}}})
	s.Medium = &pb.Medium{G: 0.4, Coefficients: &pb.Medium_Albedo{Albedo: &pb.MediumAlbedo{
		Albedo: &pb.Color{R: 0.9, G: 0.9, B: 0.9}, Density: 0.3}}}
	var spheres []*pb.Shape
	for _, sh := range s.Shapes {
		if sh.GetSphere() != nil {
			sh.Material = "murky-glass"
			spheres = append(spheres, sh)
		}
	}
	if len(spheres) < 2 {
		t.Fatalf("the test scene has %d spheres, want 2", len(spheres))
	}
	spheres[0].InteriorMedium = &pb.Medium{G: 0.95, Coefficients: &pb.Medium_Sigma{Sigma: &pb.MediumCoefficients{
		SigmaA: &pb.Color{R: 0.2, G: 0.6, B: 1.2}, SigmaS: &pb.Color{R: 0.5, G: 0.5, B: 0.5}}}}
	const n = 10
	grid := &assets.GridData{Nx: n, Ny: n, Nz: n, Max: [3]float32{1, 1, 1}}
	for z := range n {
		for y := range n {
			for x := range n {
				r := math.Hypot(math.Hypot(float64(x)-4.5, float64(y)-4.5), float64(z)-4.5) / 5
				grid.Densities = append(grid.Densities, float32(math.Max(0, 1-r)*(0.5+float64(x)/n)))
			}
		}
	}
	digest, err := f.Client.UploadBytes(context.Background(), assetstest.EncodedGrid(grid))
	if err != nil {
		t.Fatal(err)
	}
	c, r := spheres[1].GetSphere().GetCenter(), spheres[1].GetSphere().GetRadius()
	spheres[1].InteriorMedium = &pb.Medium{G: 0.2, Coefficients: &pb.Medium_Grid{Grid: &pb.MediumGrid{
		Digest: digest, Albedo: &pb.Color{R: 0.95, G: 0.85, B: 0.7}, DensityScale: 3 / r,
		Transform: &pb.Transform{Scale: &pb.Vec3{X: 2 * r, Y: 2 * r, Z: 2 * r},
			Translation: &pb.Vec3{X: c.GetX() - r, Y: c.GetY() - r, Z: c.GetZ() - r}}}}}
	return s
}

// The foggy scene at the lease scene's size (volume photon map on: 200,000 paths in 4
// shards of a few hundred milliseconds) on one worker, SIGKILLed while it holds a volume emission shard; a second
// worker, which takes the shard over, SIGKILLed while it holds a render tile; a third
// finishes the job. Each lost task took two attempts and was finished by the next worker,
// and the EXR has the bytes of an
// undisturbed render: volume photons, single scattering and volumetric paths draw nothing
// from which worker or which attempt runs a task (issue 15, acceptance 2).
func TestFoggySceneBitIdenticalAfterWorkerKillsInEmissionAndRender(t *testing.T) {
	f := farmtest.StartFarm(t, nil)
	first := f.StartWorker(t)
	first.WorkerID(t, 15*time.Second)
	sc := foggy(t, f, sizedScene(t, f, foggyLeaseScene))
	sc.Photons.PhotonsPerShard = 50000
	job := f.Submit(t, sc)
	if !planRuns(job, "volume photon map") {
		t.Fatalf("the plan does not run the volume photon map: %v", job.GetPlan())
	}

	emitVictim := killWhileLeasingOne(t, f, first, job.GetId(), "volume emission shard", func(task *pb.Task) bool {
		return task.GetEmitPhotons().GetMap() == pb.PhotonMapKind_PHOTON_MAP_KIND_VOLUME
	})
	second := f.StartWorker(t)
	secondID := second.WorkerID(t, 15*time.Second)
	renderVictim := killWhileLeasing(t, f, second, job.GetId(), pb.Phase_PHASE_RENDER)
	third := f.StartWorker(t)
	thirdID := third.WorkerID(t, 15*time.Second)

	done := f.Wait(t, job.GetId(), 180*time.Second)
	exrAfterKills := checkOutputs(t, f, done, foggyLeaseScene)
	tasks := f.Tasks(t, job.GetId())
	checkTakenOver(t, tasks, emitVictim, secondID)
	checkTakenOver(t, tasks, renderVictim, thirdID)
	checkSameAsUndisturbed(t, f, sc, exrAfterKills, 180*time.Second)
}

// checkTwoWorkersStitchAsOne renders the scene makeScene makes on a farm of two workers,
// which must share the tiles, and on a fresh farm of one: the EXRs must be the same bytes.
func checkTwoWorkersStitchAsOne(t *testing.T, makeScene func(*farmtest.Farm) *pb.Scene) {
	t.Helper()
	// Two workers.
	two := farmtest.StartFarm(t, nil)
	w1, w2 := two.StartWorker(t), two.StartWorker(t)
	w1.WorkerID(t, 15*time.Second)
	w2.WorkerID(t, 15*time.Second)
	job := two.Render(t, makeScene(two), 90*time.Second)
	exrTwo := checkOutputs(t, two, job, stitchScene)

	list := two.Tasks(t, job.GetId())
	tiles := farmtest.TasksOf(list, pb.Phase_PHASE_RENDER)
	if want := int((stitchScene.width / stitchScene.tile) * (stitchScene.height / stitchScene.tile)); len(tiles) != want {
		t.Errorf("%d render tasks, want %d", len(tiles), want)
	}
	checkAllSucceeded(t, list)
	checkBothWorkers(t, list, pb.Phase_PHASE_RENDER)

	// One worker, a fresh farm.
	one := farmtest.StartFarm(t, nil)
	one.StartWorker(t)
	jobOne := one.Render(t, makeScene(one), 90*time.Second)
	exrOne := checkOutputs(t, one, jobOne, stitchScene)
	if !bytes.Equal(farmtest.WithoutRenderTime(exrTwo), farmtest.WithoutRenderTime(exrOne)) {
		t.Errorf("EXR from two workers (%d bytes) differs from the one from one worker (%d bytes)", len(exrTwo), len(exrOne))
	}
}

// With the Gaussian filter, whose margins the redone tile renders again.
func TestKilledWorkerLeaseExpiresAndJobCompletes(t *testing.T) {
	f := farmtest.StartFarm(t, nil)
	first := f.StartWorker(t)
	sc := filtered(outdoors(t, f, sizedScene(t, f, leaseScene)), gaussian)
	job := f.Submit(t, sc)

	victim := killWhileLeasing(t, f, first, job.GetId(), pb.Phase_PHASE_RENDER)

	second := f.StartWorker(t)
	secondID := second.WorkerID(t, 15*time.Second)
	done := f.Wait(t, job.GetId(), 90*time.Second)
	exrAfterKill := checkOutputs(t, f, done, leaseScene)
	checkTakenOver(t, f.Tasks(t, job.GetId()), victim, secondID)
	checkSameAsUndisturbed(t, f, sc, exrAfterKill, 90*time.Second)
}
