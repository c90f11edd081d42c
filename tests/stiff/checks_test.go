package stiff

// Assertions on a rendered image. Every failure message names the case, the channel and
// the numbers.

import (
	"fmt"
	"math"
	"testing"

	pb "photonfarm/proto/renderfarm/v1"
)

var (
	beauty = []string{"R", "G", "B"}
	// lightAOVs are the layers that carry light (the beauty adds emission to them).
	lightAOVs = []string{"direct.R", "direct.G", "direct.B", "indirect.R", "indirect.G", "indirect.B", "caustic.R", "caustic.G", "caustic.B"}
	reflected = [][3]string{{"direct.R", "indirect.R", "caustic.R"}, {"direct.G", "indirect.G", "caustic.G"}, {"direct.B", "indirect.B", "caustic.B"}}
)

// checkFinite fails unless every channel of every pixel is finite.
func checkFinite(t *testing.T, name string, im *image) {
	t.Helper()
	for c, ch := range im.channels {
		if im.nanCount[c] == 0 && im.infCount[c] == 0 {
			continue
		}
		first := ""
		for y := 0; y < im.height && first == ""; y++ {
			for x := 0; x < im.width; x++ {
				if v := im.at(x, y, c); math.IsNaN(v) || math.IsInf(v, 0) {
					first = fmt.Sprintf("first at pixel (%d, %d) = %v", x, y, v)
					break
				}
			}
		}
		t.Errorf("case %s: channel %s: %d NaN and %d Inf of %d pixels (%s)",
			name, ch, im.nanCount[c], im.infCount[c], im.width*im.height, first)
	}
}

// brightestEmitter is, per channel, the largest radiance a surface of the scene can have
// by energy: over the emissive materials that a shape uses, Le / (1 - rho), rho being the
// emitter's own reflectance (Emissive.reflectance). Other surfaces reflect at most what
// reaches them, so no radiance exceeds sup(Le + rho sup L); with rho = 0, as for most
// emitters, the bound is Le itself. Media (which do not emit) keep it: along a ray
// through one, what arrives is T L(surface) + integral of T sigma_s (phase-weighted mean
// of L) ds <= (T + (1 - T) albedo) sup L <= sup L; so does glass, seen from outside it. 0 if no shape emits: scenes lit by point or sun lights
// state their own bound.
func brightestEmitter(sc *pb.Scene) [3]float64 {
	used := map[string]bool{}
	for _, sh := range sc.GetShapes() {
		used[sh.GetMaterial()] = true
	}
	var m [3]float64
	for _, mat := range sc.GetMaterials() {
		if e := mat.GetEmissive(); e != nil && used[mat.GetName()] {
			le, rho := e.GetRadiance(), e.GetReflectance()
			for c, v := range [3]float64{le.GetR() / (1 - rho.GetR()), le.GetG() / (1 - rho.GetG()), le.GetB() / (1 - rho.GetB())} {
				m[c] = math.Max(m[c], v)
			}
		}
	}
	return m
}

// checkBound fails if any pixel of a beauty channel, or of a light-carrying layer of the
// same colour (direct, indirect, caustic, and volume, the light media scatter towards the
// camera, where the EXR has that layer), exceeds bound[colour] (relative slack 1e-4 for
// float rounding).
func checkBound(t *testing.T, name string, im *image, bound [3]float64, why string) {
	t.Helper()
	for k, col := range beauty {
		limit := bound[k]*(1+1e-4) + 1e-6
		for _, ch := range append([]string{col, "volume." + col}, reflected[k][:]...) {
			c := im.channel(ch)
			if c < 0 {
				if ch == col {
					t.Errorf("case %s: no channel %s in %v", name, ch, im.channels)
				}
				continue
			}
			worst, wx, wy, over := math.Inf(-1), 0, 0, 0
			for y := 0; y < im.height; y++ {
				for x := 0; x < im.width; x++ {
					v := im.at(x, y, c)
					if v > limit {
						over++
					}
					if v > worst {
						worst, wx, wy = v, x, y
					}
				}
			}
			if over > 0 {
				t.Errorf("case %s: channel %s: %d pixels above the energy bound %.6g (%s); brightest %.6g at (%d, %d)",
					name, ch, over, bound[k], why, worst, wx, wy)
			}
		}
	}
}

// mean is the average of channel ch over the pixels keep accepts (every pixel if nil).
func mean(t *testing.T, name string, im *image, ch string, keep func(x, y int) bool) float64 {
	t.Helper()
	c := im.channel(ch)
	if c < 0 {
		t.Fatalf("case %s: no channel %s in %v", name, ch, im.channels)
	}
	sum, n := 0.0, 0
	for y := 0; y < im.height; y++ {
		for x := 0; x < im.width; x++ {
			if keep == nil || keep(x, y) {
				sum += im.at(x, y, c)
				n++
			}
		}
	}
	if n == 0 {
		t.Fatalf("case %s: no pixel to average channel %s over", name, ch)
	}
	return sum / float64(n)
}

// sumOf is the per-pixel sum of channels chs (e.g. direct + indirect + caustic).
func sumOf(im *image, x, y int, chs ...string) float64 {
	s := 0.0
	for _, ch := range chs {
		if c := im.channel(ch); c >= 0 {
			s += im.at(x, y, c)
		}
	}
	return s
}

// meanReflected is the image average of direct + indirect + caustic in colour k: the
// light the surfaces reflect, without what emitters show directly.
func meanReflected(im *image, k int) float64 {
	s := 0.0
	for y := 0; y < im.height; y++ {
		for x := 0; x < im.width; x++ {
			s += sumOf(im, x, y, reflected[k][:]...)
		}
	}
	return s / float64(im.width*im.height)
}

// checkClose fails unless got is within tol (relative) of want.
func checkClose(t *testing.T, name, ch, what string, got, want, tol float64) {
	t.Helper()
	rel := math.Abs(got-want) / math.Abs(want)
	if want == 0 {
		rel = math.Abs(got)
	}
	if !(rel <= tol) {
		t.Errorf("case %s: channel %s: %s = %.6g, want %.6g within %.3g%% (off by %.3g%%)",
			name, ch, what, got, want, 100*tol, 100*rel)
	} else {
		t.Logf("case %s: channel %s: %s = %.6g, want %.6g (off by %.3g%%, tolerance %.3g%%)",
			name, ch, what, got, want, 100*rel, 100*tol)
	}
}

// checkMeansClose compares the image averages of channels chs with those of a reference.
func checkMeansClose(t *testing.T, name string, got, ref *image, chs []string, tol float64, refName string) {
	t.Helper()
	for _, ch := range chs {
		checkClose(t, name, ch, "image average (vs "+refName+")", mean(t, name, got, ch, nil), mean(t, name, ref, ch, nil), tol)
	}
}

// checkPixelsClose fails if more than maxFrac of the pixels differ from the reference by
// more than tol relative (with an absolute floor of floor) in channel ch: speckles of acne
// or light leaks move few pixels a lot, which the average hides.
func checkPixelsClose(t *testing.T, name string, got, ref *image, ch string, tol, floor, maxFrac float64, refName string) {
	t.Helper()
	cg, cr := got.channel(ch), ref.channel(ch)
	if cg < 0 || cr < 0 {
		t.Fatalf("case %s: no channel %s", name, ch)
	}
	bad, wx, wy, worst := 0, 0, 0, 0.0
	for y := 0; y < got.height; y++ {
		for x := 0; x < got.width; x++ {
			a, b := got.at(x, y, cg), ref.at(x, y, cr)
			d := math.Abs(a - b)
			if d > tol*math.Abs(b)+floor {
				bad++
			}
			if d > worst {
				worst, wx, wy = d, x, y
			}
		}
	}
	n := got.width * got.height
	if float64(bad) > maxFrac*float64(n) {
		t.Errorf("case %s: channel %s: %d of %d pixels differ from %s by more than %.3g%% (+%.3g); at most %.3g%% may; worst at (%d, %d): %.6g vs %.6g",
			name, ch, bad, n, refName, 100*tol, floor, 100*maxFrac, wx, wy,
			got.at(wx, wy, cg), ref.at(wx, wy, cr))
	}
}
