package scene

import (
	"fmt"
	"math"

	pb "photonfarm/proto/renderfarm/v1"
)

// Interreflection says whether a scene's diffuse surfaces can light one another, which is
// what a global photon map is for. It is false only when that is certain: no diffuse
// surface at all, one sphere lit only from outside (its outside is convex; its inside,
// which can light itself, gets no light) and nothing else diffuse, or every diffuse surface a
// quad or triangle of one plane, with no specular surface to carry light from one part of
// it to another. Mesh files and the parts of instanced meshes are not inspected (their
// bytes are in the blob store), so a scene with a diffuse mesh file or instanced part
// always counts as interreflecting. Why is the reason.
type Interreflection struct {
	Possible bool
	Why      string
}

// InterreflectionOf inspects s, which must have passed Validate.
func InterreflectionOf(s *pb.Scene) Interreflection {
	materials := ShapeMaterials(s)
	var planes []plane
	var sphere *pb.Sphere
	spheres, others := 0, 0
	surf := SurfacesOf(s)
	for i, sh := range s.GetShapes() {
		if !anyMaterial(materials[i], func(m *pb.Material) bool { return CapabilitiesOf(m).Diffuse }) {
			continue
		}
		switch g := sh.GetGeometry().(type) {
		case *pb.Shape_Sphere:
			spheres++
			sphere = g.Sphere
		case *pb.Shape_Quad:
			o := toVec(g.Quad.GetOrigin())
			planes = append(planes, planeOf(o, toVec(g.Quad.GetEdgeU()), toVec(g.Quad.GetEdgeV())))
		case *pb.Shape_Triangles:
			ps, ix := g.Triangles.GetPositions(), g.Triangles.GetIndices()
			for i := 0; i+2 < len(ix); i += 3 {
				a, b, c := toVec(ps[ix[i]]), toVec(ps[ix[i+1]]), toVec(ps[ix[i+2]])
				if p := planeOf(a, b.sub(a), c.sub(a)); p.n.length() > 0 {
					planes = append(planes, p)
				}
			}
		case *pb.Shape_Mesh, *pb.Shape_Instance:
			others++ // its vertices are in the blob store, not here
		default:
			panic(fmt.Sprintf("scene: InterreflectionOf does not know geometry %T", g))
		}
	}
	switch {
	case spheres+others+len(planes) == 0:
		return Interreflection{Why: "no diffuse surface (Lambert, glossy or principled)"}
	case surf.Specular:
		return Interreflection{Possible: true, Why: "diffuse surfaces can light each other, directly or through specular ones"}
	case others == 0 && spheres == 1 && len(planes) == 0 && !anyLightInside(s, materials, toVec(sphere.GetCenter()), sphere.GetRadius()):
		return Interreflection{Why: "the only diffuse surface is one sphere lit from outside, which cannot light itself"}
	case others == 0 && spheres == 0 && coplanar(planes):
		return Interreflection{Why: "every diffuse surface lies in one plane, so none can light another"}
	}
	return Interreflection{Possible: true, Why: "diffuse surfaces can light each other"}
}

// plane is n·x = d with n of unit length (or zero for a degenerate triangle).
type plane struct {
	n     vec
	d     float64
	scale float64 // magnitude of the points that made it, for tolerances
}

func planeOf(o, u, v vec) plane {
	n := u.cross(v)
	l := n.length()
	if l == 0 || math.IsInf(l, 0) {
		return plane{}
	}
	n = vec{n.x / l, n.y / l, n.z / l}
	scale := math.Max(1, math.Max(o.length(), math.Max(u.length(), v.length())))
	return plane{n: n, d: n.x*o.x + n.y*o.y + n.z*o.z, scale: scale}
}

// coplanar reports whether every plane is the first one (either orientation).
func coplanar(ps []plane) bool {
	const tol = 1e-9
	p0 := ps[0]
	for _, p := range ps[1:] {
		dot := p.n.x*p0.n.x + p.n.y*p0.n.y + p.n.z*p0.n.z
		if math.Abs(math.Abs(dot)-1) > tol {
			return false
		}
		d := p.d
		if dot < 0 {
			d = -d
		}
		if math.Abs(d-p0.d) > tol*math.Max(p.scale, p0.scale) {
			return false
		}
	}
	return true
}

// anyLightInside says whether a point or spot light or an emissive shape may reach inside the
// ball (c, r), the bounding ball of a shape whose inside may light itself (a furnace) or
// hold a medium. It errs towards yes (a shape counts when its bounding ball meets the
// ball, and a mesh file's always, its vertices not being known here), since wrongly
// skipping a map loses light while wrongly keeping it only costs time. Suns are outside.
func anyLightInside(s *pb.Scene, materials [][]*pb.Material, c vec, r float64) bool {
	meets := func(centre vec, radius float64) bool { return centre.sub(c).length() < r+radius }
	for _, l := range s.GetLights() {
		if pl := l.GetPoint(); pl != nil && meets(toVec(pl.GetPosition()), 0) {
			return true
		}
		if sl := l.GetSpot(); sl != nil && meets(toVec(sl.GetPosition()), 0) {
			return true
		}
	}
	for i, sh := range s.GetShapes() {
		if !anyMaterial(materials[i], Emits) {
			continue
		}
		centre, radius, known := shapeBall(sh)
		if !known || meets(centre, radius) {
			return true
		}
	}
	return false
}

// shapeBall is a ball around the shape's geometry, known unless the geometry is a mesh
// file or an instance (whose vertices are in the blob store, not in the scene).
func shapeBall(sh *pb.Shape) (centre vec, radius float64, known bool) {
	switch g := sh.GetGeometry().(type) {
	case *pb.Shape_Sphere:
		return toVec(g.Sphere.GetCenter()), g.Sphere.GetRadius(), true
	case *pb.Shape_Quad:
		o, u, v := toVec(g.Quad.GetOrigin()), toVec(g.Quad.GetEdgeU()), toVec(g.Quad.GetEdgeV())
		return o.add(u.scale(0.5)).add(v.scale(0.5)), math.Max(u.add(v).length(), u.sub(v).length()) / 2, true
	case *pb.Shape_Triangles:
		centre, radius := boundingBall(g.Triangles.GetPositions())
		return centre, radius, true
	case *pb.Shape_Mesh, *pb.Shape_Instance:
		return vec{}, 0, false
	default:
		panic(fmt.Sprintf("scene: shapeBall does not know geometry %T", g))
	}
}

// boundingBall is a ball around points: their centroid and the largest distance from it.
func boundingBall(ps []*pb.Vec3) (vec, float64) {
	var centre vec
	for _, p := range ps {
		centre = centre.add(toVec(p))
	}
	centre = centre.scale(1 / float64(max(len(ps), 1)))
	radius := 0.0
	for _, p := range ps {
		radius = math.Max(radius, toVec(p).sub(centre).length())
	}
	return centre, radius
}
