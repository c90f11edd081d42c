package integration

import (
	"bytes"
	"context"
	"image/png"
	"path/filepath"
	"slices"
	"testing"
	"time"

	"photonfarm/client/importer"
	pb "photonfarm/proto/renderfarm/v1"
	"photonfarm/scenes/atrium"
	"photonfarm/tests/farmtest"
)

// TestAtriumRendersOnTwoWorkers renders issue 13's demonstration scene (scenes/atrium:
// some 300,000 triangles, eleven textures, alpha-masked banners and leaves, a plant placed
// 100 times, a sun through the windows and the sky map) at 160x90 with one sample a
// pixel, 16 gather rays and small photon maps, on a farm of two workers, and again without
// its sun; and checks that the picture is a lit interior that the sun shines into: most
// pixels lit, and patches of sun: the 2% of pixels the sun brightens most gain at least
// twice as much as the median pixel (in the shade, lit by the sun only indirectly).
func TestAtriumRendersOnTwoWorkers(t *testing.T) {
	dir := t.TempDir()
	if _, err := atrium.Write(dir); err != nil {
		t.Fatal(err)
	}
	r, err := importer.Import(context.Background(), filepath.Join(dir, "atrium.glb"), filepath.Join(dir, "scene"),
		importer.Options{Width: 160, Height: 90, Environment: filepath.Join(dir, "sky.hdr")})
	if err != nil {
		t.Fatal(err)
	}
	scenePath := filepath.Join(dir, "scene", "atrium.json")
	if err := importer.WriteScene(scenePath, r.Scene); err != nil {
		t.Fatal(err)
	}

	f := farmtest.StartFarm(t, nil)
	f.StartWorker(t).WorkerID(t, 15*time.Second)
	f.StartWorker(t).WorkerID(t, 15*time.Second)
	ctx, cancel := context.WithTimeout(context.Background(), 60*time.Second)
	defer cancel()
	sc, err := f.Client.LoadSceneFile(ctx, scenePath)
	if err != nil {
		t.Fatal(err)
	}
	sc.Film.TileSize = 32
	sc.Sampling = &pb.Sampling{SamplesPerPixel: 1, Seed: 13}
	sc.Indirect = &pb.Indirect{GatherRays: 16, SecondaryGatherRays: 4}
	sc.Photons = &pb.PhotonMapping{GlobalPhotons: 20000, CausticPhotons: 20000, PhotonsPerShard: 10000}
	if len(sc.GetLights()) != 1 || sc.GetLights()[0].GetSun() == nil {
		t.Fatalf("the atrium's lights are %v, want its sun", sc.GetLights())
	}

	start := time.Now()
	job := f.Render(t, sc, 300*time.Second)
	t.Logf("the atrium at 160x90 took %v on two workers", time.Since(start).Round(time.Millisecond))
	list := f.Tasks(t, job.GetId())
	checkAllSucceeded(t, list)
	checkBothWorkers(t, list, pb.Phase_PHASE_RENDER)
	if err := checkFinalEXR(f.Output(t, job, "image.exr"), 160, 90, 32); err != nil {
		t.Error(err)
	}
	sunlit := previewLuminance(t, f.Output(t, job, "preview.png"))
	sc.Lights = nil
	shade := previewLuminance(t, f.Output(t, f.Render(t, sc, 300*time.Second), "preview.png"))

	// How many times brighter each lit pixel is with the sun than without.
	var lit int
	var gain []float64
	for i := range sunlit {
		if sunlit[i] > 0 {
			lit++
			gain = append(gain, sunlit[i]/max(shade[i], 1))
		}
	}
	slices.Sort(gain)
	quantile := func(q float64) float64 { return gain[int(q*float64(len(gain)-1))] }
	t.Logf("%d of %d pixels lit; mean preview luminance %.0f with the sun, %.0f without (of 65535); gain with the sun: 10%% %.2f, median %.2f, 90%% %.2f, 98%% %.2f",
		lit, len(sunlit), mean(sunlit), mean(shade), quantile(0.1), quantile(0.5), quantile(0.9), quantile(0.98))
	if lit < len(sunlit)/2 {
		t.Fatalf("%d of %d pixels lit, want most", lit, len(sunlit))
	}
	// The sun's patches: the brightest 2% of gains at least twice the median gain (the
	// light the sun adds indirectly, in the shade).
	if !(quantile(0.98) >= 2*quantile(0.5)) {
		t.Errorf("the sun brightens its brightest 2%% of pixels %.2f times, the median pixel %.2f times: want patches of sun, at least twice the median", quantile(0.98), quantile(0.5))
	}
}

// previewLuminance decodes a PNG preview and returns each pixel's luminance (of 65535).
func previewLuminance(t *testing.T, b []byte) []float64 {
	t.Helper()
	img, err := png.Decode(bytes.NewReader(b))
	if err != nil {
		t.Fatal(err)
	}
	var l []float64
	for y := img.Bounds().Min.Y; y < img.Bounds().Max.Y; y++ {
		for x := img.Bounds().Min.X; x < img.Bounds().Max.X; x++ {
			r, g, b, _ := img.At(x, y).RGBA()
			l = append(l, 0.2126*float64(r)+0.7152*float64(g)+0.0722*float64(b))
		}
	}
	return l
}

func mean(v []float64) float64 {
	s := 0.0
	for _, x := range v {
		s += x
	}
	return s / float64(len(v))
}
