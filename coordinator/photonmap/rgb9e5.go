package photonmap

import "math"

// EncodeRGB9E5 packs three components in [0, 1] (powers relative to the map's power scale)
// as OpenGL's shared-exponent RGB9E5, exactly as docs/photon-snapshot.md specifies: in
// float64, where every step is exact or correctly rounded, so a C++ reader can recompute
// the same bits.
func EncodeRGB9E5(c [3]float64) uint32 {
	maxc := math.Max(c[0], math.Max(c[1], c[2]))
	e := -rgb9e5Bias - 1
	if maxc > 0 {
		_, ex := math.Frexp(maxc) // maxc = f * 2^ex, f in [0.5, 1): floor(log2) = ex - 1
		e = max(e, ex-1)
	}
	e += rgb9e5Bias + 1
	d := math.Ldexp(1, e-rgb9e5Bias-rgb9e5MantBits)
	if math.Floor(maxc/d+0.5) == rgb9e5MantLevels {
		e++
		d *= 2
	}
	var m [3]uint32
	for i, v := range c {
		m[i] = uint32(math.Floor(v/d + 0.5))
	}
	return m[0] | m[1]<<9 | m[2]<<18 | uint32(e)<<27
}

// DecodeRGB9E5 returns the three relative components of a packed power.
func DecodeRGB9E5(v uint32) [3]float32 {
	scale := float32(math.Ldexp(1, int(v>>27)-rgb9e5Bias-rgb9e5MantBits))
	return [3]float32{
		float32(v&0x1ff) * scale,
		float32(v>>9&0x1ff) * scale,
		float32(v>>18&0x1ff) * scale,
	}
}
