package atrium

import (
	"bytes"
	"fmt"
	"image"
	"image/color"
	"image/png"
	"math"
	"math/rand/v2"
)

// The atrium's textures, drawn here: every one a small PNG, deterministic (a fixed seed).

type texture struct {
	name string
	img  image.Image
	// srgb: a colour texture (base colour); false for data (roughness, normals).
	srgb bool
}

func pngBytes(img image.Image) []byte {
	var b bytes.Buffer
	if err := png.Encode(&b, img); err != nil {
		panic(err)
	}
	return b.Bytes()
}

// noise is value noise in [0, 1], tileable with period n cells.
type noise struct {
	n int
	v []float64
}

func newNoise(n int, seed uint64) noise {
	r := rand.New(rand.NewPCG(seed, seed^0x9e3779b97f4a7c15))
	v := make([]float64, n*n)
	for i := range v {
		v[i] = r.Float64()
	}
	return noise{n, v}
}

func (z noise) at(x, y float64) float64 {
	x, y = x*float64(z.n), y*float64(z.n)
	i, j := int(math.Floor(x)), int(math.Floor(y))
	fx, fy := x-math.Floor(x), y-math.Floor(y)
	fx, fy = fx*fx*(3-2*fx), fy*fy*(3-2*fy)
	g := func(a, b int) float64 { return z.v[((b%z.n+z.n)%z.n)*z.n+(a%z.n+z.n)%z.n] }
	return (g(i, j)*(1-fx)+g(i+1, j)*fx)*(1-fy) + (g(i, j+1)*(1-fx)+g(i+1, j+1)*fx)*fy
}

// fbm is a few octaves of noise.
func fbm(zs []noise, x, y float64) float64 {
	s, w := 0.0, 0.5
	for k, z := range zs {
		f := math.Pow(2, float64(k))
		s += w * z.at(x*f, y*f)
		w /= 2
	}
	return s
}

func octaves(seed uint64) []noise {
	return []noise{newNoise(8, seed), newNoise(8, seed+1), newNoise(8, seed+2), newNoise(8, seed+3)}
}

func clamp8(v float64) uint8 { return uint8(math.Max(0, math.Min(255, math.Round(v*255)))) }

// paint fills a size x size RGBA image with f(u, v) -> (r, g, b, a) in [0, 1].
func paint(size int, f func(u, v float64) [4]float64) *image.NRGBA {
	img := image.NewNRGBA(image.Rect(0, 0, size, size))
	for y := 0; y < size; y++ {
		for x := 0; x < size; x++ {
			c := f((float64(x)+0.5)/float64(size), (float64(y)+0.5)/float64(size))
			img.SetNRGBA(x, y, color.NRGBA{clamp8(c[0]), clamp8(c[1]), clamp8(c[2]), clamp8(c[3])})
		}
	}
	return img
}

// normalMap turns a height field h(u, v) into a tangent-space normal map (+Y up, glTF).
func normalMap(size int, strength float64, h func(u, v float64) float64) *image.NRGBA {
	e := 1 / float64(size)
	return paint(size, func(u, v float64) [4]float64 {
		dx := (h(u+e, v) - h(u-e, v)) / (2 * e) * strength
		dy := (h(u, v+e) - h(u, v-e)) / (2 * e) * strength
		n := [3]float64{-dx, dy, 1}
		l := math.Sqrt(n[0]*n[0] + n[1]*n[1] + n[2]*n[2])
		return [4]float64{n[0]/l*0.5 + 0.5, n[1]/l*0.5 + 0.5, n[2]/l*0.5 + 0.5, 1}
	})
}

// bricks is 1 in brick and 0 in mortar, in a running bond of rows x columns per tile.
func bricks(u, v float64, rows, cols int) (float64, int, int) {
	y := v * float64(rows)
	row := int(math.Floor(y))
	x := u*float64(cols) + 0.5*float64(row%2)
	col := int(math.Floor(x))
	fx, fy := x-math.Floor(x), y-math.Floor(y)
	const m = 0.06
	edge := math.Min(math.Min(fx, 1-fx)*2, math.Min(fy, 1-fy))
	return math.Min(1, edge/m), row, col
}

func textures() []texture {
	stone, dirt, marble := octaves(1), octaves(7), octaves(13)
	const size = 256
	tiles := func(u, v float64) (float64, int) {
		b, r, c := bricks(u, v, 4, 4)
		return b, r*7 + c
	}
	return []texture{
		{"floor-albedo", paint(size, func(u, v float64) [4]float64 {
			b, k := tiles(u, v)
			light := 0.55 + 0.3*float64(k%3)/2
			d := 0.85 + 0.15*fbm(dirt, u, v)
			w := light * d * (0.35 + 0.65*b)
			return [4]float64{w * 0.93, w * 0.86, w * 0.74, 1}
		}), true},
		{"floor-normal", normalMap(size, 0.02, func(u, v float64) float64 { b, _ := tiles(u, v); return b }), false},
		{"wall-albedo", paint(size, func(u, v float64) [4]float64 {
			b, r, c := bricks(u, v, 8, 4)
			tone := 0.75 + 0.25*float64((r*5+c*3)%4)/3
			n := 0.8 + 0.2*fbm(stone, u*2, v*2)
			w := (0.4 + 0.6*b) * tone * n
			return [4]float64{w * 0.76, w * 0.52, w * 0.38, 1}
		}), true},
		{"wall-normal", normalMap(size, 0.015, func(u, v float64) float64 { b, _, _ := bricks(u, v, 8, 4); return b }), false},
		{"wall-roughness", paint(size, func(u, v float64) [4]float64 {
			b, _, _ := bricks(u, v, 8, 4)
			r := 0.95 - 0.15*b
			return [4]float64{0, r, 0, 1} // glTF: roughness in green, metallic in blue
		}), false},
		{"marble-albedo", paint(size, func(u, v float64) [4]float64 {
			vein := math.Abs(math.Sin(8*u + 6*fbm(marble, u, v)))
			w := 0.82 + 0.15*math.Pow(vein, 0.3)
			return [4]float64{w, w * 0.97, w * 0.92, 1}
		}), true},
		{"arch-albedo", paint(size, func(u, v float64) [4]float64 {
			w := 0.6 + 0.25*fbm(stone, u*3, v*3)
			return [4]float64{w * 0.86, w * 0.8, w * 0.66, 1}
		}), true},
		{"banner-albedo", paint(size, func(u, v float64) [4]float64 {
			// A red banner with a gold border, and a fringe of holes at the bottom.
			border := u < 0.08 || u > 0.92 || v < 0.05
			alpha := 1.0
			if v > 0.9 && int(u*24)%2 == 0 {
				alpha = 0
			}
			if border {
				return [4]float64{0.85, 0.66, 0.2, alpha}
			}
			return [4]float64{0.62, 0.06, 0.05, alpha}
		}), true},
		{"leaf-albedo", paint(size, func(u, v float64) [4]float64 {
			// A leaf shape: opaque inside an ellipse, cut out around it.
			x, y := (u-0.5)*2, (v-0.5)*2
			in := x*x/(0.45*0.45)+y*y < 1
			vein := math.Exp(-math.Abs(x) * 40)
			g := 0.35 + 0.15*vein
			a := 0.0
			if in {
				a = 1
			}
			return [4]float64{0.12, g, 0.08, a}
		}), true},
		{"pot-albedo", paint(size, func(u, v float64) [4]float64 {
			w := 0.75 + 0.2*fbm(dirt, u*2, v*2)
			return [4]float64{w * 0.72, w * 0.36, w * 0.2, 1}
		}), true},
		{"bronze-metallic-roughness", paint(size, func(u, v float64) [4]float64 {
			return [4]float64{0, 0.25 + 0.3*fbm(dirt, u*4, v*4), 1, 1}
		}), false},
	}
}

// Sky is an equirectangular Radiance HDR sky of w x h pixels: a blue gradient overhead, a
// brighter horizon and dark ground; the sun is a separate light (KHR_lights_punctual).
func Sky(w, h int) []byte {
	var b bytes.Buffer
	fmt.Fprintf(&b, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n", h, w)
	for y := 0; y < h; y++ {
		theta := math.Pi * (float64(y) + 0.5) / float64(h) // 0 at the zenith
		up := math.Cos(theta)
		var c [3]float64
		if up >= 0 {
			t := math.Pow(1-up, 3)
			c = [3]float64{0.25 + 0.55*t, 0.45 + 0.45*t, 0.95 + 0.05*t}
		} else {
			c = [3]float64{0.12, 0.1, 0.08}
		}
		px := rgbe(c)
		// A new-style run-length scanline: its marker and width, then each channel as
		// literal runs of at most 128 bytes (flat scanlines are ambiguous to readers).
		b.Write([]byte{2, 2, byte(w >> 8), byte(w)})
		for ch := 0; ch < 4; ch++ {
			for x := 0; x < w; x += 128 {
				n := min(128, w-x)
				b.WriteByte(byte(n))
				b.Write(bytes.Repeat([]byte{px[ch]}, n))
			}
		}
	}
	return b.Bytes()
}

// rgbe encodes a colour as Radiance's shared-exponent bytes.
func rgbe(c [3]float64) []byte {
	m := math.Max(c[0], math.Max(c[1], c[2]))
	if m < 1e-32 {
		return []byte{0, 0, 0, 0}
	}
	frac, exp := math.Frexp(m)
	k := frac * 256 / m
	return []byte{byte(c[0] * k), byte(c[1] * k), byte(c[2] * k), byte(exp + 128)}
}
