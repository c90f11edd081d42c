package scene

import (
	"math"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// vec is a Vec3 to compute with.
type vec struct{ x, y, z float64 }

func toVec(v *pb.Vec3) vec { return vec{v.GetX(), v.GetY(), v.GetZ()} }

func (a vec) sub(b vec) vec       { return vec{a.x - b.x, a.y - b.y, a.z - b.z} }
func (a vec) add(b vec) vec       { return vec{a.x + b.x, a.y + b.y, a.z + b.z} }
func (a vec) scale(k float64) vec { return vec{a.x * k, a.y * k, a.z * k} }
func (a vec) cross(b vec) vec     { return vec{a.y*b.z - a.z*b.y, a.z*b.x - a.x*b.z, a.x*b.y - a.y*b.x} }
func (a vec) length() float64     { return math.Sqrt(a.x*a.x + a.y*a.y + a.z*a.z) }
func (a vec) isZero() bool        { return a.x == 0 && a.y == 0 && a.z == 0 }
func (a vec) String() string {
	return "(" + rules.Number(a.x) + ", " + rules.Number(a.y) + ", " + rules.Number(a.z) + ")"
}

// parallel reports whether a and b (both non-zero) are parallel: |a × b| <= 1e-9 |a| |b|.
// The worker uses the same tolerance.
func parallel(a, b vec) bool { return a.cross(b).length() <= 1e-9*a.length()*b.length() }
