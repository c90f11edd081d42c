package importer

import "math"

// mat4 is a 4x4 matrix, m[row][column], applied to column vectors.
type mat4 [4][4]float64

func identity() mat4 { return mat4{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}} }

func (a mat4) mul(b mat4) mat4 {
	var c mat4
	for i := 0; i < 4; i++ {
		for j := 0; j < 4; j++ {
			for k := 0; k < 4; k++ {
				c[i][j] += a[i][k] * b[k][j]
			}
		}
	}
	return c
}

// point and dir apply the matrix to a point and to a direction.
func (a mat4) point(p [3]float64) [3]float64 {
	return [3]float64{
		a[0][0]*p[0] + a[0][1]*p[1] + a[0][2]*p[2] + a[0][3],
		a[1][0]*p[0] + a[1][1]*p[1] + a[1][2]*p[2] + a[1][3],
		a[2][0]*p[0] + a[2][1]*p[1] + a[2][2]*p[2] + a[2][3],
	}
}

func (a mat4) dir(d [3]float64) [3]float64 {
	return [3]float64{
		a[0][0]*d[0] + a[0][1]*d[1] + a[0][2]*d[2],
		a[1][0]*d[0] + a[1][1]*d[1] + a[1][2]*d[2],
		a[2][0]*d[0] + a[2][1]*d[1] + a[2][2]*d[2],
	}
}

// det is the determinant of the upper 3x3 (the matrix is affine).
func (a mat4) det() float64 {
	return a[0][0]*(a[1][1]*a[2][2]-a[1][2]*a[2][1]) -
		a[0][1]*(a[1][0]*a[2][2]-a[1][2]*a[2][0]) +
		a[0][2]*(a[1][0]*a[2][1]-a[1][1]*a[2][0])
}

func (a mat4) finite() bool {
	for _, r := range a {
		for _, x := range r {
			if math.IsNaN(x) || math.IsInf(x, 0) {
				return false
			}
		}
	}
	return true
}

// rows is the matrix as Transform.matrix holds it: the first three rows, row-major.
func (a mat4) rows() []float64 {
	out := make([]float64, 0, 12)
	for i := 0; i < 3; i++ {
		out = append(out, a[i][:]...)
	}
	return out
}

// fromColumnMajor reads glTF's column-major 16 values.
func fromColumnMajor(m [16]float64) mat4 {
	var a mat4
	for c := 0; c < 4; c++ {
		for r := 0; r < 4; r++ {
			a[r][c] = m[4*c+r]
		}
	}
	return a
}

// trs is translation * rotation (unit quaternion x, y, z, w) * scale.
func trs(t [3]float64, q [4]float64, s [3]float64) mat4 {
	x, y, z, w := q[0], q[1], q[2], q[3]
	if n := math.Sqrt(x*x + y*y + z*z + w*w); n > 0 {
		x, y, z, w = x/n, y/n, z/n, w/n
	}
	r := mat4{
		{1 - 2*(y*y+z*z), 2 * (x*y - z*w), 2 * (x*z + y*w), 0},
		{2 * (x*y + z*w), 1 - 2*(x*x+z*z), 2 * (y*z - x*w), 0},
		{2 * (x*z - y*w), 2 * (y*z + x*w), 1 - 2*(x*x+y*y), 0},
		{0, 0, 0, 1},
	}
	for i := 0; i < 3; i++ {
		for j := 0; j < 3; j++ {
			r[i][j] *= s[j]
		}
		r[i][3] = t[i]
	}
	return r
}

func normalize(v [3]float64) [3]float64 {
	n := math.Sqrt(v[0]*v[0] + v[1]*v[1] + v[2]*v[2])
	if n == 0 {
		return v
	}
	return [3]float64{v[0] / n, v[1] / n, v[2] / n}
}

// box is an axis-aligned box; the zero box is empty.
type box struct {
	min, max [3]float64
	full     bool
}

func (b box) add(p [3]float64) box {
	if !b.full {
		return box{p, p, true}
	}
	for i := range p {
		b.min[i] = math.Min(b.min[i], p[i])
		b.max[i] = math.Max(b.max[i], p[i])
	}
	return b
}

func (b box) union(o box) box {
	if !o.full {
		return b
	}
	return b.add(o.min).add(o.max)
}

// transformed is the box around b's corners moved by m.
func (b box) transformed(m mat4) box {
	if !b.full {
		return b
	}
	var out box
	for k := 0; k < 8; k++ {
		c := b.min
		for i := 0; i < 3; i++ {
			if k&(1<<i) != 0 {
				c[i] = b.max[i]
			}
		}
		out = out.add(m.point(c))
	}
	return out
}
