package atrium

import "math"

// part is triangles with normals and texture coordinates, built in metres.
type part struct {
	pos [][3]float32
	nrm [][3]float32
	uv  [][2]float32
	idx []uint32
}

func (p *part) vertex(x, y, z, nx, ny, nz, u, v float64) uint32 {
	p.pos = append(p.pos, [3]float32{float32(x), float32(y), float32(z)})
	p.nrm = append(p.nrm, [3]float32{float32(nx), float32(ny), float32(nz)})
	p.uv = append(p.uv, [2]float32{float32(u), float32(v)})
	return uint32(len(p.pos) - 1)
}

func (p *part) tri(a, b, c uint32) { p.idx = append(p.idx, a, b, c) }

// quad adds a rectangle from corner o along edges e1 and e2 (counter-clockwise seen from
// the side the normal e1 x e2 points to), texture repeated every tile metres.
func (p *part) quad(o, e1, e2 [3]float64, tile float64) {
	p.quadUV(o, e1, e2, length(e1)/tile, length(e2)/tile)
}

// quadUV adds a rectangle whose texture coordinates run from 0 to l1 along e1 and from 0
// to l2 along e2 (1 and 1: the texture once over the rectangle).
func (p *part) quadUV(o, e1, e2 [3]float64, l1, l2 float64) {
	n := cross(e1, e2)
	n = scale(n, 1/length(n))
	at := func(s, t float64) [3]float64 { return add(o, add(scale(e1, s), scale(e2, t))) }
	var ids [4]uint32
	for k, st := range [4][2]float64{{0, 0}, {1, 0}, {1, 1}, {0, 1}} {
		q := at(st[0], st[1])
		ids[k] = p.vertex(q[0], q[1], q[2], n[0], n[1], n[2], st[0]*l1, (1-st[1])*l2)
	}
	p.tri(ids[0], ids[1], ids[2])
	p.tri(ids[0], ids[2], ids[3])
}

// box adds the six outward faces of an axis-aligned box.
func (p *part) box(min, max [3]float64, tile float64) {
	x0, y0, z0 := min[0], min[1], min[2]
	x1, y1, z1 := max[0], max[1], max[2]
	dx, dy, dz := [3]float64{x1 - x0, 0, 0}, [3]float64{0, y1 - y0, 0}, [3]float64{0, 0, z1 - z0}
	p.quad([3]float64{x0, y0, z1}, dx, dy, tile)            // +z
	p.quad([3]float64{x1, y0, z0}, scale(dx, -1), dy, tile) // -z
	p.quad([3]float64{x1, y0, z1}, scale(dz, -1), dy, tile) // +x
	p.quad([3]float64{x0, y0, z0}, dz, dy, tile)            // -x
	p.quad([3]float64{x0, y1, z1}, dx, scale(dz, -1), tile) // +y
	p.quad([3]float64{x0, y0, z0}, dx, dz, tile)            // -y
}

// column adds a fluted column: a cylinder of radius r around (x, z) from y0 to y1, with
// segments around and rings up (flutes make the radius wave around).
func (p *part) column(x, z, y0, y1, r float64, segments, rings int) {
	base := uint32(len(p.pos))
	for j := 0; j <= rings; j++ {
		t := float64(j) / float64(rings)
		y := y0 + t*(y1-y0)
		// Entasis: a column swells a little a third of the way up.
		swell := 1 + 0.04*math.Sin(math.Pi*math.Min(t*1.5, 1))
		for i := 0; i <= segments; i++ {
			a := 2 * math.Pi * float64(i) / float64(segments)
			flute := 1 - 0.03*math.Abs(math.Cos(12*a))
			rr := r * swell * flute
			nx, nz := math.Cos(a), math.Sin(a)
			p.vertex(x+rr*nx, y, z+rr*nz, nx, 0, nz, float64(i)/float64(segments)*2, t*(y1-y0))
		}
	}
	row := uint32(segments + 1)
	for j := 0; j < rings; j++ {
		for i := 0; i < segments; i++ {
			a := base + uint32(j)*row + uint32(i)
			b, c, d := a+1, a+row+1, a+row
			p.tri(a, d, c)
			p.tri(a, c, b)
		}
	}
}

// arch adds a semicircular arch of inner radius r and thickness t between two columns at
// x0 and x1, springing at height y, depth d along z from z0.
func (p *part) arch(x0, x1, y, z0, d, t float64, segments int) {
	cx, r := (x0+x1)/2, (x1-x0)/2
	for i := 0; i < segments; i++ {
		a0 := math.Pi * float64(i) / float64(segments)
		a1 := math.Pi * float64(i+1) / float64(segments)
		in0 := [3]float64{cx - r*math.Cos(a0), y + r*math.Sin(a0), z0}
		in1 := [3]float64{cx - r*math.Cos(a1), y + r*math.Sin(a1), z0}
		out0 := [3]float64{cx - (r+t)*math.Cos(a0), y + (r+t)*math.Sin(a0), z0}
		// The soffit (underside) faces the arch's centre.
		p.quad(in1, sub(in0, in1), [3]float64{0, 0, d}, 0.5)
		// Front and back faces of the voussoir.
		p.quad(in0, sub(in1, in0), sub(out0, in0), 0.5)
		p.quad(add(in1, [3]float64{0, 0, d}), sub(in0, in1), sub(add(out0, sub(in1, in0)), in1), 0.5)
	}
}

func add(a, b [3]float64) [3]float64 { return [3]float64{a[0] + b[0], a[1] + b[1], a[2] + b[2]} }
func sub(a, b [3]float64) [3]float64 { return [3]float64{a[0] - b[0], a[1] - b[1], a[2] - b[2]} }
func scale(a [3]float64, k float64) [3]float64 {
	return [3]float64{a[0] * k, a[1] * k, a[2] * k}
}
func cross(a, b [3]float64) [3]float64 {
	return [3]float64{a[1]*b[2] - a[2]*b[1], a[2]*b[0] - a[0]*b[2], a[0]*b[1] - a[1]*b[0]}
}
func length(a [3]float64) float64 { return math.Sqrt(a[0]*a[0] + a[1]*a[1] + a[2]*a[2]) }
