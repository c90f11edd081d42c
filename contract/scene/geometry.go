package scene

import (
	"fmt"
	"strconv"

	"photonfarm/contract/rules"
	pb "photonfarm/proto/renderfarm/v1"
)

// checkView: the camera looks somewhere (camera.look_at) and knows which way is up
// (camera.up).
func checkView(s *pb.Scene) *FieldError {
	c := s.GetCamera()
	pos, at, up := toVec(c.GetPosition()), toVec(c.GetLookAt()), toVec(c.GetUp())
	view := at.sub(pos)
	switch {
	case view.isZero():
		return rules.Errorf("camera.look_at", "must differ from camera.position, both are %s", pos)
	case up.isZero():
		return rules.Errorf("camera.up", "must be non-zero")
	case parallel(view, up):
		return rules.Errorf("camera.up", "must not be parallel to the view direction look_at - position = %s, got %s", view, up)
	}
	return nil
}

// checkShapes checks each shape's geometry beyond its bounds: quads that span an area,
// triangle lists that name their corners, mesh and instance transforms that can be
// inverted, and so can the transform of its interior medium's grid; then the scene
// medium's grid transform.
func checkShapes(s *pb.Scene) *FieldError {
	for i, sh := range s.GetShapes() {
		p := index("shapes", i)
		var err *FieldError
		switch g := sh.GetGeometry().(type) {
		case *pb.Shape_Quad:
			err = checkQuad(p+".quad", g.Quad)
		case *pb.Shape_Triangles:
			err = checkTriangles(p+".triangles", g.Triangles)
		case *pb.Shape_Mesh:
			err = checkTransform(p+".mesh.transform", g.Mesh.GetTransform())
		case *pb.Shape_Instance:
			err = checkTransform(p+".instance.transform", g.Instance.GetTransform())
		case *pb.Shape_Sphere:
			// rules.Check has bounded its radius; a centre may be anywhere.
		default:
			panic(fmt.Sprintf("scene: checkShapes does not know geometry %T", g))
		}
		if err == nil {
			err = checkGridTransform(p+".interior_medium", sh.GetInteriorMedium())
		}
		if err != nil {
			return err
		}
	}
	return checkGridTransform("medium", s.GetMedium())
}

// checkGridTransform checks the transform of m's grid, if m is a grid medium at p.
func checkGridTransform(p string, m *pb.Medium) *FieldError {
	if g := m.GetGrid(); g != nil {
		return checkTransform(p+".grid.transform", g.GetTransform())
	}
	return nil
}

func checkQuad(p string, q *pb.Quad) *FieldError {
	u, v := toVec(q.GetEdgeU()), toVec(q.GetEdgeV())
	switch {
	case u.isZero():
		return rules.Errorf(p+".edge_u", "must be non-zero")
	case v.isZero():
		return rules.Errorf(p+".edge_v", "must be non-zero")
	case parallel(u, v):
		return rules.Errorf(p+".edge_v", "must not be parallel to edge_u %s, got %s", u, v)
	}
	return nil
}

func checkTriangles(p string, t *pb.TriangleMesh) *FieldError {
	n, ind := len(t.GetPositions()), t.GetIndices()
	if len(ind) == 0 || len(ind)%3 != 0 {
		return rules.Errorf(p+".indices", "count must be a non-zero multiple of 3, got %d", len(ind))
	}
	for j, v := range ind {
		if int64(v) >= int64(n) {
			return rules.Errorf(index(p+".indices", j), "must be < %d (the number of positions), got %d", n, v)
		}
	}
	return nil
}

// checkTransform checks a transform, which may be unset (the identity): a matrix of 12
// values alone, which can be inverted; or a scale of non-zero components and a rotation
// about a non-zero axis.
func checkTransform(p string, t *pb.Transform) *FieldError {
	if m := t.GetMatrix(); len(m) > 0 {
		trs := []struct {
			name string
			set  bool
		}{{"translation", t.GetTranslation() != nil}, {"scale", t.GetScale() != nil},
			{"rotation_axis", t.GetRotationAxis() != nil}, {"rotation_degrees", t.GetRotationDegrees() != 0}}
		if len(m) != 12 {
			return rules.Errorf(p+".matrix", "must have 12 values (3 rows of 4: an affine matrix without its last row), got %d", len(m))
		}
		for _, f := range trs {
			if f.set {
				return rules.Errorf(p+".matrix", "must be the only part of the transform set, but %s is set too", f.name)
			}
		}
		if MatrixDeterminant(m) == 0 {
			return rules.Errorf(p+".matrix", "must be invertible, but the determinant of its 3x3 part is 0")
		}
		return nil
	}
	if sc := t.GetScale(); sc != nil {
		for _, c := range []struct {
			name string
			v    float64
		}{{"x", sc.GetX()}, {"y", sc.GetY()}, {"z", sc.GetZ()}} {
			if c.v == 0 {
				return rules.Errorf(p+".scale."+c.name, "must be non-zero")
			}
		}
	}
	if deg := t.GetRotationDegrees(); deg != 0 && toVec(t.GetRotationAxis()).isZero() {
		return rules.Errorf(p+".rotation_axis", "must be non-zero when rotation_degrees is %s", rules.Number(deg))
	}
	return nil
}

// MatrixDeterminant is the determinant of the linear (3x3) part of Transform.matrix m (12
// values, row-major), expanded along the first row; the worker computes it in the same
// order.
func MatrixDeterminant(m []float64) float64 {
	return m[0]*(m[5]*m[10]-m[6]*m[9]) - m[1]*(m[4]*m[10]-m[6]*m[8]) + m[2]*(m[4]*m[9]-m[5]*m[8])
}

func index(list string, i int) string { return list + "[" + strconv.Itoa(i) + "]" }
