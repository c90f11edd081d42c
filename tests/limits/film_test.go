package limits

import (
	"flag"
	"testing"
	"time"

	"photonfarm/contract/rules"
	"photonfarm/contract/scene/scenetest"
	"photonfarm/contract/tasks"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/tests/farmtest"
)

var filmSide = flag.Uint("limits.film-side", 0, "width and height of the film of TestLargestFilmCompletes (0: max_film_pixels, 4096x2048, with -limits.full, else 512x512)")

// TestLargestFilmCompletes renders a film of the most pixels allowed (max_film_pixels:
// 4096x2048; reduced: 512x512) in 64-pixel tiles and logs what the composite cost the
// worker and the sizes of its EXRs.
func TestLargestFilmCompletes(t *testing.T) {
	width, height := size(uint32(4096), 512), size(uint32(2048), 512)
	if *filmSide != 0 {
		width, height = uint32(*filmSide), uint32(*filmSide)
	}
	if uint64(width)*uint64(height) > rules.Scene.GetMaxFilmPixels() {
		t.Fatalf("%dx%d is over max_film_pixels %d", width, height, rules.Scene.GetMaxFilmPixels())
	}
	r := newRun(t)
	// Lit, one sample and one light sample a pixel: noisy, so that the EXRs compress as
	// little as real images do.
	sc := scenetest.Valid(width, height)
	sc.Film.TileSize = 64
	sc.Sampling.SamplesPerPixel, sc.Sampling.LightSamples = 1, 1
	sc.Antialiasing = &pb.Antialiasing{Mode: pb.AntialiasingMode_ANTIALIASING_MODE_NONE}
	sc.Photons = &pb.PhotonMapping{GlobalPhotons: 10000, PhotonsPerShard: 10000}
	sc.Indirect = &pb.Indirect{Mode: pb.IndirectMode_INDIRECT_MODE_PHOTON_MAP}
	job := r.render(sc, time.Hour)
	pixels := float64(width) * float64(height)
	t.Logf("film %dx%d: worker peak %.0f bytes a pixel", width, height, float64(r.worker().PeakRSS(t))/pixels)
	for _, task := range farmtest.TasksOf(r.f.Tasks(t, job.GetId()), pb.Phase_PHASE_COMPOSITE) {
		for _, a := range task.GetOutputs() {
			t.Logf("  %-18s %s (%.1f bytes a pixel)", a.GetName(), mb(uint64(a.GetSizeBytes())), float64(a.GetSizeBytes())/pixels)
		}
	}
	if a := tasks.Find(job.GetOutputs(), pb.ArtifactKind_ARTIFACT_KIND_IMAGE_EXR); a == nil {
		t.Errorf("the job's outputs %v have no image.exr", job.GetOutputs())
	}
	r.taskTimes()
}
